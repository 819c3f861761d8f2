//! Sampling convergence on an analytic scene: a straight emitter edge across the image, whose
//! exact pixel values (box filter) are the covered fractions of the pixels. Plain Monte Carlo
//! must converge as spp^−½; Owen-scrambled Sobol must converge faster and beat it at equal
//! spp.

use crate::support::{emitter, ortho, quad};
use glam::{DVec2, Vec3};
use glint::accel::BackendKind;
use glint::converge::fit_log_slope;
use glint::render::{self, FilterSpec, PixelSampling, RenderSettings};
use glint::scene::Scene;

const WIDTH: u32 = 48;
const HEIGHT: u32 = 48;
/// A point on the edge and the edge's angle (radians from +x), in scene units = pixels.
const EDGE_POINT: DVec2 = DVec2::new(0.37, -0.21);
const EDGE_ANGLE: f64 = 0.3;

fn edge_normal() -> DVec2 {
    DVec2::new(-EDGE_ANGLE.sin(), EDGE_ANGLE.cos())
}

/// The emitter covers `{p : n·(p − EDGE_POINT) > 0}` (within 200 units).
fn scene() -> Scene {
    let d = Vec3::new(EDGE_ANGLE.cos() as f32, EDGE_ANGLE.sin() as f32, 0.0);
    let n = Vec3::new(edge_normal().x as f32, edge_normal().y as f32, 0.0);
    let p0 = Vec3::new(EDGE_POINT.x as f32, EDGE_POINT.y as f32, 0.0);
    Scene {
        // Front face along d × n = +Z, toward the camera.
        meshes: vec![quad(p0 + n * 100.0, d * 1000.0, n * 100.0, 0)],
        materials: vec![emitter(Vec3::ONE)],
        ..Scene::default()
    }
}

/// Area of the unit square at `min` on the emitter's side: clip the square by the half-plane
/// (Sutherland–Hodgman) and take the shoelace area.
fn covered_fraction(min: DVec2) -> f64 {
    let corners = [min, min + DVec2::X, min + DVec2::ONE, min + DVec2::Y];
    let side = |p: DVec2| edge_normal().dot(p - EDGE_POINT);
    let mut poly = Vec::new();
    for i in 0..4 {
        let (a, b) = (corners[i], corners[(i + 1) % 4]);
        let (sa, sb) = (side(a), side(b));
        if sa >= 0.0 {
            poly.push(a);
        }
        if (sa >= 0.0) != (sb >= 0.0) {
            poly.push(a + (b - a) * (sa / (sa - sb)));
        }
    }
    let mut area = 0.0;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        area += a.x * b.y - b.x * a.y;
    }
    area.abs() / 2.0
}

/// Exact pixel values: pixel (i, j) covers x ∈ [i − W/2, i + 1 − W/2],
/// y ∈ [H/2 − j − 1, H/2 − j] (film y points down, world y up).
fn exact() -> Vec<f64> {
    let mut v = Vec::new();
    for j in 0..HEIGHT {
        for i in 0..WIDTH {
            v.push(covered_fraction(DVec2::new(
                i as f64 - WIDTH as f64 / 2.0,
                HEIGHT as f64 / 2.0 - j as f64 - 1.0,
            )));
        }
    }
    v
}

/// RMSE over the pixels the edge crosses (the others are exactly 0 or 1 at any spp), averaged
/// over `seeds` seeds (in the MSE) to steady the slope fit.
fn edge_rmse(sampling: PixelSampling, spp: u32, seeds: u64) -> f64 {
    let scene = scene();
    let camera = ortho(
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::ZERO,
        Vec3::Y,
        WIDTH as f32 / 2.0,
        HEIGHT as f32 / 2.0,
    );
    let accel =
        render::prepare(&scene, BackendKind::Bvh, Default::default()).expect("build the edge");
    let exact = exact();
    let (mut se, mut n) = (0.0, 0usize);
    for seed in 0..seeds {
        let settings = RenderSettings {
            integrator: glint::render::Integrator::Direct,
            width: WIDTH,
            height: HEIGHT,
            spp,
            seed,
            sampling,
            filter: FilterSpec::default(),
            threads: 2,
            ..RenderSettings::default()
        };
        let out = render::render(&scene, accel.as_ref(), &camera, &settings, None).expect("render");
        for (p, &e) in out.image.pixels.iter().zip(&exact) {
            if e > 0.0 && e < 1.0 {
                se += (p.x as f64 - e).powi(2);
                n += 1;
            }
        }
    }
    assert!(n > 40, "the edge should cross many pixels, crossed {n}");
    (se / n as f64).sqrt()
}

fn slope(sampling: PixelSampling) -> (f64, Vec<f64>) {
    let counts = [1u32, 2, 4, 8, 16, 32, 64, 128];
    let rmse: Vec<f64> = counts.iter().map(|&n| edge_rmse(sampling, n, 4)).collect();
    let points: Vec<(f64, f64)> = counts.iter().map(|&n| n as f64).zip(rmse.clone()).collect();
    (fit_log_slope(&points).expect("slope"), rmse)
}

#[test]
fn independent_sampling_converges_at_the_monte_carlo_rate() {
    let (s, rmse) = slope(PixelSampling::Independent);
    assert!((s + 0.5).abs() < 0.1, "slope {s}, RMSE {rmse:?}");
}

#[test]
fn sobol_converges_faster_and_beats_independent_at_equal_spp() {
    let (sobol, sobol_rmse) = slope(PixelSampling::Sobol);
    // Owen-scrambled (0,2)-sequences reach spp^−¾ on integrands with a straight edge.
    assert!(sobol < -0.65, "Sobol slope {sobol}, RMSE {sobol_rmse:?}");
    let (_, independent_rmse) = slope(PixelSampling::Independent);
    for (i, (s, r)) in sobol_rmse.iter().zip(&independent_rmse).enumerate().skip(2) {
        assert!(s < r, "at 2^{i} spp Sobol {s} vs independent {r}");
    }
}

#[test]
fn the_exact_coverage_is_right() {
    // The closed form itself: coverage sums to the area on the emitter's side of the line
    // inside the image, checked against a fine grid count.
    let exact = exact();
    let covered: f64 = exact.iter().sum();
    let grid = 960;
    let mut count = 0usize;
    for j in 0..grid {
        for i in 0..grid {
            let p = DVec2::new(
                (i as f64 + 0.5) / grid as f64 * WIDTH as f64 - WIDTH as f64 / 2.0,
                (j as f64 + 0.5) / grid as f64 * HEIGHT as f64 - HEIGHT as f64 / 2.0,
            );
            if edge_normal().dot(p - EDGE_POINT) > 0.0 {
                count += 1;
            }
        }
    }
    let area = count as f64 / (grid * grid) as f64 * (WIDTH * HEIGHT) as f64;
    assert!((covered - area).abs() < 1.0, "{covered} vs {area}");
}
