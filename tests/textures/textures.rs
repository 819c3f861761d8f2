//! Texture filtering: MIP level selection against the analytic footprint, wrap modes at
//! extreme and exact coordinates, 1 × 1 and non-power-of-two MIP chains, sRGB versus linear
//! decoding, procedural textures from `extras`, and the aliasing order of the filters on the
//! checker-plane scene (both backends).

use crate::support::look_at;
use glam::{Vec2, Vec3, Vec4};
use glint::accel::{BackendKind, BuildOptions};
use glint::render::{self, CameraRays, Image, RenderSettings};
use glint::scene::texture_decode::{ColorSpace, decode_image, srgb_to_linear};
use glint::scene::{MagFilter, WrapMode};
use glint::texture::differentials::{at_surface, attribute_derivative, barycentric_derivatives};
use glint::texture::filter::isotropic_lod;
use glint::texture::image::{TexelGrid, Wrap};
use glint::texture::{MipMap, TextureFilter, UvFootprint, lookup};
use std::path::Path;

/// A plane y = 0 seen from height h, pitched down by α: at the image centre the pixel's
/// footprint is d·δ across and d·δ / sin α along the view, with d = h / sin α the distance and
/// δ = 2·tan(yfov/2)/H the pixel's angular size. The differentials and the selected MIP level
/// must match (a plane's texture coordinates are linear in position, so first order is exact
/// up to the pixel's own curvature).
#[test]
fn mip_level_matches_the_analytic_footprint() {
    let (width, height) = (400u32, 300u32);
    let yfov = 0.8f32;
    let metres_per_uv = 4.0f32;
    let texels = 1024u32;
    let mip = MipMap::from_grid(
        TexelGrid::new(texels, texels, vec![Vec4::ONE; (texels * texels) as usize]).unwrap(),
        Wrap::default(),
        MagFilter::Linear,
    );
    // A big triangle in y = 0 with uv = (x, z) / metres_per_uv.
    let tri = [
        Vec3::new(-1000.0, 0.0, 1000.0),
        Vec3::new(1000.0, 0.0, 1000.0),
        Vec3::new(0.0, 0.0, -1000.0),
    ];
    let uvs: Vec<Vec2> = tri
        .iter()
        .map(|p| Vec2::new(p.x, p.z) / metres_per_uv)
        .collect();
    for &(h, alpha_deg) in &[(2.0f32, 60.0f32), (1.5, 20.0), (10.0, 5.0), (0.5, 85.0)] {
        let alpha = alpha_deg.to_radians();
        let d = h / alpha.sin();
        let eye = Vec3::new(0.0, h, 0.0);
        let target = eye + Vec3::new(0.0, -alpha.sin(), -alpha.cos()) * d;
        let camera = look_at(eye, target, Vec3::Y, yfov);
        let rays = CameraRays::new(&camera, width, height).unwrap();
        let (x, y) = (width as f32 / 2.0, height as f32 / 2.0);
        let ray = rays.ray(x, y);
        let t = -ray.origin.y / ray.dir.y;
        let p = ray.origin + ray.dir * t;
        assert!(
            (t - d).abs() / d < 1e-4,
            "the centre ray hits at the distance d"
        );
        let sd = at_surface(&rays.ray_differential(x, y, 1.0), p, Vec3::Y);
        let db_dx = barycentric_derivatives(tri, sd.dp_dx);
        let db_dy = barycentric_derivatives(tri, sd.dp_dy);
        let footprint = UvFootprint {
            duv_dx: attribute_derivative(&uvs, [0, 1, 2], db_dx).unwrap(),
            duv_dy: attribute_derivative(&uvs, [0, 1, 2], db_dy).unwrap(),
        };
        let delta = 2.0 * (yfov / 2.0).tan() / height as f32;
        let across_uv = d * delta / metres_per_uv;
        let along_uv = d * delta / alpha.sin() / metres_per_uv;
        let rel = |got: f32, want: f32| (got - want).abs() / want;
        // The differential is a one-pixel finite difference: across the view it is exact to
        // first order; along it the footprint grows over the pixel by about δ / tan α
        // relative (the second-order term), which matters at grazing angles.
        let second_order = 2.0 * delta / alpha.tan();
        assert!(
            rel(footprint.duv_dx.length(), across_uv) < 0.01,
            "h {h} α {alpha_deg}"
        );
        assert!(
            rel(footprint.duv_dy.length(), along_uv) < 0.01 + second_order,
            "h {h} α {alpha_deg}: {} vs {along_uv}",
            footprint.duv_dy.length()
        );
        let lod = isotropic_lod(&mip, &footprint);
        let want = (along_uv.max(across_uv) * texels as f32).log2();
        assert!(
            (lod - want).abs() < 0.05,
            "h {h} α {alpha_deg}: λ {lod} vs {want}"
        );
    }
}

fn ramp(width: u32, height: u32) -> TexelGrid {
    let texels: Vec<Vec4> = (0..width * height).map(|i| Vec4::splat(i as f32)).collect();
    TexelGrid::new(width, height, texels).unwrap()
}

fn wrap(s: WrapMode) -> Wrap {
    Wrap { s, t: s }
}

/// Texel i of a 4 × 1 ramp holds the value i.
#[test]
fn wrap_modes_far_away_at_integers_and_on_texel_borders() {
    let g = ramp(4, 1);
    let at = |u: f32, mode| g.nearest(Vec2::new(u, 0.5), wrap(mode)).x;
    let (r, m, c) = (
        WrapMode::Repeat,
        WrapMode::MirroredRepeat,
        WrapMode::ClampToEdge,
    );
    // ±1e6 is an even integer: repeat and mirrored repeat are back at the first period.
    for u in [1e6f32, -1e6] {
        assert_eq!(at(u + 0.125, r), 0.0);
        assert_eq!(at(u + 0.875, r), 3.0);
        assert_eq!(at(u + 0.125, m), 0.0);
        assert_eq!(at(u + 0.625, m), 2.0);
    }
    // 1e6 + 1: an odd period, mirrored.
    assert_eq!(at(1e6 + 1.125, m), 3.0);
    assert_eq!(at(1e6 + 0.5, c), 3.0);
    assert_eq!(at(-1e6, c), 0.0);
    // Exact integers: u = 1 starts the next period (repeat) or its mirror (last texel).
    assert_eq!(at(1.0, r), 0.0);
    assert_eq!(at(1.0, m), 3.0);
    assert_eq!(at(1.0, c), 3.0);
    assert_eq!(at(-1.0, r), 0.0);
    assert_eq!(at(0.0, m), 0.0);
    // Texel borders are half-open: u = 1/4 is texel 1.
    assert_eq!(at(0.25, r), 1.0);
    // Bilinear on a border is the average of the two texels; at u = 0 (a period border) it
    // blends the last and the first texel under repeat, and the first with itself otherwise.
    let bilinear = |u: f32, mode| g.bilinear(Vec2::new(u, 0.5), wrap(mode)).x;
    assert_eq!(bilinear(0.25, r), 0.5);
    assert_eq!(bilinear(0.0, r), 1.5);
    assert_eq!(bilinear(0.0, m), 0.0);
    assert_eq!(bilinear(0.0, c), 0.0);
    assert_eq!(bilinear(1e6, r), 1.5);
    // Texel centres are exact under the interpolating filters.
    for mode in [r, m, c] {
        assert_eq!(g.bicubic(Vec2::new(0.375, 0.5), wrap(mode)).x, 1.0);
        assert_eq!(bilinear(0.625, mode), 2.0);
    }
}

#[test]
fn one_by_one_textures_read_their_texel_under_every_filter() {
    let value = Vec4::new(0.2, 0.4, 0.6, 1.0);
    let mip = MipMap::from_grid(
        TexelGrid::new(1, 1, vec![value]).unwrap(),
        wrap(WrapMode::MirroredRepeat),
        MagFilter::Nearest,
    );
    assert_eq!(mip.level_count(), 1);
    let footprints = [
        UvFootprint::default(),
        UvFootprint {
            duv_dx: Vec2::new(30.0, 0.1),
            duv_dy: Vec2::new(0.0, 1e-3),
        },
        UvFootprint {
            duv_dx: Vec2::splat(f32::INFINITY),
            duv_dy: Vec2::NAN,
        },
    ];
    for filter in [
        TextureFilter::Nearest,
        TextureFilter::Bilinear,
        TextureFilter::Bicubic,
        TextureFilter::Trilinear,
        TextureFilter::Anisotropic,
    ] {
        for f in &footprints {
            for uv in [Vec2::ZERO, Vec2::new(-7.3, 1e6), Vec2::NAN] {
                let got = lookup(&mip, uv, f, filter);
                assert!(
                    (got - value).abs().max_element() < 1e-6,
                    "{filter:?} {uv} {f:?}"
                );
            }
        }
    }
}

/// Non-power-of-two chains: sides halve rounding down to 1, every level keeps the base mean
/// (the box filter drops and doubles nothing), and the chain costs at most 4/3 of the base
/// when both sides halve (aspect ≤ 2), at most 2× for strip-like textures whose tail halves
/// one side only.
#[test]
fn non_power_of_two_chains_keep_the_mean_within_four_thirds() {
    for &(w, h) in &[
        (5u32, 3u32),
        (7, 1),
        (1, 9),
        (33, 17),
        (100, 75),
        (255, 256),
    ] {
        let mip = MipMap::from_grid(ramp(w, h), Wrap::default(), MagFilter::Linear);
        let levels = mip.levels();
        let mean = |g: &TexelGrid| {
            g.texels.iter().map(|t| f64::from(t.x)).sum::<f64>() / g.texels.len() as f64
        };
        let base_mean = mean(&levels[0]);
        for pair in levels.windows(2) {
            assert_eq!(pair[1].width, (pair[0].width / 2).max(1));
            assert_eq!(pair[1].height, (pair[0].height / 2).max(1));
        }
        let top = levels.last().unwrap();
        assert_eq!((top.width, top.height), (1, 1));
        for level in levels {
            assert!(
                (mean(level) - base_mean).abs() <= 1e-4 * base_mean.max(1.0),
                "{w}×{h}"
            );
        }
        let (base, all) = (levels[0].bytes(), mip.bytes());
        if w.max(h) <= 2 * w.min(h) {
            assert!(
                all * 3 <= base * 4,
                "{w}×{h}: {all} bytes for a base of {base}"
            );
        }
        assert!(all <= 2 * base, "{w}×{h}: {all} bytes for a base of {base}");
    }
}

/// Base colour (sRGB) and data (linear) decoding of the same 8-bit code differ by the sRGB
/// EOTF; the checker scene's base colour texture decodes to the linear reflectances the
/// generator encoded.
#[test]
fn srgb_base_colour_versus_linear_data() {
    let image = image::RgbaImage::from_raw(1, 1, vec![128, 10, 255, 128]).unwrap();
    let mut png = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    let srgb = decode_image(&png, ColorSpace::Srgb, 1 << 20)
        .unwrap()
        .texels
        .texel(0);
    let linear = decode_image(&png, ColorSpace::Linear, 1 << 20)
        .unwrap()
        .texels
        .texel(0);
    assert!((srgb.x - srgb_to_linear(128.0 / 255.0)).abs() < 1e-6);
    assert!(
        (srgb.x - 0.2158605).abs() < 1e-5,
        "sRGB 128 is about 0.216 linear"
    );
    assert!(
        (srgb.y - 10.0 / 255.0 / 12.92).abs() < 1e-6,
        "the linear segment"
    );
    assert!((linear.x - 128.0 / 255.0).abs() < 1e-6);
    assert_eq!(srgb.w, linear.w, "alpha is linear in both");

    let scene = glint::scene::gltf::load(&scene_path()).unwrap();
    let texture = &scene.textures[0];
    let (lo, hi) = texture
        .texels
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), t| {
            (lo.min(t.x), hi.max(t.x))
        });
    // 8-bit sRGB quantisation: within half a code's slope of 0.05 and 0.8.
    assert!(
        (lo - 0.05).abs() < 0.002 && (hi - 0.8).abs() < 0.004,
        "{lo} {hi}"
    );
}

fn scene_path() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/checker-plane.gltf")
}

#[test]
fn procedural_textures_load_from_extras_and_bad_ones_name_the_material() {
    let scene = glint::scene::gltf::load(&scene_path()).unwrap();
    let procedural = scene.materials[1]
        .procedural
        .as_ref()
        .expect("material 1 is procedural");
    assert_eq!(procedural.frequency, 32.0);
    assert!(scene.materials[0].procedural.is_none());

    let text = std::fs::read_to_string(scene_path()).unwrap();
    for (bad, expect) in [
        ("\"pattern\": \"checker\"", "unknown pattern"),
        ("\"domain\": \"uv0\"", "unknown domain"),
        ("\"frequency\": 32.0", "frequency"),
    ] {
        let replacement = match expect {
            "unknown pattern" => "\"pattern\": \"plaid\"",
            "unknown domain" => "\"domain\": \"uv7\"",
            _ => "\"frequency\": -1.0",
        };
        assert!(text.contains(bad), "the scene spells {bad}");
        let broken = text.replace(bad, replacement);
        let err = glint::scene::gltf::load_slice(broken.as_bytes(), "broken.gltf", None)
            .expect_err("bad extras must fail")
            .to_string();
        assert!(
            err.contains("procedural checker")
                && err.contains("glint_procedural")
                && err.contains(expect),
            "{err}"
        );
    }
}

fn relative_rmse(image: &Image<Vec3>, reference: &Image<Vec3>) -> f64 {
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for (x, r) in image.pixels.iter().zip(&reference.pixels) {
        num += f64::from((*x - *r).length_squared());
        den += f64::from(r.length_squared());
    }
    (num / den).sqrt()
}

/// On the checker plane at 1 spp, against a high-spp bilinear (unfiltered texture, box pixel)
/// reference: error(anisotropic) < error(trilinear) < error(nearest), on both backends; the
/// procedural half alone shows the same order.
#[test]
fn filtering_reduces_aliasing_on_the_checker_plane() {
    let scene = glint::scene::gltf::load(&scene_path()).unwrap();
    let camera = scene.cameras[0].clone();
    for &backend in BackendKind::available() {
        let accel = render::prepare(&scene, backend, BuildOptions::default()).unwrap();
        let settings = |filter, spp| RenderSettings {
            integrator: glint::render::Integrator::Direct,
            width: 192,
            height: 108,
            spp,
            seed: 3,
            threads: 2,
            texture_filter: filter,
            ..RenderSettings::default()
        };
        let run = |filter, spp| {
            let out = render::render(
                &scene,
                accel.as_ref(),
                &camera,
                &settings(filter, spp),
                None,
            )
            .unwrap();
            assert!(out.image.pixels.iter().all(|p| p.is_finite()));
            out.image
        };
        let reference = run(TextureFilter::Bilinear, 256);
        let error = |filter| relative_rmse(&run(filter, 1), &reference);
        let (nearest, trilinear, anisotropic) = (
            error(TextureFilter::Nearest),
            error(TextureFilter::Trilinear),
            error(TextureFilter::Anisotropic),
        );
        assert!(
            anisotropic < trilinear && trilinear < nearest,
            "{backend}: anisotropic {anisotropic}, trilinear {trilinear}, nearest {nearest}"
        );
    }
}
