//! MIS compensation of the environment (Karlík et al. 2019) changes no mean: on a diffuse and
//! a glossy plane under a synthetic map (bright lamps on a gradient), light sampling alone
//! (with the full distribution), BSDF sampling alone, MIS with the full distribution and MIS
//! with the compensated one agree within 4σ over independent seeds.

use crate::support::{look_at, quad, scene};
use glam::{Vec3, Vec4};
use glint::accel::{BackendKind, BuildOptions};
use glint::light::environment::{EnvImage, EnvOptions, EnvironmentLight};
use glint::render::{self, Integrator, LightStrategy, PixelSampling, RenderInputs, RenderSettings};
use glint::scene::{Camera, Material, Scene};

/// A 32 × 16 map: a smooth gradient with three small bright lamps, one saturated.
fn lamps_on_a_gradient() -> EnvironmentLight {
    let (w, h) = (32usize, 16usize);
    let texels = (0..w * h)
        .map(|k| {
            let (i, j) = (k % w, k / w);
            match (i, j) {
                (6, 3) => Vec3::splat(300.0),
                (22, 5) => Vec3::new(0.0, 0.0, 400.0),
                (14, 2) => Vec3::new(150.0, 120.0, 60.0),
                _ => Vec3::splat(0.3 + (i as f32 + 2.0 * j as f32) / 80.0),
            }
        })
        .collect();
    EnvironmentLight::from_image(
        EnvImage {
            width: w,
            height: h,
            texels,
        },
        &EnvOptions::default(),
    )
    .expect("map")
}

fn plane(roughness: f32, metallic: f32) -> Scene {
    let material = Material {
        name: "plane".into(),
        base_color: Vec4::new(0.7, 0.7, 0.7, 1.0),
        metallic,
        roughness,
        double_sided: false,
        ..Material::default()
    };
    scene(
        vec![quad(Vec3::ZERO, Vec3::X * 20.0, Vec3::NEG_Z * 20.0, 0)],
        vec![material],
        vec![],
    )
}

/// Per seed, the mean of the image's three channels; then their mean and standard error.
fn image_mean(
    scene: &Scene,
    camera: &Camera,
    env: &EnvironmentLight,
    strategy: LightStrategy,
    compensation: bool,
) -> (f64, f64) {
    let accel = render::prepare(scene, BackendKind::Bvh, BuildOptions::default()).expect("build");
    let mut inputs = RenderInputs::of_scene(scene, accel.as_ref(), camera);
    inputs.environment = Some(env);
    let seeds = 16;
    let runs: Vec<f64> = (0..seeds)
        .map(|seed| {
            let s = RenderSettings {
                width: 8,
                height: 8,
                spp: 256,
                seed: 100 + seed,
                threads: 2,
                max_depth: 1,
                sampling: PixelSampling::Independent,
                integrator: Integrator::Path,
                light_strategy: strategy,
                mis_compensation: compensation,
                ..RenderSettings::default()
            };
            let out = render::render_with(&inputs, &s, None).expect("render");
            let n = out.image.pixels.len() as f64;
            out.image
                .pixels
                .iter()
                .map(|p| f64::from(p.x + p.y + p.z) / 3.0)
                .sum::<f64>()
                / n
        })
        .collect();
    let k = seeds as f64;
    let mean = runs.iter().sum::<f64>() / k;
    let var = runs.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (k - 1.0);
    (mean, (var / k).sqrt())
}

#[test]
fn compensated_mis_agrees_with_light_and_bsdf_sampling() {
    let env = lamps_on_a_gradient();
    let camera = look_at(Vec3::new(0.0, 1.5, 2.0), Vec3::ZERO, Vec3::Y, 0.6);
    for (name, roughness, metallic) in [("diffuse", 1.0, 0.0), ("glossy", 0.3, 1.0)] {
        let scene = plane(roughness, metallic);
        let results = [
            (
                "light only",
                image_mean(&scene, &camera, &env, LightStrategy::LightOnly, true),
            ),
            (
                "BSDF only",
                image_mean(&scene, &camera, &env, LightStrategy::BsdfOnly, true),
            ),
            (
                "MIS",
                image_mean(&scene, &camera, &env, LightStrategy::Mis, false),
            ),
            (
                "compensated MIS",
                image_mean(&scene, &camera, &env, LightStrategy::Mis, true),
            ),
        ];
        let (reference, _) = results[3].1;
        for (a, (ma, sa)) in &results {
            // The bounds must be tight enough to see a bias of a few per cent (BSDF sampling
            // alone finds the small lamps rarely: 10 %).
            let tight = if *a == "BSDF only" { 0.1 } else { 0.03 };
            assert!(4.0 * sa < tight * reference, "{name} {a}: ± {sa} of {ma}");
            for (b, (mb, sb)) in &results {
                let sigma = (sa * sa + sb * sb).sqrt();
                assert!(
                    (ma - mb).abs() <= 4.0 * sigma,
                    "{name}: {a} {ma} ± {sa} vs {b} {mb} ± {sb}"
                );
            }
        }
    }
}
