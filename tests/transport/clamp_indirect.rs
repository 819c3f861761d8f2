//! `--clamp-indirect` (biased, off by default): direct light is never clamped, a limit above
//! every contribution changes no byte, and a low limit darkens only what arrives through two
//! or more bounces.

use crate::support::{emitter, lambert, look_at, quad, scene};
use glam::Vec3;
use glint::accel::BackendKind;
use glint::render::{self, Integrator, PixelSampling, RenderOutput, RenderSettings};
use glint::scene::{Camera, Light, Scene};

/// A grey floor under a point light and a bright emitting panel beside it: direct light from
/// both, indirect light bouncing between the floor and a grey wall.
fn room() -> (Scene, Camera) {
    let floor = quad(Vec3::ZERO, Vec3::X * 2.0, Vec3::NEG_Z * 2.0, 0);
    let wall = quad(Vec3::new(0.0, 1.0, -1.0), Vec3::X * 2.0, Vec3::Y, 0);
    let panel = quad(Vec3::new(0.0, 1.5, 0.0), Vec3::X * 0.2, Vec3::Z * 0.2, 1);
    let light = Light::Point {
        position: Vec3::new(0.5, 2.0, 1.0),
        intensity: Vec3::splat(3.0),
        range: None,
    };
    let s = scene(
        vec![floor, wall, panel],
        vec![lambert(Vec3::splat(0.7), false), emitter(Vec3::splat(40.0))],
        vec![light],
    );
    let camera = look_at(
        Vec3::new(0.0, 1.2, 3.0),
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::Y,
        0.9,
    );
    (s, camera)
}

fn render(max_depth: u32, clamp: Option<f32>) -> RenderOutput {
    let (scene, camera) = room();
    let settings = RenderSettings {
        width: 24,
        height: 16,
        spp: 16,
        threads: 2,
        max_depth,
        sampling: PixelSampling::Sobol,
        integrator: Integrator::Path,
        clamp_indirect: clamp,
        ..RenderSettings::default()
    };
    let accel = render::prepare(&scene, BackendKind::Bvh, Default::default()).expect("build");
    render::render(&scene, accel.as_ref(), &camera, &settings, None).expect("render")
}

fn bits(o: &RenderOutput) -> Vec<[u32; 3]> {
    o.image
        .pixels
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect()
}

fn mean(o: &RenderOutput) -> f64 {
    o.image.pixels.iter().map(|p| f64::from(p.x)).sum::<f64>() / o.image.pixels.len() as f64
}

#[test]
fn direct_light_is_never_clamped() {
    // max_depth 1: direct light only; even a tiny limit changes nothing.
    assert_eq!(bits(&render(1, None)), bits(&render(1, Some(1e-6))));
}

#[test]
fn a_limit_above_every_contribution_changes_nothing() {
    assert_eq!(bits(&render(8, None)), bits(&render(8, Some(1e30))));
}

#[test]
fn a_low_limit_darkens_the_indirect_light_only() {
    let (free, clamped) = (render(8, None), render(8, Some(0.01)));
    let direct = render(1, None);
    let (f, c, d) = (mean(&free), mean(&clamped), mean(&direct));
    // Indirect light exists here, and the clamp removes most of it but never the direct part.
    assert!(f > d * 1.05, "indirect {f} vs direct {d}");
    assert!(c < f && c >= d * 0.999, "clamped {c}, free {f}, direct {d}");
    for (p, q) in clamped.image.pixels.iter().zip(&free.image.pixels) {
        assert!(p.x <= q.x + 1e-5, "a clamped pixel is brighter: {p} vs {q}");
    }
}
