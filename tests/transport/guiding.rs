//! Path guiding (`--guiding`): the guide's directional density integrates to 1 and is the
//! density of its samples (χ² at p < 1e-4); a guide trained on records pointing at a light
//! points there; guided renders agree with closed forms and with unguided renders within
//! their standard errors; guiding lowers the noise where only BSDF sampling finds the light;
//! and the image is the same for any thread count.

use crate::support;

use crate::support::chi_square;
use crate::support::{image_bits, ortho, quad, scene};
use glam::{Vec2, Vec3, Vec4};
use glint::accel::{BackendKind, BuildOptions};
use glint::guiding::directional::{BINS, from_map};
use glint::guiding::{Directional, Record, Trainer};
use glint::render::{self, Integrator, LightStrategy, PixelSampling, RenderInputs, RenderSettings};
use glint::scene::{Camera, Material, Scene};
use std::f64::consts::PI;

/// The χ² quantile at 1 − 1e-4 (Wilson–Hilferty).
fn chi_square_threshold_1e4(dof: usize) -> f64 {
    let k = dof.max(1) as f64;
    let z = 3.719_016; // standard normal quantile at 1 − 1e-4
    k * (1.0 - 2.0 / (9.0 * k) + z * (2.0 / (9.0 * k)).sqrt()).powi(3)
}

/// A small deterministic generator for the tests' uniforms.
struct Lcg(u64);
impl Lcg {
    fn unit(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((self.0 >> 40) as f32 / (1u64 << 24) as f32).min(1.0 - f32::EPSILON)
    }
}

/// A histogram with a smooth ramp, two bright bins and a run of empty ones.
fn peaked_weights() -> Vec<f32> {
    (0..BINS)
        .map(|k| match k {
            700 => 400.0,
            1500 => 90.0,
            100..=300 => 0.0,
            _ => 0.2 + (k % 64) as f32 / 64.0,
        })
        .collect()
}

/// The direction at polar angle θ (from +Z) and azimuth φ.
fn direction(theta: f64, phi: f64) -> Vec3 {
    Vec3::new(
        (theta.sin() * phi.cos()) as f32,
        (theta.sin() * phi.sin()) as f32,
        theta.cos() as f32,
    )
}

/// The guide's density integrated over cell `(i, j)` of an `nz × np` grid in (cos θ, φ)
/// (whose Jacobian is 1; the grid is not aligned with the histogram's), by the midpoint rule
/// on `sub × sub` subcells.
fn cell_probability(d: &Directional, (i, j): (usize, usize), (nz, np): (usize, usize)) -> f64 {
    let sub = 32;
    let (dz, dp) = (2.0 / nz as f64, 2.0 * PI / np as f64);
    let mut sum = 0.0;
    for a in 0..sub {
        for b in 0..sub {
            let z = -1.0 + (i as f64 + (a as f64 + 0.5) / sub as f64) * dz;
            let phi = (j as f64 + (b as f64 + 0.5) / sub as f64) * dp;
            sum += d.pdf(direction(z.acos(), phi)) as f64;
        }
    }
    sum * dz * dp / (sub * sub) as f64
}

/// The cell of the (cos θ, φ) grid holding direction `w`.
fn cell_of(w: Vec3, (nz, np): (usize, usize)) -> usize {
    let z = (w.z as f64).clamp(-1.0, 1.0);
    let phi = (w.y as f64).atan2(w.x as f64).rem_euclid(2.0 * PI);
    let i = (((z + 1.0) / 2.0 * nz as f64) as usize).min(nz - 1);
    let j = ((phi / (2.0 * PI) * np as f64) as usize).min(np - 1);
    i * np + j
}

#[test]
fn guide_density_integrates_to_one_and_matches_its_samples() {
    let d = Directional::from_weights(&peaked_weights()).expect("distribution");
    let (nt, np) = (18, 36);
    let expected: Vec<f64> = (0..nt * np)
        .map(|k| cell_probability(&d, (k / np, k % np), (nt, np)))
        .collect();
    let total: f64 = expected.iter().sum();
    assert!((total - 1.0).abs() < 2e-3, "∫ p dω = {total}");
    let n = 400_000u64;
    let mut counts = vec![0u64; nt * np];
    let mut rng = Lcg(7);
    for _ in 0..n {
        let (w, pdf) = d.sample(Vec2::new(rng.unit(), rng.unit()));
        assert!(pdf > 0.0 && (w.length() - 1.0).abs() < 1e-4);
        assert!(
            (d.pdf(w) - pdf).abs() <= 1e-3 * pdf,
            "{} vs {pdf}",
            d.pdf(w)
        );
        counts[cell_of(w, (nt, np))] += 1;
    }
    let expected: Vec<f64> = expected.iter().map(|p| p / total * n as f64).collect();
    let (chi, dof) = chi_square(&counts, &expected);
    assert!(chi < chi_square_threshold_1e4(dof), "χ² {chi}, {dof} dof");
}

#[test]
fn a_wrong_density_fails_the_same_chi_square() {
    // The test above can fail: samples from one histogram against another's density.
    let d = Directional::from_weights(&peaked_weights()).expect("distribution");
    let mut other = peaked_weights();
    other[700] = 100.0;
    let wrong = Directional::from_weights(&other).expect("distribution");
    let (nt, np) = (18, 36);
    let expected: Vec<f64> = (0..nt * np)
        .map(|k| cell_probability(&wrong, (k / np, k % np), (nt, np)) * 100_000.0)
        .collect();
    let mut counts = vec![0u64; nt * np];
    let mut rng = Lcg(9);
    for _ in 0..100_000 {
        let (w, _) = d.sample(Vec2::new(rng.unit(), rng.unit()));
        counts[cell_of(w, (nt, np))] += 1;
    }
    let (chi, dof) = chi_square(&counts, &expected);
    assert!(chi > chi_square_threshold_1e4(dof), "χ² {chi}, {dof} dof");
}

#[test]
fn a_guide_trained_on_light_from_one_point_points_at_it() {
    // Records in a unit box: most carry nothing from uniform directions, one in four carries
    // radiance from a lamp at (5, 5, 5). The trained guide's density toward the lamp is far
    // above uniform everywhere in the box, and the tree has split.
    let lamp = Vec3::splat(5.0);
    let mut rng = Lcg(3);
    let mut records = Vec::new();
    for k in 0..60_000 {
        let position = Vec3::new(rng.unit(), rng.unit(), rng.unit());
        let (direction, weight) = if k % 4 == 0 {
            ((lamp - position).normalize(), 10.0)
        } else {
            (from_map(Vec2::new(rng.unit(), rng.unit())), 0.0)
        };
        records.push(Record {
            position,
            direction,
            weight,
        });
    }
    let mut trainer = Trainer::new(Vec3::ZERO, Vec3::ONE);
    let guide = trainer.learn(records.iter());
    let (leaves, guiding) = guide.leaves();
    assert!(
        leaves > 4 && guiding == leaves,
        "{leaves} leaves, {guiding} guide"
    );
    for p in [Vec3::splat(0.1), Vec3::splat(0.5), Vec3::new(0.9, 0.2, 0.6)] {
        let d = guide.at(p).expect("a guiding leaf");
        let toward = d.pdf((lamp - p).normalize());
        let away = d.pdf(-(lamp - p).normalize());
        assert!(
            toward > 100.0 / (4.0 * std::f32::consts::PI),
            "{p}: {toward}"
        );
        assert_eq!(away, 0.0);
    }
}

/// A Lambertian (or rough metallic, `metallic` 1) floor material of albedo ρ.
fn floor(rho: f32, metallic: f32, roughness: f32) -> Material {
    Material {
        specular: 0.0,
        name: "floor".into(),
        base_color: Vec4::new(rho, rho, rho, 1.0),
        metallic,
        roughness,
        double_sided: true,
        ..Material::default()
    }
}

/// A floor under a square emitter of radiance `le`, half-side `s`, at height 1, facing down.
fn floor_under_a_lamp(material: Material, le: f32, s: f32) -> Scene {
    scene(
        vec![
            quad(Vec3::ZERO, Vec3::X * 20.0, -Vec3::Z * 20.0, 0),
            quad(Vec3::Y, Vec3::X * s, Vec3::Z * s, 1),
        ],
        vec![
            material,
            Material {
                name: "lamp".into(),
                base_color: Vec4::new(0.0, 0.0, 0.0, 1.0),
                specular: 0.0,
                emissive: Vec3::splat(le),
                double_sided: false,
                ..Material::default()
            },
        ],
        vec![],
    )
}

/// The floor around the origin, seen at a glancing angle from beside the lamp.
fn floor_camera() -> Camera {
    ortho(Vec3::new(3.0, 0.5, 0.0), Vec3::ZERO, Vec3::Y, 1e-3, 1e-3)
}

fn settings(spp: u32, guiding: bool, strategy: LightStrategy) -> RenderSettings {
    RenderSettings {
        width: 8,
        height: 8,
        spp,
        threads: 2,
        max_depth: 4,
        sampling: PixelSampling::Sobol,
        integrator: Integrator::Path,
        light_strategy: strategy,
        guiding,
        ..RenderSettings::default()
    }
}

/// Per seed, the image's mean first channel; their mean, standard error, and the mean over
/// seeds of the per-pixel variance across seeds (the noise of one render).
fn estimate(scene: &Scene, camera: &Camera, base: &RenderSettings, seeds: u64) -> (f64, f64, f64) {
    let accel = render::prepare(scene, BackendKind::default(), BuildOptions::default()).unwrap();
    let inputs = RenderInputs::of_scene(scene, accel.as_ref(), camera);
    let images: Vec<Vec<f64>> = (0..seeds)
        .map(|seed| {
            let s = RenderSettings {
                seed: 500 + seed,
                ..*base
            };
            let out = render::render_with(&inputs, &s, None).expect("render");
            out.image.pixels.iter().map(|p| p.x as f64).collect()
        })
        .collect();
    let means: Vec<f64> = images
        .iter()
        .map(|im| im.iter().sum::<f64>() / im.len() as f64)
        .collect();
    let (mean, error) = support::mean_and_error(&means);
    let k = seeds as f64;
    let pixels = images[0].len();
    let noise = (0..pixels)
        .map(|i| {
            let m = images.iter().map(|im| im[i]).sum::<f64>() / k;
            images.iter().map(|im| (im[i] - m).powi(2)).sum::<f64>() / (k - 1.0)
        })
        .sum::<f64>()
        / pixels as f64;
    (mean, error, noise)
}

/// Form factor from a differential area to a parallel rectangle of sides a × b at distance
/// h, the area's normal through one corner of the rectangle.
fn corner_form_factor(a: f64, b: f64, h: f64) -> f64 {
    let (x, y) = (a / h, b / h);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * PI)
}

#[test]
fn guided_renders_match_the_form_factor_and_unguided_renders() {
    // Lambertian floor under a square lamp: radiance ρ Le F at the origin (the view is 0.05
    // wide, so F varies by well under the tolerance across it). BSDF sampling alone (the
    // strategy guiding changes most) and MIS, guided against the closed form; a rough metal
    // floor (no closed form), guided against unguided.
    let (rho, le, s) = (0.5f32, 3.0f32, 0.3f32);
    let camera = floor_camera();
    let f = 4.0 * corner_form_factor(s as f64, s as f64, 1.0);
    let want = rho as f64 * le as f64 * f;
    for strategy in [LightStrategy::BsdfOnly, LightStrategy::Mis] {
        let scene = floor_under_a_lamp(floor(rho, 0.0, 1.0), le, s);
        let st = RenderSettings {
            max_depth: 1,
            ..settings(256, true, strategy)
        };
        let (mean, error, _) = estimate(&scene, &camera, &st, 16);
        assert!(
            (mean - want).abs() <= 4.0 * error + 2e-3 * want,
            "{strategy:?}: {mean} ± {error}, want {want}"
        );
        assert!(
            4.0 * error < 0.02 * want,
            "{strategy:?}: bound {error} too loose"
        );
    }
    let scene = floor_under_a_lamp(floor(0.8, 1.0, 0.6), le, s);
    for strategy in [LightStrategy::BsdfOnly, LightStrategy::Mis] {
        let (guided, eg, _) = estimate(&scene, &camera, &settings(256, true, strategy), 16);
        let (plain, ep, _) = estimate(&scene, &camera, &settings(256, false, strategy), 16);
        let sigma = (eg * eg + ep * ep).sqrt();
        assert!(
            (guided - plain).abs() <= 4.0 * sigma,
            "{strategy:?}: guided {guided} ± {eg}, unguided {plain} ± {ep}"
        );
        assert!(
            4.0 * sigma < 0.05 * plain,
            "{strategy:?}: bound {sigma} too loose"
        );
    }
}

#[test]
fn guiding_lowers_the_noise_where_only_bsdf_sampling_finds_the_light() {
    // A small lamp (half-side 0.1 at height 1) found by BSDF sampling alone: a cosine-weighted
    // direction hits it about once in 80; the guide learns where it is. Noise: the per-pixel
    // variance over seeds.
    let scene = floor_under_a_lamp(floor(0.5, 0.0, 1.0), 50.0, 0.1);
    let camera = floor_camera();
    let st = |guiding| RenderSettings {
        max_depth: 1,
        ..settings(512, guiding, LightStrategy::BsdfOnly)
    };
    let (_, _, guided) = estimate(&scene, &camera, &st(true), 8);
    let (_, _, plain) = estimate(&scene, &camera, &st(false), 8);
    // Measured: 2.7× lower (a quarter of the samples train, the first ones unguided).
    assert!(
        guided * 2.0 < plain,
        "variance guided {guided}, unguided {plain}"
    );
}

#[test]
fn guided_images_do_not_depend_on_the_thread_count() {
    let scene = floor_under_a_lamp(floor(0.6, 0.5, 0.5), 5.0, 0.3);
    let camera = ortho(Vec3::new(3.0, 0.5, 0.4), Vec3::ZERO, Vec3::Y, 2.0, 2.0);
    let accel = render::prepare(&scene, BackendKind::default(), BuildOptions::default()).unwrap();
    let render = |threads, adaptive, guiding| {
        let s = RenderSettings {
            threads,
            width: 40,
            height: 24,
            seed: 3,
            adaptive,
            ..settings(32, guiding, LightStrategy::Mis)
        };
        image_bits(&render::render(&scene, accel.as_ref(), &camera, &s, None).unwrap())
    };
    assert_eq!(render(1, None, true), render(2, None, true));
    assert_eq!(render(1, Some(0.05), true), render(3, Some(0.05), true));
    // And guiding changed the image (the guide was used).
    assert_ne!(render(2, None, false), render(2, None, true));
}

#[test]
fn guiding_is_refused_for_the_direct_integrator_and_partial_renders() {
    let scene = floor_under_a_lamp(floor(0.5, 0.0, 1.0), 1.0, 0.3);
    let camera = floor_camera();
    let accel = render::prepare(&scene, BackendKind::default(), BuildOptions::default()).unwrap();
    let inputs = RenderInputs::of_scene(&scene, accel.as_ref(), &camera);
    let direct = RenderSettings {
        integrator: Integrator::Direct,
        ..settings(4, true, LightStrategy::Mis)
    };
    let err = render::render_with(&inputs, &direct, None).unwrap_err();
    assert!(err.to_string().contains("--integrator path"), "{err}");
    let err = render::render_film(&inputs, &settings(4, true, LightStrategy::Mis), 0..2, None)
        .unwrap_err();
    assert!(err.to_string().contains("partial"), "{err}");
}

#[test]
fn progressive_guided_renders_train_and_do_not_depend_on_the_thread_count() {
    // A progressive render relearns the guide after 2, 4, 8 and 16 spp whatever its passes;
    // the image is the same bytes for 1 and 2 threads, and it is not the unguided one.
    let scene = floor_under_a_lamp(floor(0.6, 0.5, 0.5), 5.0, 0.3);
    let camera = ortho(Vec3::new(3.0, 0.5, 0.4), Vec3::ZERO, Vec3::Y, 2.0, 2.0);
    let accel = render::prepare(&scene, BackendKind::default(), BuildOptions::default()).unwrap();
    let inputs = RenderInputs::of_scene(&scene, accel.as_ref(), &camera);
    let rule = render::StopRule {
        target_error: Some(1e-4),
        max_spp: 40,
        ..render::StopRule::default()
    };
    let run = |threads, guiding| {
        let s = RenderSettings {
            threads,
            width: 32,
            height: 16,
            seed: 5,
            ..settings(40, guiding, LightStrategy::Mis)
        };
        let out =
            render::progressive::render_progressive_with(&inputs, &s, &rule, None).expect("render");
        assert_eq!(out.spp, 40);
        image_bits(&out.output)
    };
    let guided = run(1, true);
    assert_eq!(guided, run(2, true));
    assert_ne!(guided, run(2, false));
}
