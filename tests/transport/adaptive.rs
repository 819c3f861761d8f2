//! Adaptive sampling (`render::adaptive`): it changes no mean (4σ over seeds, on a scene whose
//! rare bright paths make a plain "stop when converged" rule stop dark), it beats uniform
//! sampling at equal total samples on a scene with a converged background and a noisy object,
//! and the same seed gives the same image on 1 and 2 threads.

use crate::support::mean_and_error;
use crate::support::{emitter, image_bits, lambert, look_at, quad, scene};
use glam::Vec3;
use glint::accel::BackendKind;
use glint::render::{self, Integrator, LightStrategy, PixelSampling, RenderOutput, RenderSettings};
use glint::scene::{Camera, Light, Scene};

/// A grey floor lit by a point light (noise-free: its pixels converge at once) and, over its
/// middle, a grey card with a small bright lamp just above it that only BSDF sampling finds
/// (rare bright hits: noise). The card hides the lamp from every point of the floor.
fn floor_and_lamp() -> (Scene, Camera) {
    let floor = quad(Vec3::ZERO, Vec3::X * 1.2, Vec3::NEG_Z * 1.2, 0);
    let card = quad(
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::X * 0.3,
        Vec3::NEG_Z * 0.3,
        0,
    );
    // Faces down (X × Z = −Y), at 0.08 above the card.
    let lamp = quad(Vec3::new(0.0, 0.58, 0.0), Vec3::X * 0.03, Vec3::Z * 0.03, 1);
    let light = Light::Point {
        position: Vec3::new(0.0, 3.0, 1.0),
        intensity: Vec3::splat(4.0),
        range: None,
    };
    let s = scene(
        vec![floor, card, lamp],
        vec![lambert(Vec3::splat(0.5), false), emitter(Vec3::splat(50.0))],
        vec![light],
    );
    let camera = look_at(Vec3::new(0.0, 2.5, 0.001), Vec3::ZERO, Vec3::NEG_Z, 1.2);
    (s, camera)
}

fn settings(spp: u32, seed: u64, adaptive: Option<f32>) -> RenderSettings {
    RenderSettings {
        width: 24,
        height: 24,
        spp,
        seed,
        threads: 2,
        sampling: PixelSampling::Independent,
        integrator: Integrator::Path,
        light_strategy: LightStrategy::BsdfOnly,
        max_depth: 2,
        adaptive,
        ..RenderSettings::default()
    }
}

fn render(scene: &Scene, camera: &Camera, s: &RenderSettings) -> RenderOutput {
    let accel = render::prepare(scene, BackendKind::Bvh, Default::default()).expect("build");
    render::render(scene, accel.as_ref(), camera, s, None).expect("render")
}

fn image_mean(out: &RenderOutput) -> f64 {
    let n = out.image.pixels.len() as f64;
    out.image.pixels.iter().map(|p| p.x as f64).sum::<f64>() / n
}

fn total_samples(out: &RenderOutput) -> u64 {
    let counts = out
        .aovs
        .samples
        .as_ref()
        .expect("sample counts with adaptive sampling");
    counts.pixels.iter().map(|&n| n as u64).sum()
}

/// Unbiased: the image mean over many seeds is the uniform render's within 4σ, although most
/// pixels stop early and many of the stopped ones have not yet seen the lamp.
#[test]
fn adaptive_sampling_changes_no_mean() {
    let (scene, camera) = floor_and_lamp();
    let seeds = 24;
    let (mut uniform, mut adaptive) = (Vec::new(), Vec::new());
    let mut saved = 0.0;
    for seed in 0..seeds {
        uniform.push(image_mean(&render(
            &scene,
            &camera,
            &settings(32, seed, None),
        )));
        let out = render(&scene, &camera, &settings(32, 1000 + seed, Some(0.5)));
        saved += 1.0 - total_samples(&out) as f64 / (32.0 * 24.0 * 24.0);
        adaptive.push(image_mean(&out));
    }
    let (mu, su) = mean_and_error(&uniform);
    let (ma, sa) = mean_and_error(&adaptive);
    let sigma = (su * su + sa * sa).sqrt();
    assert!(
        (mu - ma).abs() < 4.0 * sigma,
        "uniform {mu} ± {su}, adaptive {ma} ± {sa}"
    );
    // The test means something only if adaptive sampling stopped pixels.
    assert!(saved / seeds as f64 > 0.2, "saved {saved}");
}

/// At equal total samples adaptive sampling has the lower error against a converged
/// reference: the floor's pixels stop and their samples go to the noisy ones.
#[test]
fn adaptive_sampling_beats_uniform_at_equal_samples() {
    let (scene, camera) = floor_and_lamp();
    let reference = render(&scene, &camera, &settings(2048, 99, None));
    let mse = |out: &RenderOutput| {
        let n = out.image.pixels.len() as f64;
        out.image
            .pixels
            .iter()
            .zip(&reference.image.pixels)
            .map(|(a, b)| ((a.x - b.x) as f64).powi(2))
            .sum::<f64>()
            / n
    };
    let (mut e_adaptive, mut e_uniform) = (0.0, 0.0);
    for seed in 0..6 {
        let a = render(&scene, &camera, &settings(128, seed, Some(0.05)));
        let pixels = a.image.pixels.len() as u64;
        // Uniform sampling with at least as many samples in total.
        let spp = total_samples(&a).div_ceil(pixels) as u32;
        assert!(spp < 128, "adaptive sampling stopped nothing ({spp} spp)");
        let u = render(&scene, &camera, &settings(spp, 500 + seed, None));
        e_adaptive += mse(&a);
        e_uniform += mse(&u);
    }
    assert!(
        e_adaptive < e_uniform,
        "MSE adaptive {e_adaptive} vs uniform {e_uniform} at equal samples"
    );
}

/// Decisions are made on the calling thread from the whole film: 1 and 2 threads give the
/// same bytes, sample counts included.
#[test]
fn adaptive_sampling_is_the_same_on_one_and_two_threads() {
    let (scene, camera) = floor_and_lamp();
    let mut s = settings(32, 7, Some(0.3));
    s.sampling = PixelSampling::Sobol;
    let two = render(&scene, &camera, &s);
    s.threads = 1;
    let one = render(&scene, &camera, &s);
    assert_eq!(image_bits(&one), image_bits(&two));
    assert_eq!(one.aovs.samples, two.aovs.samples);
    assert!(total_samples(&one) < 32 * 24 * 24, "nothing stopped");
}

/// Bad thresholds are refused before any work.
#[test]
fn bad_thresholds_are_refused() {
    let (scene, camera) = floor_and_lamp();
    let accel = render::prepare(&scene, BackendKind::Bvh, Default::default()).expect("build");
    for t in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        let s = settings(8, 0, Some(t));
        assert!(
            render::render(&scene, accel.as_ref(), &camera, &s, None).is_err(),
            "{t}"
        );
    }
}
