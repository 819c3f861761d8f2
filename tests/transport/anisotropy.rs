//! KHR_materials_anisotropy in a render (issue 35): the highlight of a point light on a flat
//! anisotropic metal plane, seen straight down by an orthographic camera, is stretched along
//! the anisotropy direction by the closed-form ratio, and the direction follows
//! `anisotropyTexture` and `anisotropyRotation`.
//!
//! At a plane point `p = (x, y, 0)` with the light at `(0, 0, H)` and the view `wo = +Z`, the
//! radiance is `L(p) = f(wo, wi) cos θi I / d²` with `f = F D(h) G2(wo, wi) k / (4 cos θo
//! cos θi)`: for white metal `F = 1` and the compensation `k(μo)` is the same everywhere,
//! so `L ∝ D(h) G2(wo, wi) / d²`, written out again here in f64 for the extension's
//! `αt = mix(α, 1, s²)`, `αb = α`. The half-maximum extents of that profile along `t` and
//! `b` have a ratio near `αt/αb`; the render must give the f64 ratio within 5 %.

use crate::support::{centre_settings, ortho, quad, render_with};
use glam::{DVec3, Vec2, Vec3, Vec4};
use glint::accel::BackendKind;
use glint::render::{Integrator, RenderSettings};
use glint::scene::layers::Anisotropy;
use glint::scene::{Light, MagFilter, Material, Scene, Texture, TextureRef, WrapMode};

/// Image side (odd: the centre pixel sits on the light's foot).
const W: u32 = 301;
/// Half the view's width (scene units).
const VIEW: f32 = 1.6;
/// The light's height above the plane.
const H: f64 = 2.0;

/// The extension's roughnesses `(αt, αb)` for perceptual roughness `r` and strength `s`.
fn alphas(r: f64, s: f64) -> (f64, f64) {
    let a = r * r;
    (a + (1.0 - a) * s * s, a)
}

/// `L(p) ∝ D(h) G2(wo, wi) / d²` for the plane point `(x, y, 0)` with the anisotropy along X.
fn radiance(x: f64, y: f64, (ax, ay): (f64, f64)) -> f64 {
    let to_light = DVec3::new(-x, -y, H);
    let d2 = to_light.length_squared();
    let wi = to_light / d2.sqrt();
    let wo = DVec3::Z;
    let h = (wo + wi).normalize();
    let dd = {
        let s = (h.x / ax).powi(2) + (h.y / ay).powi(2) + h.z * h.z;
        1.0 / (std::f64::consts::PI * ax * ay * s * s)
    };
    let lambda = |w: DVec3| {
        let t = ((ax * w.x).powi(2) + (ay * w.y).powi(2)) / (w.z * w.z);
        ((1.0 + t).sqrt() - 1.0) / 2.0
    };
    dd / (1.0 + lambda(wo) + lambda(wi)) / d2
}

/// Distance from the centre at which `profile` (sampled at offsets `k · step`, k ≥ 0) first
/// falls below half its value at 0, linearly interpolated between samples.
fn half_width(profile: impl Fn(usize) -> f64, step: f64, n: usize) -> f64 {
    let peak = profile(0);
    for k in 1..n {
        let (a, b) = (profile(k - 1), profile(k));
        if b < 0.5 * peak {
            let t = (a - 0.5 * peak) / (a - b);
            return (k as f64 - 1.0 + t) * step;
        }
    }
    f64::INFINITY
}

/// The closed-form half-maximum extents along X and Y.
fn expected_extents(alphas: (f64, f64)) -> (f64, f64) {
    let step = 1e-4;
    let n = 200_000;
    (
        half_width(|k| radiance(k as f64 * step, 0.0, alphas), step, n),
        half_width(|k| radiance(0.0, k as f64 * step, alphas), step, n),
    )
}

/// Renders the plane (white metal, perceptual roughness `r`) with `anisotropy`, a 1×1
/// `texel` texture when given, and returns the half-maximum extents of the highlight along
/// world X and Y, averaged over both sides of the centre.
fn rendered_extents(
    backend: BackendKind,
    r: f32,
    anisotropy: Anisotropy,
    texel: Option<Vec4>,
) -> (f64, f64) {
    let mut plane = quad(Vec3::ZERO, Vec3::X * 3.0, Vec3::Y * 3.0, 0);
    plane.tangents = Some(vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4]);
    plane.texcoords[0] = Some(vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y]);
    let textures = texel.map_or_else(Vec::new, |c| {
        vec![Texture {
            name: "anisotropy".into(),
            width: 1,
            height: 1,
            texels: vec![c].into(),
            wrap_s: WrapMode::ClampToEdge,
            wrap_t: WrapMode::ClampToEdge,
            mag_filter: MagFilter::Nearest,
        }]
    });
    let material = Material {
        name: "brushed".into(),
        base_color: Vec4::ONE,
        metallic: 1.0,
        roughness: r,
        anisotropy: Some(Anisotropy {
            texture: texel.map(|_| TextureRef {
                texture: 0,
                texcoord: 0,
                transform: glam::Affine2::IDENTITY,
            }),
            ..anisotropy
        }),
        ..Material::default()
    };
    let scene = Scene {
        meshes: vec![plane],
        materials: vec![material],
        lights: vec![Light::Point {
            position: Vec3::new(0.0, 0.0, H as f32),
            intensity: Vec3::splat(10.0),
            range: None,
        }],
        textures,
        ..Scene::default()
    };
    let camera = ortho(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO, Vec3::Y, VIEW, VIEW);
    // One sample at each pixel centre: a point light's direct light there is deterministic.
    let settings = RenderSettings {
        integrator: Integrator::Path,
        max_depth: 2,
        ..centre_settings(W, W)
    };
    let out = render_with(&scene, &camera, backend, &settings);
    let px = |x: u32, y: u32| f64::from(out.image.pixels[(y * W + x) as usize].x);
    let c = W / 2;
    let step = 2.0 * f64::from(VIEW) / f64::from(W);
    let n = c as usize;
    let along_x = 0.5
        * (half_width(|k| px(c + k as u32, c), step, n)
            + half_width(|k| px(c - k as u32, c), step, n));
    let along_y = 0.5
        * (half_width(|k| px(c, c + k as u32), step, n)
            + half_width(|k| px(c, c - k as u32), step, n));
    (along_x, along_y)
}

#[test]
fn highlight_extents_follow_the_anisotropic_roughnesses_and_direction() {
    let (r, s) = (0.3f32, 0.5f32);
    let (want_t, want_b) = expected_extents(alphas(f64::from(r), f64::from(s)));
    let ratio = want_t / want_b;
    eprintln!("closed form: extents along t {want_t:.4}, along b {want_b:.4}, ratio {ratio:.3}");
    assert!(
        ratio > 3.0,
        "the test needs a clearly elongated highlight: {ratio}"
    );
    let plain = Anisotropy {
        strength: s,
        rotation: 0.0,
        texture: None,
    };
    let quarter = Anisotropy {
        rotation: std::f32::consts::FRAC_PI_2,
        ..plain
    };
    let mut failures = Vec::new();
    for &backend in BackendKind::available() {
        // (what, anisotropy, texel, whether t lies along world X)
        let cases = [
            ("tangent direction", plain, None, true),
            ("rotation π/2", quarter, None, false),
            // RG (0.5, 1) is the bitangent, +Y here; B = 1 keeps the strength.
            (
                "texture direction +b",
                plain,
                Some(Vec4::new(0.5, 1.0, 1.0, 1.0)),
                false,
            ),
            // RG (1, 0.5) is the tangent again, and a quarter rotation turns it to +b.
            (
                "texture +t, rotation π/2",
                quarter,
                Some(Vec4::new(1.0, 0.5, 1.0, 1.0)),
                false,
            ),
        ];
        for (what, a, texel, along_x) in cases {
            let (x, y) = rendered_extents(backend, r, a, texel);
            let (long, short) = if along_x { (x, y) } else { (y, x) };
            let got = long / short;
            eprintln!("{backend}, {what}: extents x {x:.4}, y {y:.4}, ratio {got:.3}");
            if (got / ratio - 1.0).abs() > 0.05
                || (long / want_t - 1.0).abs() > 0.05
                || (short / want_b - 1.0).abs() > 0.05
            {
                failures.push(format!(
                    "{backend}, {what}: extents ({long:.4}, {short:.4}) ratio {got:.3}, want ({want_t:.4}, {want_b:.4}) ratio {ratio:.3}"
                ));
            }
        }
        // Strength 0 through the texture's blue channel: a round highlight.
        let (x, y) = rendered_extents(backend, r, plain, Some(Vec4::new(1.0, 0.5, 0.0, 1.0)));
        let (iso, _) = expected_extents(alphas(f64::from(r), 0.0));
        if (x / y - 1.0).abs() > 0.02 || (x / iso - 1.0).abs() > 0.05 {
            failures.push(format!(
                "{backend}, texture strength 0: extents ({x:.4}, {y:.4}), want round {iso:.4}"
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
