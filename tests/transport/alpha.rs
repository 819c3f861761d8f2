//! Alpha coverage, back-face culling and unlit materials, against closed forms on every
//! backend and through both kernels (the direct integrator's classic kernel and the path
//! tracer's):
//! - a MASK cut-out quad casts a shadow of exactly its cut-out shape;
//! - a BLEND occluder of coverage α passes 1 − α of the light (statistical tolerance below),
//!   and a BLEND surface seen by the camera shows α of itself and 1 − α of what is behind;
//! - MASK cutoff edge cases (α = cutoff is kept, cutoff 0 keeps everything, cutoff > 1 hides
//!   everything), for constant, texture and vertex-colour alpha;
//! - a single-sided quad seen from behind shows what lies behind it, yet still blocks light;
//! - an unlit surface shows its base colour, whatever the lights and its emissive factor;
//! - Embree and the BVH give the same images, and BLEND images do not depend on the thread
//!   count.

use crate::support::*;
use glam::{Affine2, DVec3, Vec2, Vec3, Vec4};
use glint::accel::BackendKind;
use glint::render::{Integrator, RenderOutput, RenderSettings};
use glint::scene::{
    AlphaMode, Camera, Light, MagFilter, Material, Mesh, Scene, Texture, TextureRef, WrapMode,
};

/// Irradiance of the directional light on a surface facing it, W/m².
const E: f32 = 2.0;
/// Reflectance of the floor.
const RHO: f32 = 0.5;

/// The two kernels: the direct integrator (classic kernel, punctual lights only) and the path
/// tracer limited to direct light (so a shadowed floor is exactly black).
fn kernels(width: u32, height: u32, spp: u32) -> [RenderSettings; 2] {
    let base = RenderSettings {
        spp,
        ..centre_settings(width, height)
    };
    [
        RenderSettings {
            integrator: Integrator::Direct,
            ..base
        },
        RenderSettings {
            integrator: Integrator::Path,
            max_depth: 1,
            ..base
        },
    ]
}

fn render(scene: &Scene, camera: &Camera, backend: BackendKind, s: &RenderSettings) -> Vec<Vec3> {
    let out: RenderOutput = render_with(scene, camera, backend, s);
    out.image.pixels
}

/// `quad` with texture coordinates (0, 0) at `center − u − v`, (1, 1) at `center + u + v`.
fn textured_quad(center: Vec3, u: Vec3, v: Vec3, material: usize) -> Mesh {
    Mesh {
        texcoords: [
            Some(vec![
                Vec2::new(0.0, 0.0),
                Vec2::new(1.0, 0.0),
                Vec2::new(1.0, 1.0),
                Vec2::new(0.0, 1.0),
            ]),
            None,
        ],
        ..quad(center, u, v, material)
    }
}

/// A texture of `alphas` (rows top first) with white RGB and nearest-texel lookups.
fn alpha_texture(alphas: &[&[f32]]) -> Texture {
    let (height, width) = (alphas.len() as u32, alphas[0].len() as u32);
    Texture {
        name: "alpha".into(),
        width,
        height,
        texels: alphas
            .iter()
            .flat_map(|row| row.iter().map(|&a| Vec4::new(1.0, 1.0, 1.0, a)))
            .collect::<Vec<_>>()
            .into(),
        wrap_s: WrapMode::ClampToEdge,
        wrap_t: WrapMode::ClampToEdge,
        mag_filter: MagFilter::Nearest,
    }
}

fn texture_ref() -> Option<TextureRef> {
    Some(TextureRef {
        texture: 0,
        texcoord: 0,
        transform: Affine2::IDENTITY,
    })
}

/// An unlit material of colour `c` (alpha factor `a`).
fn unlit(c: Vec3, a: f32, alpha: AlphaMode) -> Material {
    Material {
        name: "unlit".into(),
        base_color: c.extend(a),
        alpha,
        unlit: true,
        double_sided: true,
        ..Material::default()
    }
}

// ---------------------------------------------------------------------------------------
// Shadows: a floor at y = 0 (x ∈ [−4, 2], z ∈ [−3, 3]) lit along (1, −1, 0)/√2, and an
// occluder at y = 2 over x ∈ [−4, −2], z ∈ [−1, 1], facing the floor. Its shadow falls on
// x ∈ [−2, 0], z ∈ [−1, 1]: a floor point (x, 0, z) sees the light through the occluder
// point (x − 2, 2, z), at texture coordinates ((x + 2)/2, (z + 1)/2). An orthographic camera
// at y = 0.5, below the occluder, looks straight down at exactly that region.
// ---------------------------------------------------------------------------------------

fn shadow_scene(occluder: Material, textures: Vec<Texture>) -> (Scene, Camera) {
    let floor = quad(
        Vec3::new(-1.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 3.0),
        Vec3::new(3.0, 0.0, 0.0),
        0,
    );
    // u × v = X × Z = −Y: the front face looks down at the floor.
    let occluder_mesh = textured_quad(Vec3::new(-3.0, 2.0, 0.0), Vec3::X, Vec3::Z, 1);
    let light = Light::Directional {
        direction: Vec3::new(1.0, -1.0, 0.0).normalize(),
        irradiance: Vec3::splat(E),
    };
    let mut scene = scene(
        vec![floor, occluder_mesh],
        vec![lambert(Vec3::splat(RHO), false), occluder],
        vec![light],
    );
    scene.textures = textures;
    let camera = ortho(
        Vec3::new(-1.0, 0.5, 0.0),
        Vec3::new(-1.0, 0.0, 0.0),
        Vec3::X,
        1.0,
        1.0,
    );
    (scene, camera)
}

/// The unshadowed floor's radiance under `settings`: the scene rendered without its occluder
/// (uniform over the image). For the direct integrator it must be the Lambertian closed form
/// ρ/π · E · cos 45°; the path tracer's metallic-roughness BSDF adds its dielectric specular
/// lobe, so there the occluder-free render is the reference.
fn lit_floor(scene: &Scene, camera: &Camera, backend: BackendKind, s: &RenderSettings) -> f64 {
    let mut open = scene.clone();
    open.meshes.truncate(1);
    let pixels = render(&open, camera, backend, s);
    let lit = pixels[0].x as f64;
    assert!(
        pixels.iter().all(|p| *p == pixels[0]),
        "the lit floor is not uniform"
    );
    if s.integrator == Integrator::Direct {
        let lambert =
            RHO as f64 / std::f64::consts::PI * E as f64 * std::f64::consts::FRAC_1_SQRT_2;
        assert!(
            ((lit - lambert) / lambert).abs() < 1e-5,
            "{lit} vs {lambert}"
        );
    }
    lit
}

/// Where pixel (x, y)'s ray meets the floor, as occluder texture coordinates.
fn occluder_uv(camera: &Camera, w: u32, h: u32, x: u32, y: u32) -> DVec3 {
    let ray = centre_ray(camera, w, h, x, y);
    let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
    let p = o + d * (-o.y / d.y);
    DVec3::new((p.x + 2.0) / 2.0, (p.z + 1.0) / 2.0, 0.0)
}

const PATTERN: [[f32; 4]; 4] = [
    [1.0, 0.0, 0.7, 0.3],
    [0.3, 0.7, 0.0, 1.0],
    [0.7, 0.7, 0.3, 0.0],
    [0.0, 1.0, 1.0, 0.5],
];

/// The occluder's material: white Lambert, double-sided (so only alpha is under test).
fn occluder(alpha: AlphaMode, a: f32, textured: bool) -> Material {
    Material {
        alpha,
        base_color_texture: if textured { texture_ref() } else { None },
        ..lambert(Vec3::ONE, true).with_alpha(a)
    }
}

trait WithAlpha {
    fn with_alpha(self, a: f32) -> Self;
}

impl WithAlpha for Material {
    fn with_alpha(mut self, a: f32) -> Self {
        self.base_color.w = a;
        self
    }
}

/// Whether `t` lies within `margin` of a multiple of 1/4 (a texel edge of the pattern).
fn near_cell_edge(t: f64, margin: f64) -> bool {
    let f = (t * 4.0).fract();
    !(margin..1.0 - margin).contains(&f)
}

#[test]
fn mask_cutout_casts_a_shadow_of_its_shape() {
    let rows: Vec<&[f32]> = PATTERN.iter().map(|r| &r[..]).collect();
    let (scene, camera) = shadow_scene(
        occluder(AlphaMode::Mask { cutoff: 0.5 }, 1.0, true),
        vec![alpha_texture(&rows)],
    );
    let (w, h) = (64, 64);
    for settings in kernels(w, h, 1) {
        let mut images = Vec::new();
        for &backend in BackendKind::available() {
            let lit = lit_floor(&scene, &camera, backend, &settings);
            let pixels = render(&scene, &camera, backend, &settings);
            let (mut shadowed, mut open) = (0, 0);
            for y in 0..h {
                for x in 0..w {
                    let uv = occluder_uv(&camera, w, h, x, y);
                    if near_cell_edge(uv.x, 0.03) || near_cell_edge(uv.y, 0.03) {
                        continue;
                    }
                    let (col, row) = ((uv.x * 4.0) as usize, (uv.y * 4.0) as usize);
                    let got = pixels[(y * w + x) as usize];
                    let solid = PATTERN[row][col] >= 0.5;
                    let want = if solid { 0.0 } else { lit };
                    assert!(
                        close(got, DVec3::splat(want), 1e-4),
                        "{backend} {:?}: pixel ({x}, {y}) under texel ({col}, {row}) of alpha {}: \
                         {got} instead of {want}",
                        settings.integrator,
                        PATTERN[row][col]
                    );
                    if solid {
                        shadowed += 1;
                    } else {
                        open += 1;
                    }
                }
            }
            // Both kinds of texel were checked, in the pattern's proportions (9 of 16 solid).
            assert!(
                shadowed > 1500 && open > 1100,
                "{shadowed} shadowed, {open} open"
            );
            images.push(pixels);
        }
        // Backends agree pixel for pixel, edges included (the same hits, the same tests).
        for other in &images[1..] {
            let differ = images[0].iter().zip(other).filter(|(a, b)| a != b).count();
            assert!(differ <= 8, "{differ} pixels differ between backends");
        }
    }
}

/// A BLEND occluder of coverage α over the whole shadow region passes 1 − α of the light:
/// the floor's mean radiance is (1 − α) · lit. Each of the n = 64 × 64 × 16 shadow rays is
/// an independent Bernoulli(1 − α) trial, so the mean's standard deviation is
/// √(α(1 − α)/n) = 0.0018 (α = 0.3); the tolerance 0.01 is 5.5 σ (a false failure has
/// probability below 10⁻⁷), and an opaque or an α-weighted-twice occluder is off by 0.3 or
/// more.
#[test]
fn blend_occluder_transmits_one_minus_alpha_of_the_light() {
    let alpha = 0.3;
    for textured in [false, true] {
        // Constant α, and α from a texture (factor 0.6 × texel 0.5).
        let (scene, camera) = if textured {
            shadow_scene(
                occluder(AlphaMode::Blend, 0.6, true),
                vec![alpha_texture(&[&[0.5]])],
            )
        } else {
            shadow_scene(occluder(AlphaMode::Blend, alpha, false), Vec::new())
        };
        let (w, h) = (64, 64);
        for settings in kernels(w, h, 16) {
            let mut means = Vec::new();
            for &backend in BackendKind::available() {
                let pixels = render(&scene, &camera, backend, &settings);
                let mean = pixels.iter().map(|p| p.x as f64).sum::<f64>() / pixels.len() as f64;
                let transmitted = mean / lit_floor(&scene, &camera, backend, &settings);
                assert!(
                    (transmitted - (1.0 - alpha as f64)).abs() < 0.01,
                    "{backend} {:?} textured {textured}: transmitted {transmitted}, expected {}",
                    settings.integrator,
                    1.0 - alpha
                );
                means.push(mean);
            }
            // The same rays make the same random choices on both backends.
            for m in &means[1..] {
                assert!((m - means[0]).abs() <= 1e-3 * means[0], "{means:?}");
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Camera rays: a front quad at z = 0 (±1, facing +Z) before an unlit background at z = −1
// (±3, colour B), seen by an orthographic camera at z = 2 framing ±0.5. Every camera ray
// meets the front quad, then the background.
// ---------------------------------------------------------------------------------------

const B: Vec3 = Vec3::new(0.0, 0.25, 1.0);
const C: Vec3 = Vec3::new(1.0, 0.5, 0.0);

fn layered(front: Material, front_mesh: Mesh, textures: Vec<Texture>) -> (Scene, Camera) {
    let background = quad(Vec3::new(0.0, 0.0, -1.0), Vec3::X * 3.0, Vec3::Y * 3.0, 1);
    let mut scene = scene(
        vec![front_mesh, background],
        vec![front, unlit(B, 1.0, AlphaMode::Opaque)],
        Vec::new(),
    );
    scene.textures = textures;
    let camera = ortho(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, Vec3::Y, 0.5, 0.5);
    (scene, camera)
}

fn front_quad() -> Mesh {
    textured_quad(Vec3::ZERO, Vec3::X, Vec3::Y, 0)
}

/// The mean colour of every pixel, per backend and kernel.
fn mean_colours(scene: &Scene, camera: &Camera, w: u32, spp: u32) -> Vec<(String, Vec3)> {
    let mut out = Vec::new();
    for settings in kernels(w, w, spp) {
        for &backend in BackendKind::available() {
            let pixels = render(scene, camera, backend, &settings);
            let sum = pixels.iter().fold(DVec3::ZERO, |s, p| s + p.as_dvec3());
            let label = format!("{backend} {:?}", settings.integrator);
            out.push((label, (sum / pixels.len() as f64).as_vec3()));
        }
    }
    out
}

/// A BLEND surface of coverage α = 0.25 shows α · C + (1 − α) · B on average. 32 × 32 pixels
/// × 64 samples = 65536 independent choices: σ = √(α(1 − α)/n) · |C − B| per channel, at most
/// 0.0017; tolerance 0.01 (≥ 5.9 σ).
#[test]
fn blend_surface_shows_alpha_of_itself_and_the_rest_behind() {
    let a = 0.25;
    let (scene, camera) = layered(unlit(C, a, AlphaMode::Blend), front_quad(), Vec::new());
    let want = C * a + B * (1.0 - a);
    for (label, got) in mean_colours(&scene, &camera, 32, 64) {
        assert!(
            (got - want).abs().max_element() < 0.01,
            "{label}: {got} instead of {want}"
        );
    }
}

/// Whether the front quad shows (C) or is cut away (B) in every pixel, for each way of
/// giving it the coverage `alpha` under `mode`.
fn mask_shows(mode: AlphaMode, alpha: f32) -> bool {
    let mut answers = Vec::new();
    // Constant α, α from a texture, α from COLOR_0.
    for source in 0..3 {
        let (factor, textures, mesh) = match source {
            0 => (alpha, Vec::new(), front_quad()),
            1 => (1.0, vec![alpha_texture(&[&[alpha]])], front_quad()),
            _ => (
                1.0,
                Vec::new(),
                Mesh {
                    colors: Some(vec![Vec4::ONE.with_w(alpha); 4]),
                    ..front_quad()
                },
            ),
        };
        let mut material = unlit(C, factor, mode);
        if source == 1 {
            material.base_color_texture = texture_ref();
        }
        let (scene, camera) = layered(material, mesh, textures);
        for (label, got) in mean_colours(&scene, &camera, 8, 1) {
            let shows = got == C;
            assert!(
                shows || got == B,
                "{label}, source {source}: {got} is neither C nor B"
            );
            answers.push(shows);
        }
    }
    assert!(
        answers.iter().all(|&s| s == answers[0]),
        "{mode:?} α {alpha}: sources, kernels or backends disagree: {answers:?}"
    );
    answers[0]
}

#[test]
fn mask_cutoff_edge_cases() {
    let mask = |cutoff| AlphaMode::Mask { cutoff };
    // glTF: opaque where α ≥ alphaCutoff, transparent below.
    assert!(mask_shows(mask(0.5), 0.5));
    assert!(!mask_shows(mask(0.5), 0.5f32.next_down()));
    assert!(mask_shows(mask(0.5), 0.75));
    assert!(!mask_shows(mask(0.5), 0.0));
    // Cutoff 0 keeps even α = 0; cutoff 1 keeps only α = 1; above 1 nothing is kept.
    assert!(mask_shows(mask(0.0), 0.0));
    assert!(mask_shows(mask(1.0), 1.0));
    assert!(!mask_shows(mask(1.0), 0.99));
    assert!(!mask_shows(mask(1.5), 1.0));
    // OPAQUE ignores α; BLEND at α = 0 and 1 is deterministic.
    assert!(mask_shows(AlphaMode::Opaque, 0.0));
    assert!(!mask_shows(AlphaMode::Blend, 0.0));
    assert!(mask_shows(AlphaMode::Blend, 1.0));
}

#[test]
fn single_sided_quad_seen_from_behind_shows_what_lies_behind_it() {
    let front = |double_sided| Material {
        double_sided,
        ..unlit(C, 1.0, AlphaMode::Opaque)
    };
    // Facing the camera (+Z): seen, single- or double-sided.
    for double_sided in [false, true] {
        let (scene, camera) = layered(front(double_sided), front_quad(), Vec::new());
        for (label, got) in mean_colours(&scene, &camera, 8, 1) {
            assert_eq!(got, C, "{label}: front face, double-sided {double_sided}");
        }
    }
    // Facing away (−Z): a single-sided quad is culled, a double-sided one is seen.
    let away = textured_quad(Vec3::ZERO, Vec3::Y, Vec3::X, 0);
    for (double_sided, want) in [(false, B), (true, C)] {
        let (scene, camera) = layered(front(double_sided), away.clone(), Vec::new());
        for (label, got) in mean_colours(&scene, &camera, 8, 1) {
            assert_eq!(got, want, "{label}: back face, double-sided {double_sided}");
        }
    }
}

/// glint culls back faces for camera rays only (docs/alpha.md): a single-sided occluder whose
/// back faces the light still shadows the floor, as in Cycles.
#[test]
fn single_sided_back_faces_still_block_light() {
    let (mut scene, camera) = shadow_scene(lambert(Vec3::ONE, false), Vec::new());
    // Turn the occluder's front face up, toward the light: the floor sees its back.
    scene.meshes[1] = textured_quad(Vec3::new(-3.0, 2.0, 0.0), Vec3::Z, Vec3::X, 1);
    for settings in kernels(16, 16, 1) {
        for &backend in BackendKind::available() {
            let pixels = render(&scene, &camera, backend, &settings);
            assert!(
                pixels.iter().all(|p| *p == Vec3::ZERO),
                "{backend} {:?}: light leaked through a back face",
                settings.integrator
            );
        }
    }
}

/// An unlit surface shows its base colour (× vertex colour) whatever lights the scene and
/// whatever its emissive factor.
#[test]
fn unlit_surface_shows_its_base_colour_only() {
    let material = Material {
        emissive: Vec3::splat(5.0),
        ..unlit(Vec3::new(0.5, 1.0, 0.25), 1.0, AlphaMode::Opaque)
    };
    let mesh = Mesh {
        colors: Some(vec![Vec4::new(0.5, 0.5, 1.0, 1.0); 4]),
        ..front_quad()
    };
    let (mut scene, camera) = layered(material, mesh, Vec::new());
    scene.lights.push(Light::Directional {
        direction: -Vec3::Z,
        irradiance: Vec3::splat(10.0),
    });
    for (label, got) in mean_colours(&scene, &camera, 8, 1) {
        assert_eq!(got, Vec3::new(0.25, 0.5, 0.25), "{label}");
    }
}

/// BLEND decisions hash the ray's identity, never a worker's state: 1 and 2 threads give
/// bit-identical images, and another seed gives another image.
#[test]
fn blend_images_do_not_depend_on_thread_count() {
    let (scene, camera) = shadow_scene(occluder(AlphaMode::Blend, 0.5, false), Vec::new());
    for settings in kernels(48, 48, 4) {
        let sobol = RenderSettings {
            sampling: glint::render::PixelSampling::Sobol,
            ..settings
        };
        let one = render(
            &scene,
            &camera,
            BackendKind::Bvh,
            &RenderSettings {
                threads: 1,
                ..sobol
            },
        );
        let two = render(
            &scene,
            &camera,
            BackendKind::Bvh,
            &RenderSettings {
                threads: 2,
                ..sobol
            },
        );
        assert!(
            one == two,
            "{:?}: thread count changed the image",
            settings.integrator
        );
        let reseeded = render(
            &scene,
            &camera,
            BackendKind::Bvh,
            &RenderSettings { seed: 9, ..sobol },
        );
        assert!(
            one != reseeded,
            "{:?}: the seed is not used",
            settings.integrator
        );
    }
}

/// Issue 36: the ID AOVs follow the camera's visibility rules. A MASK front quad cut away on
/// its left half (texture α 0 there, 1 on the right) before the opaque background: every
/// pixel's `instance_id` and `material_id` name what the pixel shows, the background (mesh 1,
/// material 1) through the hole and the front quad (mesh 0, material 0) elsewhere, on every
/// backend; the radiance agrees (B through the hole, C elsewhere).
#[test]
fn id_aovs_show_the_surface_behind_an_alpha_cut_out() {
    let (scene, camera) = layered(
        Material {
            base_color_texture: texture_ref(),
            ..unlit(C, 1.0, AlphaMode::Mask { cutoff: 0.5 })
        },
        front_quad(),
        vec![alpha_texture(&[&[0.0, 1.0]])],
    );
    let (w, h) = (8, 4);
    let settings = RenderSettings {
        integrator: glint::render::Integrator::Direct,
        aovs: glint::render::AovSelection {
            instance_id: true,
            material_id: true,
            ..Default::default()
        },
        ..centre_settings(w, h)
    };
    for &backend in BackendKind::available() {
        let out = render_with(&scene, &camera, backend, &settings);
        let ids = out.aovs.instance_id.as_ref().expect("instance_id");
        let materials = out.aovs.material_id.as_ref().expect("material_id");
        for y in 0..h {
            for x in 0..w {
                let i = (y * w + x) as usize;
                // The camera frames x ∈ [−0.5, 0.5] of the quad's [−1, 1]: texture u =
                // (x + 1)/2 < 0.5 (the hole) for the left half of the image.
                let hole = x < w / 2;
                let want = if hole { 1 } else { 0 };
                assert_eq!(ids.pixels[i], want, "{backend}: instance_id at ({x}, {y})");
                assert_eq!(
                    materials.pixels[i], want,
                    "{backend}: material_id at ({x}, {y})"
                );
                let colour = if hole { B } else { C };
                assert!(
                    (out.image.pixels[i] - colour).abs().max_element() < 1e-4,
                    "{backend}: radiance {} at ({x}, {y})",
                    out.image.pixels[i]
                );
            }
        }
    }
}
