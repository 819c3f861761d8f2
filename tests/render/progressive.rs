//! Progressive rendering: the time budget stops within its stated overshoot, the target error
//! is reached on the demo scene (and the estimate is honest against a reference), and bad
//! requests are refused.

use glint::accel::BackendKind;
use glint::render::{
    self, PixelSampling, RenderSettings, StopReason, StopRule, film::RELATIVE_ERROR_FLOOR,
    film::luminance,
};
use glint::scene::{self, Camera, Scene};
use std::time::Duration;

fn demo() -> (Scene, Camera) {
    let mut scene = scene::demo::demo_scene().expect("demo scene");
    scene::defaults::complete(&mut scene);
    let camera = scene.cameras[0].clone();
    (scene, camera)
}

fn settings() -> RenderSettings {
    RenderSettings {
        integrator: glint::render::Integrator::Direct,
        width: 96,
        height: 54,
        threads: 2,
        sampling: PixelSampling::Sobol,
        ..RenderSettings::default()
    }
}

/// Stated in the module docs: a budgeted render ends within 25% of its budget plus the time of
/// its first (2-sample) pass, whatever else the machine does.
#[test]
fn time_budget_stops_within_the_stated_overshoot() {
    let (scene, camera) = demo();
    let accel = render::prepare(&scene, BackendKind::Bvh, Default::default()).expect("build");
    let budget = Duration::from_millis(800);
    let rule = StopRule {
        time_budget: Some(budget),
        ..StopRule::default()
    };
    let out = render::render_progressive(&scene, accel.as_ref(), &camera, &settings(), &rule, None)
        .expect("render");
    let elapsed = out.output.stats.elapsed.as_secs_f64();
    let first_pass = elapsed / out.spp as f64 * 2.0;
    assert_eq!(out.reason, StopReason::TimeBudget, "{out:?}");
    assert!(
        elapsed <= budget.as_secs_f64() * 1.25 + first_pass,
        "{elapsed} s for a {budget:?} budget"
    );
    // And it used the budget rather than stopping early.
    assert!(
        elapsed >= budget.as_secs_f64() * 0.5,
        "{elapsed} s for a {budget:?} budget"
    );
    assert!(out.passes >= 2);
}

#[test]
fn target_error_is_reached_on_the_demo_scene_and_is_honest() {
    let (scene, camera) = demo();
    let accel = render::prepare(&scene, BackendKind::Bvh, Default::default()).expect("build");
    let target = 0.03;
    let rule = StopRule {
        target_error: Some(target),
        ..StopRule::default()
    };
    let out = render::render_progressive(&scene, accel.as_ref(), &camera, &settings(), &rule, None)
        .expect("render");
    assert_eq!(out.reason, StopReason::TargetError, "{out:?}");
    assert!(out.relative_error <= target);
    assert!(
        out.spp > 2,
        "a 2-sample render should not already be at {target}"
    );

    // The true error, same metric, against a 2048-spp reference from another seed.
    let reference = render::render(
        &scene,
        accel.as_ref(),
        &camera,
        &RenderSettings {
            spp: 2048,
            seed: 99,
            ..settings()
        },
        None,
    )
    .expect("reference");
    let n = reference.image.pixels.len() as f64;
    let mean = reference
        .image
        .pixels
        .iter()
        .map(|&p| luminance(p) as f64)
        .sum::<f64>()
        / n;
    let floor = RELATIVE_ERROR_FLOOR as f64 * mean;
    let true_error = (out
        .output
        .image
        .pixels
        .iter()
        .zip(&reference.image.pixels)
        .map(|(&x, &r)| {
            let (x, r) = (luminance(x) as f64, luminance(r) as f64);
            (x - r).powi(2) / (r * r + floor * floor)
        })
        .sum::<f64>()
        / n)
        .sqrt();
    assert!(
        true_error <= 1.5 * target,
        "true error {true_error} vs target {target}"
    );
}

#[test]
fn bad_requests_are_refused() {
    let (scene, camera) = demo();
    let accel = render::prepare(&scene, BackendKind::Bvh, Default::default()).expect("build");
    let run = |settings: &RenderSettings, rule: &StopRule| {
        render::render_progressive(&scene, accel.as_ref(), &camera, settings, rule, None)
    };
    let budget = StopRule {
        time_budget: Some(Duration::from_millis(10)),
        ..StopRule::default()
    };
    let stratified = RenderSettings {
        sampling: PixelSampling::Stratified,
        ..settings()
    };
    let err = run(&stratified, &budget).expect_err("stratified is not progressive");
    assert!(err.to_string().contains("sobol"), "{err}");
    let err = run(&settings(), &StopRule::default()).expect_err("no stop rule");
    assert!(err.to_string().contains("time budget"), "{err}");
    let negative = StopRule {
        target_error: Some(-1.0),
        ..StopRule::default()
    };
    assert!(run(&settings(), &negative).is_err());
}

#[test]
fn the_sample_cap_stops_a_render() {
    let (scene, camera) = demo();
    let accel = render::prepare(&scene, BackendKind::Bvh, Default::default()).expect("build");
    let rule = StopRule {
        target_error: Some(1e-9),
        max_spp: 12,
        ..StopRule::default()
    };
    let out = render::render_progressive(&scene, accel.as_ref(), &camera, &settings(), &rule, None)
        .expect("render");
    assert_eq!((out.reason, out.spp), (StopReason::MaxSpp, 12));
}
