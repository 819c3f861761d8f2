//! White furnace for the glTF metallic-roughness material (issue 22): a white sphere (base
//! colour 1) under a uniform environment of radiance 1 reflects exactly 1 wherever it is seen,
//! when the BRDF conserves energy. Rendered with the path tracer (≥ 32 bounces, Russian
//! roulette on) at roughness 0.25, 0.5 and 1 for metallic 1 and metallic 0, on every backend:
//! the mean over the sphere's pixels must be 1 within 1 %, and every ring from centre to rim
//! (equal widths in the disc's radius; the last ring sees the surface at grazing angles) within
//! 2 %. Non-convex: two touching rough-metal spheres on a metal slab, where light bounces
//! many times between the surfaces, render every 8×8 block within 3 % of 1. With
//! `BrdfModel::Spec`, glTF's Appendix B taken literally, the rough metal sphere
//! must be clearly darker: single-scatter GGX loses the light that bounces between microfacets,
//! which proves the option changes the model.

mod render_support;

use glam::{Vec2, Vec3, Vec4};
use glint::accel::{BackendKind, BuildOptions};
use glint::light::environment::EnvironmentLight;
use glint::render::{self, BrdfModel, Integrator, PixelSampling, RenderInputs, RenderSettings};
use glint::scene::{Material, Mesh};
use render_support::{look_at, ortho, quad, scene};

/// Image side in pixels; the sphere's disc spans `SIZE · RADIUS_IN_VIEW` of it.
const SIZE: u32 = 48;
/// Half the orthographic view's width over the sphere's radius.
const VIEW: f32 = 1.05;
/// Rings from centre to rim, and the share of the radius they cover (pixels farther out may
/// straddle the silhouette, where the tessellation's flat facets show).
const RINGS: usize = 6;
const RIM: f64 = 0.97;

/// A UV sphere of radius 1 around the origin with smooth vertex normals.
fn sphere(material: usize) -> Mesh {
    let (stacks, slices) = (96u32, 192u32);
    let mut positions = Vec::new();
    for i in 0..=stacks {
        let theta = std::f32::consts::PI * i as f32 / stacks as f32;
        for j in 0..=slices {
            let phi = std::f32::consts::TAU * j as f32 / slices as f32;
            positions.push(Vec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ));
        }
    }
    let row = slices + 1;
    let mut indices = Vec::new();
    for i in 0..stacks {
        for j in 0..slices {
            let (a, b) = (i * row + j, i * row + j + 1);
            let (c, d) = (a + row, b + row);
            if i > 0 {
                indices.push([a, c, b]);
            }
            if i + 1 < stacks {
                indices.push([b, c, d]);
            }
        }
    }
    Mesh {
        name: "sphere".into(),
        normals: Some(positions.clone()),
        positions,
        indices,
        material,
        ..Mesh::default()
    }
}

fn white(metallic: f32, roughness: f32) -> Material {
    Material {
        name: "white".into(),
        base_color: Vec4::ONE,
        metallic,
        roughness,
        ..Material::default()
    }
}

/// The mean over the sphere's pixels and per ring, by backend.
fn furnace(material: Material, brdf: BrdfModel, backend: BackendKind, spp: u32) -> (f64, Vec<f64>) {
    let scene = scene(vec![sphere(0)], vec![material], vec![]);
    let camera = ortho(Vec3::new(0.0, -4.0, 0.3), Vec3::ZERO, Vec3::Z, VIEW, VIEW);
    let env = EnvironmentLight::constant(Vec3::ONE);
    let accel = render::prepare(&scene, backend, BuildOptions::default()).expect("build");
    let mut inputs = RenderInputs::of_scene(&scene, accel.as_ref(), &camera);
    inputs.environment = Some(&env);
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        spp,
        seed: 7,
        threads: 2,
        max_depth: 32,
        sampling: PixelSampling::Sobol,
        integrator: Integrator::Path,
        russian_roulette: true,
        brdf,
        ..RenderSettings::default()
    };
    let (film, _) = render::render_film(&inputs, &settings, 0..spp, None).expect("render");
    let (image, _) = film.resolve();
    let (mut sum, mut count) = (0.0, 0usize);
    let mut rings = [(0.0, 0usize); RINGS];
    for y in 0..SIZE {
        for x in 0..SIZE {
            // The pixel centre's distance from the disc's centre, in sphere radii.
            let c = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) / SIZE as f32 * 2.0 - Vec2::ONE;
            let r = f64::from(c.length() * VIEW);
            if r >= RIM {
                continue;
            }
            let v = image.pixels[(y * SIZE + x) as usize].dot(Vec3::ONE) as f64 / 3.0;
            sum += v;
            count += 1;
            let ring = ((r / RIM) * RINGS as f64) as usize;
            rings[ring.min(RINGS - 1)].0 += v;
            rings[ring.min(RINGS - 1)].1 += 1;
        }
    }
    let rings = rings.iter().map(|&(s, n)| s / n.max(1) as f64).collect();
    (sum / count as f64, rings)
}

#[test]
fn white_spheres_reflect_the_furnace_exactly() {
    for &backend in BackendKind::available() {
        for metallic in [1.0, 0.0] {
            for roughness in [0.25, 0.5, 1.0] {
                let (mean, rings) = furnace(
                    white(metallic, roughness),
                    BrdfModel::Compensated,
                    backend,
                    64,
                );
                let what = format!("{backend}, metallic {metallic}, roughness {roughness}");
                eprintln!("{what}: mean {mean:.4}, rings {rings:.4?}");
                assert!((mean - 1.0).abs() <= 0.01, "{what}: sphere mean {mean}");
                for (i, r) in rings.iter().enumerate() {
                    assert!((r - 1.0).abs() <= 0.02, "{what}: ring {i} of {RINGS} = {r}");
                }
            }
        }
    }
}

/// Appendix B taken literally loses light on rough metal: the option really switches the
/// model (the same sphere renders at 1 with the default). The dielectric is printed too (the
/// spec's mix gains a little at grazing angles and loses to masking elsewhere).
#[test]
fn the_spec_brdf_loses_energy_on_rough_metal() {
    for &backend in BackendKind::available() {
        for metallic in [1.0, 0.0] {
            for roughness in [0.25, 0.5, 1.0] {
                let (mean, rings) =
                    furnace(white(metallic, roughness), BrdfModel::Spec, backend, 16);
                eprintln!(
                    "spec, {backend}, metallic {metallic}, roughness {roughness}: mean {mean:.4}, rings {rings:.4?}"
                );
                let bound = match (metallic, roughness) {
                    (1.0, 1.0) => 0.8,
                    (1.0, 0.5) => 0.97,
                    _ => continue,
                };
                assert!(
                    mean < bound,
                    "{backend}, roughness {roughness}: spec white metal {mean}, expected below {bound}"
                );
            }
        }
    }
}

/// The spheres touch each other and the slab: every point of the scene sees the others, and
/// near the contacts light bounces many times before it escapes. With an albedo of 1 at every
/// angle, radiance 1 everywhere still solves the rendering equation. Roughness 0.5 only:
/// at roughness 1 the estimator is unbiased but heavy-tailed here (Turquin's sample weights
/// are 0 for the half of the visible-normal draws that leave below the horizon and up to
/// 1/E0 ≈ 3.3 otherwise, and they multiply along the crevices' paths: single 8×8 blocks were
/// 4-50 % off at 256-2048 spp; see docs/bsdf.md).
#[test]
fn touching_metal_spheres_on_a_metal_slab_reflect_the_furnace_everywhere() {
    let size = 48u32;
    for &backend in BackendKind::available() {
        for roughness in [0.5] {
            let mut left = sphere(0);
            let mut right = sphere(0);
            left.positions
                .iter_mut()
                .for_each(|p| *p += Vec3::new(-1.0, 0.0, 1.0));
            right
                .positions
                .iter_mut()
                .for_each(|p| *p += Vec3::new(1.0, 0.0, 1.0));
            let slab = quad(Vec3::ZERO, Vec3::X * 4.0, Vec3::Y * 4.0, 0);
            let material = Material {
                double_sided: true,
                ..white(1.0, roughness)
            };
            let scene = scene(vec![left, right, slab], vec![material], vec![]);
            let camera = look_at(
                Vec3::new(0.0, -4.5, 3.0),
                Vec3::new(0.0, 0.0, 0.7),
                Vec3::Z,
                0.8,
            );
            let env = EnvironmentLight::constant(Vec3::ONE);
            let spp = 256;
            let accel = render::prepare(&scene, backend, BuildOptions::default()).expect("build");
            let mut inputs = RenderInputs::of_scene(&scene, accel.as_ref(), &camera);
            inputs.environment = Some(&env);
            let settings = RenderSettings {
                width: size,
                height: size,
                spp,
                seed: 11,
                threads: 2,
                max_depth: 32,
                sampling: PixelSampling::Sobol,
                integrator: Integrator::Path,
                russian_roulette: true,
                brdf: BrdfModel::Compensated,
                ..RenderSettings::default()
            };
            let (film, _) = render::render_film(&inputs, &settings, 0..spp, None).expect("render");
            let (image, _) = film.resolve();
            let mut worst = 0.0f64;
            for by in 0..size / 8 {
                for bx in 0..size / 8 {
                    let mut sum = 0.0;
                    for y in by * 8..by * 8 + 8 {
                        for x in bx * 8..bx * 8 + 8 {
                            let p = image.pixels[(y * size + x) as usize];
                            sum += f64::from(p.dot(Vec3::ONE)) / 3.0;
                        }
                    }
                    let block = sum / 64.0;
                    worst = worst.max((block - 1.0).abs());
                    assert!(
                        (block - 1.0).abs() <= 0.03,
                        "{backend}, roughness {roughness}: block ({bx}, {by}) = {block}"
                    );
                }
            }
            eprintln!("{backend}, roughness {roughness}: worst block |mean − 1| = {worst:.4}");
        }
    }
}
