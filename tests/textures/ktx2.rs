//! KHR_texture_basisu: KTX2 images with Basis Universal payloads, end to end.
//!
//! The inputs are made here: a 64×64 test image (a red/green gradient under a blue 8×8
//! checker, optionally with an alpha ramp) is encoded by Binomial's reference Basis Universal
//! encoder (the `basisu_c_sys` dev-dependency; its output is a KTX2 file) as ETC1S (BasisLZ)
//! and as UASTC with and without Zstandard, embedded in a small glTF as data URIs, and loaded.
//!
//! What is asserted, and why each check can fail:
//! - glint's decode (the pure-Rust `basisu` transcoder) equals the reference C++ transcoder's
//!   RGBA8 output byte for byte, for ETC1S and UASTC (a different transcoder would not);
//! - the decoded texels are within a stated error of the source image: UASTC (near-lossless)
//!   PSNR ≥ 50 dB and max error ≤ 4 codes, ETC1S (lossy) PSNR ≥ 33 dB and max error ≤ 32
//!   codes, in 8-bit code space (measured: UASTC 58.1 dB / 1 code, ETC1S 36.9–38.3 dB /
//!   10–14 codes),
//!   for a colour (sRGB) and a data (linear) use; a flipped, channel-swapped or mis-spaced
//!   decode misses these by far;
//! - alpha survives (an RGBA image keeps its ramp; an opaque one stores no alpha);
//! - a render of an unlit quad textured with the KTX2 matches the same quad with the PNG
//!   of the source image: mean absolute difference ≤ 1 % (UASTC; measured 0.2 %) / 6 %
//!   (ETC1S; measured 3.9 %) of the mean radiance;
//! - with a PNG fallback `source`, the KTX2 is used when it is usable, and the fallback
//!   (with a warning) when it is not;
//! - bad inputs (truncated, wrong magic, non-Basis vkFormat, wrong supercompression, absurd
//!   size, a DFD disagreeing with the use) give a named error or warning, never a panic.

use crate::support;

use crate::support::{Fixture, data_uri, png};
use basisu_c_sys::BasisTextureFormat;
use basisu_c_sys::common;
use basisu_c_sys::extra::{
    BasisuEncoder, BasisuEncoderParams, BasisuTranscoder, ChannelType, SourceImage,
    SourceImageFormat, SupportedTextureCompression, basisu_encoder_init, basisu_transcoder_init,
    types::Extent3d,
};
use glam::Vec3;
use glint::accel::BackendKind;
use glint::scene::Scene;
use glint::scene::gltf::{LoadError, Loaded};
use glint::scene::ktx2_decode::{Ktx2Error, decode_ktx2};
use glint::scene::texture_decode::{ColorSpace, srgb_to_linear};
use serde_json::{Value, json};

const SIZE: u32 = 64;

/// The test image, RGBA8, rows top first: red grows to the right, green downwards, blue is
/// an 8×8-texel checker (40 / 215), alpha a left-to-right ramp when `alpha` is set.
fn test_image(alpha: bool) -> Vec<u8> {
    let mut rgba = Vec::with_capacity((SIZE * SIZE * 4) as usize);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let checker = ((x / 8) + (y / 8)) % 2 == 0;
            rgba.extend_from_slice(&[
                (x * 4) as u8,
                (y * 4) as u8,
                if checker { 215 } else { 40 },
                if alpha { (255 - x * 4) as u8 } else { 255 },
            ]);
        }
    }
    rgba
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Codec {
    Etc1s,
    Uastc,
    UastcZstd,
}

/// The reference encoder's KTX2 file of `rgba` (SIZE × SIZE), base level only.
fn encode(rgba: &[u8], codec: Codec, srgb: bool) -> Vec<u8> {
    basisu_encoder_init();
    let mut encoder = BasisuEncoder::new();
    encoder
        .set_image(SourceImage {
            data: rgba,
            format: SourceImageFormat::Rgba8,
            size: Extent3d {
                width: SIZE,
                height: SIZE,
                depth_or_array_layers: 1,
            },
        })
        .expect("set the source image");
    let format = match codec {
        Codec::Etc1s => BasisTextureFormat::Etc1s,
        Codec::Uastc | Codec::UastcZstd => BasisTextureFormat::UastcLdr4x4,
    };
    let mut params = if srgb {
        BasisuEncoderParams::new_with_srgb_defaults(format)
    } else {
        BasisuEncoderParams::new_with_linear_defaults(format)
    }
    .with_removed_flags(common::BU_COMP_FLAGS_THREADED);
    if codec == Codec::Uastc {
        params = params.with_removed_flags(common::BU_COMP_FLAGS_KTX2_UASTC_ZSTD);
    }
    params.quality_level = 100;
    encoder.compress(params).expect("encode")
}

/// The reference C++ transcoder's RGBA8 base level of a KTX2 file.
fn reference_rgba(ktx2: &[u8]) -> Vec<u8> {
    basisu_transcoder_init();
    let transcoder = BasisuTranscoder::new(
        ktx2,
        SupportedTextureCompression::empty(),
        ChannelType::Auto,
    )
    .expect("reference transcoder opens the file");
    let image = transcoder
        .transcode(Some(basisu_c_sys::TranscodeTargetFormat::RGBA32), None)
        .expect("reference transcode");
    image.data[..(SIZE * SIZE * 4) as usize].to_vec()
}

/// 8-bit code of a texel value read in `space` (the inverse of glint's decode).
fn code(value: f32, space: ColorSpace) -> f64 {
    match space {
        ColorSpace::Linear => f64::from(value) * 255.0,
        ColorSpace::Srgb => {
            // The nearest code whose EOTF gives `value` (exact for 8-bit inputs).
            (0..=255u16)
                .min_by(|&a, &b| {
                    let da = (srgb_to_linear(f32::from(a) / 255.0) - value).abs();
                    let db = (srgb_to_linear(f32::from(b) / 255.0) - value).abs();
                    da.total_cmp(&db)
                })
                .map_or(0.0, f64::from)
        }
    }
}

/// PSNR (dB) and max absolute error, in 8-bit codes over all four channels, of decoded texels
/// against RGBA8 codes.
fn error_vs(texels: &glint::scene::texels::Texels, space: ColorSpace, rgba: &[u8]) -> (f64, f64) {
    let mut squared = 0.0;
    let mut worst: f64 = 0.0;
    for (i, want) in rgba.chunks_exact(4).enumerate() {
        let got = texels.texel(i);
        for c in 0..4 {
            let got = if c == 3 {
                f64::from(got[c]) * 255.0
            } else {
                code(got[c], space)
            };
            let e = got - f64::from(want[c]);
            squared += e * e;
            worst = worst.max(e.abs());
        }
    }
    let mse = squared / rgba.len() as f64;
    (10.0 * (255.0 * 255.0 / mse.max(1e-12)).log10(), worst)
}

/// A unit quad (z = 0, x and y in [0, 1]) with uv (0, 0) at its top left, textured by
/// texture 0 as `slot` ("base" or "metallicRoughness"), unlit when `unlit`.
fn quad_document(fixture: &mut Fixture, textures: Value, images: Value, unlit: bool) -> Value {
    let position = fixture.positions(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ]);
    let uv = fixture.floats(&[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0], "VEC2", 2);
    let indices = fixture.indices_u16(&[0, 1, 2, 0, 2, 3]);
    let mut material = json!({
        "pbrMetallicRoughness": {
            "baseColorTexture": {"index": 0},
            "metallicRoughnessTexture": {"index": 1}
        }
    });
    let mut used = vec!["KHR_texture_basisu"];
    if unlit {
        material["extensions"] = json!({"KHR_materials_unlit": {}});
        used.push("KHR_materials_unlit");
    }
    json!({
        "extensionsUsed": used,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": position, "TEXCOORD_0": uv}, "indices": indices, "material": 0}]}],
        "materials": [material],
        "textures": textures,
        "images": images,
        "samplers": [{"wrapS": 33071, "wrapT": 33071}]
    })
}

fn ktx2_image(bytes: &[u8]) -> Value {
    json!({"uri": data_uri("image/ktx2", bytes)})
}

fn png_image(rgba: &[u8]) -> Value {
    json!({"uri": data_uri("image/png", &png(SIZE, SIZE, rgba))})
}

/// Texture `i` reading image `i` through KHR_texture_basisu (no fallback).
fn basisu_texture(image: usize) -> Value {
    json!({"sampler": 0, "extensions": {"KHR_texture_basisu": {"source": image}}})
}

/// A quad whose base colour is `colour` (KTX2, sRGB use) and metallic-roughness `data`
/// (KTX2, linear use).
fn load_pair(colour: &[u8], data: &[u8]) -> Result<Loaded, LoadError> {
    let mut fixture = Fixture::new();
    let rest = quad_document(
        &mut fixture,
        json!([basisu_texture(0), basisu_texture(1)]),
        json!([ktx2_image(colour), ktx2_image(data)]),
        false,
    );
    fixture.load(rest)
}

/// The loaded texture of glTF texture `index` (the loader keeps them in request order:
/// base colour, then metallic-roughness).
fn texture(scene: &Scene, index: usize) -> &glint::scene::Texture {
    &scene.textures[index]
}

#[test]
fn glint_decodes_exactly_what_the_reference_transcoder_decodes() {
    for (codec, alpha) in [
        (Codec::Etc1s, false),
        (Codec::Etc1s, true),
        (Codec::Uastc, true),
        (Codec::UastcZstd, false),
    ] {
        let ktx2 = encode(&test_image(alpha), codec, false);
        let reference = reference_rgba(&ktx2);
        let (image, notes) =
            decode_ktx2(&ktx2, ColorSpace::Linear, 1 << 20).expect("glint decodes the KTX2");
        assert!(notes.is_empty(), "{codec:?}: {notes:?}");
        assert_eq!((image.width, image.height), (SIZE, SIZE));
        for (i, want) in reference.chunks_exact(4).enumerate() {
            let got = image
                .texels
                .texel(i)
                .to_array()
                .map(|v| (v * 255.0).round() as u8);
            assert_eq!(got, want, "{codec:?} alpha {alpha}: texel {i}");
        }
    }
}

#[test]
fn uastc_and_etc1s_textures_decode_within_their_error_bounds_for_colour_and_data() {
    let source = test_image(false);
    // (codec, min PSNR dB, max error in codes), measured figures in the README.
    for (codec, min_psnr, max_error) in [
        (Codec::Uastc, 50.0, 4.0),
        (Codec::UastcZstd, 50.0, 4.0),
        (Codec::Etc1s, 33.0, 32.0),
    ] {
        let loaded = load_pair(
            &encode(&source, codec, true),
            &encode(&source, codec, false),
        )
        .expect("the KTX2 textures load");
        assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
        for (index, space) in [(0, ColorSpace::Srgb), (1, ColorSpace::Linear)] {
            let t = texture(&loaded.scene, index);
            assert_eq!((t.width, t.height), (SIZE, SIZE));
            let (psnr, worst) = error_vs(&t.texels, space, &source);
            eprintln!("{codec:?} {space:?}: PSNR {psnr:.1} dB, max error {worst} codes");
            assert!(
                psnr >= min_psnr && worst <= max_error,
                "{codec:?} {space:?}: PSNR {psnr:.1} dB, max error {worst}"
            );
        }
    }
}

#[test]
fn alpha_is_kept_when_present_and_not_stored_when_opaque() {
    let with_alpha = test_image(true);
    let ktx2 = encode(&with_alpha, Codec::Uastc, true);
    let (image, _) = decode_ktx2(&ktx2, ColorSpace::Srgb, 1 << 20).expect("decode");
    assert_eq!(image.texels.channels(), 4);
    // UASTC spends bits on alpha: measured 44.5 dB with the ramp.
    let (psnr, _) = error_vs(&image.texels, ColorSpace::Srgb, &with_alpha);
    assert!(psnr >= 42.0, "PSNR {psnr:.1} dB");
    let opaque = encode(&test_image(false), Codec::Etc1s, true);
    let (image, _) = decode_ktx2(&opaque, ColorSpace::Srgb, 1 << 20).expect("decode");
    assert_eq!(
        image.texels.channels(),
        3,
        "an opaque image stores no alpha"
    );
}

/// Mean of the image's RGB.
fn mean(pixels: &[Vec3]) -> f32 {
    pixels.iter().map(|p| p.element_sum() / 3.0).sum::<f32>() / pixels.len() as f32
}

/// Renders the unlit quad (one texel per pixel, pixel centres) with `image` as base colour.
fn render_quad(image: Value) -> Vec<Vec3> {
    let mut fixture = Fixture::new();
    let rest = quad_document(
        &mut fixture,
        json!([{"sampler": 0, "source": 0}, {"sampler": 0, "source": 0}]),
        json!([image]),
        true,
    );
    let loaded = fixture.load(rest).expect("load");
    let camera = support::ortho(
        Vec3::new(0.5, 0.5, 1.0),
        Vec3::new(0.5, 0.5, 0.0),
        Vec3::Y,
        0.5,
        0.5,
    );
    let settings = support::centre_settings(SIZE, SIZE);
    support::render_with(&loaded.scene, &camera, BackendKind::Bvh, &settings)
        .image
        .pixels
}

#[test]
fn a_ktx2_textured_quad_renders_like_the_same_quad_with_the_png() {
    let source = test_image(false);
    let reference = render_quad(png_image(&source));
    let m = mean(&reference);
    assert!(m > 0.05, "the reference render is lit: mean {m}");
    for (codec, tolerance) in [(Codec::UastcZstd, 0.01), (Codec::Etc1s, 0.06)] {
        let render = render_quad(ktx2_image(&encode(&source, codec, true)));
        let difference = reference
            .iter()
            .zip(&render)
            .map(|(a, b)| (*a - *b).abs().element_sum() / 3.0)
            .sum::<f32>()
            / reference.len() as f32;
        eprintln!(
            "{codec:?}: mean |KTX2 − PNG| = {:.4} of mean {m:.4}",
            difference
        );
        assert!(
            difference <= tolerance * m,
            "{codec:?}: mean |KTX2 − PNG| {difference} > {tolerance} × {m}"
        );
    }
}

/// A document whose texture 0 has a PNG fallback `source` (image 0, a solid colour) and a
/// KHR_texture_basisu KTX2 (image 1).
fn load_with_fallback(ktx2: &[u8], fallback_rgba: &[u8]) -> Loaded {
    let mut fixture = Fixture::new();
    let texture =
        json!({"sampler": 0, "source": 0, "extensions": {"KHR_texture_basisu": {"source": 1}}});
    let rest = quad_document(
        &mut fixture,
        json!([texture, texture]),
        json!([png_image(fallback_rgba), ktx2_image(ktx2)]),
        false,
    );
    fixture.load(rest).expect("load")
}

#[test]
fn the_ktx2_is_preferred_over_the_fallback_and_the_fallback_covers_an_unusable_one() {
    let source = test_image(false);
    let grey: Vec<u8> = std::iter::repeat_n([128u8, 128, 128, 255], (SIZE * SIZE) as usize)
        .flatten()
        .collect();
    let ktx2 = encode(&source, Codec::Uastc, true);
    let loaded = load_with_fallback(&ktx2, &grey);
    // (Texture 1 reads the sRGB file as linear data, which is warned about; nothing else is.)
    assert!(
        !loaded.warnings.iter().any(|w| w.contains("fallback")),
        "{:?}",
        loaded.warnings
    );
    let (psnr, _) = error_vs(&texture(&loaded.scene, 0).texels, ColorSpace::Srgb, &source);
    assert!(
        psnr >= 50.0,
        "the KTX2 (not the grey fallback) was used: PSNR {psnr:.1}"
    );

    let mut broken = ktx2.clone();
    broken[12..16].copy_from_slice(&37u32.to_le_bytes()); // VK_FORMAT_R8G8B8A8_UNORM
    let loaded = load_with_fallback(&broken, &grey);
    assert!(
        loaded
            .warnings
            .iter()
            .any(|w| w.contains("KHR_texture_basisu")
                && w.contains("vkFormat is 37")
                && w.contains("fallback")),
        "{:?}",
        loaded.warnings
    );
    let (psnr, worst) = error_vs(&texture(&loaded.scene, 0).texels, ColorSpace::Srgb, &grey);
    assert!(worst == 0.0, "the grey fallback was used: PSNR {psnr:.1}");
}

#[test]
fn a_file_requiring_the_extension_loads() {
    let source = test_image(false);
    let ktx2 = encode(&source, Codec::Etc1s, true);
    let mut fixture = Fixture::new();
    let mut rest = quad_document(
        &mut fixture,
        json!([basisu_texture(0), basisu_texture(0)]),
        json!([ktx2_image(&ktx2)]),
        false,
    );
    rest["extensionsRequired"] = json!(["KHR_texture_basisu"]);
    let loaded = fixture
        .load(rest)
        .expect("a file requiring KHR_texture_basisu loads");
    assert_eq!(loaded.scene.textures.len(), 2);
}

#[test]
fn a_dfd_that_disagrees_with_the_use_is_followed_by_the_use_with_a_warning() {
    let source = test_image(false);
    // The sRGB-encoded file as the (linear) metallic-roughness map, and the linear one as
    // base colour.
    let loaded = load_pair(
        &encode(&source, Codec::Uastc, false),
        &encode(&source, Codec::Uastc, true),
    )
    .expect("load");
    let transfer: Vec<_> = loaded
        .warnings
        .iter()
        .filter(|w| w.contains("transfer function"))
        .collect();
    assert_eq!(transfer.len(), 2, "{:?}", loaded.warnings);
    assert!(
        transfer
            .iter()
            .any(|w| w.contains("says linear but glTF uses the texture as sRGB"))
    );
    // The use wins: the base colour still reads as sRGB codes of the source.
    let (psnr, _) = error_vs(&texture(&loaded.scene, 0).texels, ColorSpace::Srgb, &source);
    assert!(psnr >= 50.0, "PSNR {psnr:.1}");
}

/// Loads a quad whose two textures read `ktx2` through KHR_texture_basisu (no fallback) and
/// returns the error's message.
fn load_error(ktx2: &[u8]) -> String {
    let mut fixture = Fixture::new();
    let rest = quad_document(
        &mut fixture,
        json!([basisu_texture(0), basisu_texture(0)]),
        json!([ktx2_image(ktx2)]),
        false,
    );
    let err = fixture.load(rest).expect_err("the bad KTX2 is refused");
    assert!(matches!(err, LoadError::Basisu { .. }), "{err:?}");
    let message = err.to_string();
    assert!(
        message.contains("fixture.gltf")
            && message.contains("texture 0")
            && message.contains("image 0")
            && message.contains("KHR_texture_basisu"),
        "names the file, texture, image and extension: {message}"
    );
    message
}

#[test]
fn bad_ktx2_inputs_are_named_errors() {
    let good = encode(&test_image(false), Codec::UastcZstd, true);

    let truncated = &good[..good.len() / 2];
    let message = load_error(truncated);
    assert!(
        message.contains("KTX2") || message.contains("truncated"),
        "{message}"
    );

    let mut magic = good.clone();
    magic[1] = b'X';
    let message = load_error(&magic);
    assert!(message.contains("not a readable KTX2 file"), "{message}");

    let mut vk = good.clone();
    vk[12..16].copy_from_slice(&37u32.to_le_bytes());
    let message = load_error(&vk);
    assert!(message.contains("vkFormat is 37"), "{message}");

    let mut scheme = good.clone();
    scheme[44..48].copy_from_slice(&1u32.to_le_bytes()); // BasisLZ on a UASTC payload
    let message = load_error(&scheme);
    assert!(
        message.contains("UASTC needs none or Zstandard"),
        "{message}"
    );

    let mut huge = good.clone();
    huge[20..24].copy_from_slice(&(1u32 << 20).to_le_bytes());
    huge[24..28].copy_from_slice(&(1u32 << 20).to_le_bytes());
    let message = load_error(&huge);
    assert!(message.contains("over the budget"), "{message}");

    let mut cube = good.clone();
    cube[36..40].copy_from_slice(&6u32.to_le_bytes());
    let message = load_error(&cube);
    assert!(message.contains("single 2D images"), "{message}");

    // Key/value data ending off a 4-byte boundary (the transcoder's metadata scan would
    // underflow on it).
    let mut kvd = good.clone();
    let length = u32::from_le_bytes(kvd[60..64].try_into().expect("4 bytes"));
    kvd[60..64].copy_from_slice(&(length - 1).to_le_bytes());
    let message = load_error(&kvd);
    assert!(message.contains("4-byte boundary"), "{message}");

    // A Zstandard level declaring an absurd uncompressed length (the transcoder would
    // allocate it) is refused before transcoding.
    let level0_uncompressed = 80 + 16;
    let mut inflated = good.clone();
    inflated[level0_uncompressed..level0_uncompressed + 8]
        .copy_from_slice(&(1u64 << 60).to_le_bytes());
    let message = load_error(&inflated);
    assert!(message.contains("bytes of UASTC blocks"), "{message}");
}

#[test]
fn the_size_budget_is_checked_before_transcoding() {
    let good = encode(&test_image(false), Codec::Etc1s, true);
    let err = decode_ktx2(&good, ColorSpace::Srgb, u64::from(SIZE * SIZE) - 1)
        .expect_err("over the budget");
    assert_eq!(
        err,
        Ktx2Error::TooLarge {
            width: SIZE,
            height: SIZE,
            pixels: u64::from(SIZE * SIZE),
            max: u64::from(SIZE * SIZE) - 1
        }
    );
}

/// Every truncation of an encoded file and 6000 seeded corruptions (1–8 bytes overwritten)
/// end in an image or a `Ktx2Error`, never a panic: the header checks, the container reader
/// and the transcoder all see hostile bytes.
#[test]
fn truncated_and_corrupted_ktx2_files_never_panic() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_pcg::Pcg64::seed_from_u64(15);
    for codec in [Codec::Etc1s, Codec::Uastc, Codec::UastcZstd] {
        let good = encode(&test_image(true), codec, true);
        // The decoder turns a transcoder panic into `TranscoderPanicked`; none may occur.
        let check = |bytes: &[u8]| {
            let result = decode_ktx2(bytes, ColorSpace::Srgb, 1 << 20);
            assert!(
                !matches!(result, Err(Ktx2Error::TranscoderPanicked(_))),
                "{codec:?}: the transcoder panicked"
            );
        };
        for len in 0..good.len() {
            check(&good[..len]);
        }
        for _ in 0..2000 {
            let mut bad = good.clone();
            for _ in 0..rng.random_range(1..=8) {
                // Half the hits land in the header, level index, DFD, metadata and BasisLZ
                // global data (the first 256 bytes), where the sizes and offsets live.
                let at = if rng.random_bool(0.5) {
                    rng.random_range(0..256.min(bad.len()))
                } else {
                    rng.random_range(0..bad.len())
                };
                bad[at] = rng.random();
            }
            check(&bad);
        }
    }
}

/// `ktx2` with its `KTXwriter` metadata entry rewritten, in place, as a `KTXorientation`
/// entry of value `orientation` (the reference encoder writes no orientation).
fn with_orientation(ktx2: &[u8], orientation: &str) -> Vec<u8> {
    let key = b"KTXwriter\0";
    let at = ktx2
        .windows(key.len())
        .position(|w| w == key)
        .expect("the encoder writes KTXwriter");
    let length = u32::from_le_bytes(ktx2[at - 4..at].try_into().expect("4 bytes")) as usize;
    let mut entry = b"KTXorientation\0".to_vec();
    entry.extend_from_slice(orientation.as_bytes());
    entry.push(0);
    assert!(entry.len() <= length, "the writer entry is long enough");
    entry.resize(length, 0);
    let mut out = ktx2.to_vec();
    out[at..at + length].copy_from_slice(&entry);
    out
}

#[test]
fn a_bottom_up_ktxorientation_is_flipped_to_gltf_top_down_with_a_note() {
    let good = encode(&test_image(false), Codec::Uastc, true);
    let (top_down, notes) = decode_ktx2(&good, ColorSpace::Srgb, 1 << 20).expect("decode");
    assert!(notes.is_empty(), "{notes:?}");
    let rd = with_orientation(&good, "rd");
    let (same, notes) = decode_ktx2(&rd, ColorSpace::Srgb, 1 << 20).expect("decode rd");
    assert!(notes.is_empty(), "{notes:?}");
    assert_eq!(same, top_down, "rd is glTF's orientation: nothing changes");
    let ru = with_orientation(&good, "ru");
    let (flipped, notes) = decode_ktx2(&ru, ColorSpace::Srgb, 1 << 20).expect("decode ru");
    assert!(
        notes.len() == 1 && notes[0].contains("KTXorientation is \"ru\""),
        "{notes:?}"
    );
    let n = SIZE as usize;
    for y in 0..n {
        for x in 0..n {
            assert_eq!(
                flipped.texels.texel(y * n + x),
                top_down.texels.texel((n - 1 - y) * n + x),
                "texel ({x}, {y})"
            );
        }
    }
}

#[test]
fn a_ktx2_image_in_a_buffer_view_loads_like_a_data_uri() {
    let source = test_image(false);
    let ktx2 = encode(&source, Codec::Etc1s, true);
    let mut fixture = Fixture::new();
    let view = fixture.view(&ktx2);
    let rest = quad_document(
        &mut fixture,
        json!([basisu_texture(0), basisu_texture(0)]),
        json!([{"bufferView": view, "mimeType": "image/ktx2"}]),
        false,
    );
    let from_view = fixture.load(rest).expect("load from a buffer view");
    let from_uri = load_pair(&ktx2, &ktx2).expect("load from data URIs");
    assert_eq!(
        texture(&from_view.scene, 0).texels,
        texture(&from_uri.scene, 0).texels
    );
}
