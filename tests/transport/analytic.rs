//! Closed-form radiometry: every checked pixel (1 spp at its centre) must equal the analytic
//! radiance at the exact hit point of its camera ray, to relative error 1e-4, on every backend.

use crate::support::*;
use glam::{DVec3, Vec3};
use glint::accel::BackendKind;
use glint::light::{LUMENS_PER_WATT, LightUnits};
use glint::render::RenderOutput;
use glint::scene::{Camera, Light};
use std::f64::consts::PI;

const TOL: f64 = 1e-4;
/// Pixels whose exact hit lies within this fraction of the quad's half-extent from an edge are
/// not checked (the f32 and f64 answers may legitimately disagree on hit or miss).
const EDGE: f64 = 1e-3;
const RHO: Vec3 = Vec3::new(0.8, 0.5, 0.2);

/// A closed form held to the base tolerance alone.
fn plain(value: DVec3) -> Option<(DVec3, f64)> {
    Some((value, 0.0))
}

/// Compares every pixel against `expected(p)` at the exact hit point (or 0 where the ray
/// misses the quad) to relative error `tol`, or to `tol` plus the extra tolerance a closed
/// form returns (for ill-conditioned formulas); returns how many pixels saw the quad.
fn check(
    out: &RenderOutput,
    camera: &Camera,
    quad: ExactQuad,
    label: &str,
    tol: f64,
    mut expected: impl FnMut(DVec3) -> Option<(DVec3, f64)>,
) -> usize {
    let (w, h) = (out.image.width, out.image.height);
    let mut seen = 0;
    for y in 0..h {
        for x in 0..w {
            let ray = centre_ray(camera, w, h, x, y);
            if quad.near_edge(&ray, EDGE) {
                continue;
            }
            let got = out.image.get(x, y).unwrap();
            let (want, extra) = match quad.hit(&ray, EDGE) {
                Some((_, p)) => {
                    seen += 1;
                    match expected(p) {
                        Some(want) => want,
                        None => continue,
                    }
                }
                None => (DVec3::ZERO, 0.0),
            };
            assert!(
                close(got, want, tol + extra),
                "{label}: pixel ({x}, {y}) = {got}, closed form {want}"
            );
        }
    }
    seen
}

fn plane_quad(half: f32) -> (ExactQuad, glint::scene::Mesh) {
    let (u, v) = (Vec3::new(half, 0.0, 0.0), Vec3::new(0.0, 0.0, -half));
    (ExactQuad::new(Vec3::ZERO, u, v), quad(Vec3::ZERO, u, v, 0))
}

fn point_scene(units: LightUnits) -> (glint::scene::Scene, ExactQuad, Camera, f64) {
    let (exact, mesh) = plane_quad(2.0);
    let light = Light::Point {
        position: Vec3::new(0.5, 1.5, -0.3),
        intensity: Vec3::new(10.0, 20.0, 5.0),
        range: None,
    };
    let scene = scene(vec![mesh], vec![lambert(RHO, false)], vec![light]);
    let camera = look_at(Vec3::new(1.0, 3.0, 4.0), Vec3::ZERO, Vec3::Y, 0.9);
    let scale = match units {
        LightUnits::Radiometric => 1.0,
        LightUnits::Photometric => 1.0 / LUMENS_PER_WATT as f64,
    };
    (scene, exact, camera, scale)
}

#[test]
fn lambertian_plane_under_a_point_light() {
    for &backend in BackendKind::available() {
        let (scene, quad, camera, _) = point_scene(LightUnits::Radiometric);
        let out = render_with(&scene, &camera, backend, &centre_settings(64, 48));
        let light = DVec3::new(0.5, 1.5, -0.3);
        let seen = check(&out, &camera, quad, backend.name(), TOL, |p| {
            plain(point_light_radiance(
                RHO,
                Vec3::new(10.0, 20.0, 5.0),
                light,
                p,
                quad.normal(),
            ))
        });
        assert!(
            seen > 64 * 48 / 4,
            "{backend}: only {seen} pixels saw the plane"
        );
        assert_eq!(out.stats.rays.camera, 64 * 48);
        assert_eq!(out.stats.rays.shadow, seen_shadow_rays(&out));
    }
}

/// Every hit pixel has the light above its horizon here, so shadow rays = plane pixels.
fn seen_shadow_rays(out: &RenderOutput) -> u64 {
    out.image.pixels.iter().filter(|p| p.x > 0.0).count() as u64
}

#[test]
fn photometric_units_divide_by_683() {
    for &backend in BackendKind::available() {
        let (scene, quad, camera, scale) = point_scene(LightUnits::Photometric);
        let mut settings = centre_settings(32, 24);
        settings.light_units = LightUnits::Photometric;
        let out = render_with(&scene, &camera, backend, &settings);
        let light = DVec3::new(0.5, 1.5, -0.3);
        let seen = check(&out, &camera, quad, "photometric", TOL, |p| {
            let radiometric =
                point_light_radiance(RHO, Vec3::new(10.0, 20.0, 5.0), light, p, quad.normal());
            plain(radiometric * scale)
        });
        assert!(seen > 100);
    }
}

#[test]
fn spot_light_inner_cone_falloff_and_outside() {
    let (inner, outer) = (0.3f32, 0.6f32);
    let (cos_inner, cos_outer) = (inner.cos(), outer.cos());
    let position = Vec3::new(0.2, 2.0, -0.1);
    let intensity = Vec3::new(30.0, 10.0, 20.0);
    let axis = Vec3::new(0.1, -1.0, 0.05).normalize();
    for &backend in BackendKind::available() {
        let (exact, mesh) = plane_quad(3.0);
        let light = Light::Spot {
            position,
            direction: axis,
            intensity,
            range: None,
            cos_inner,
            cos_outer,
        };
        let scene = scene(vec![mesh], vec![lambert(RHO, false)], vec![light]);
        let camera = look_at(Vec3::new(0.0, 5.0, 3.0), Vec3::ZERO, Vec3::Y, 0.8);
        let out = render_with(&scene, &camera, backend, &centre_settings(80, 60));
        let (mut full, mut partial, mut dark) = (0, 0, 0);
        let (ci, co) = (cos_inner as f64, cos_outer as f64);
        check(&out, &camera, exact, "spot", TOL, |p| {
            let to_p = (p - position.as_dvec3()).normalize();
            let cd = axis.as_dvec3().dot(to_p);
            // The cone's edge: f32 and f64 may round to either side.
            if (cd - co).abs() < 1e-5 {
                return None;
            }
            let t = ((cd - co) / (ci - co).max(0.001)).clamp(0.0, 1.0);
            match t {
                0.0 => dark += 1,
                1.0 => full += 1,
                _ => partial += 1,
            }
            let unspotted =
                point_light_radiance(RHO, intensity, position.as_dvec3(), p, exact.normal());
            // t = (cd − cos_outer)·scale amplifies the few-ulp f32 error of cd near the edge.
            let conditioning = 2.0 * 4.0 * f32::EPSILON as f64 / (cd - co).abs();
            Some((unspotted * t * t, conditioning))
        });
        assert!(
            full > 50 && partial > 50 && dark > 50,
            "{full} {partial} {dark}"
        );
        assert!(out.stats.rays.skipped_outside_cone >= dark as u64);
    }
}

#[test]
fn directional_light() {
    let direction = Vec3::new(1.0, -2.0, 0.5).normalize();
    let irradiance = Vec3::new(2.0, 3.0, 4.0);
    for &backend in BackendKind::available() {
        let (exact, mesh) = plane_quad(2.0);
        let light = Light::Directional {
            direction,
            irradiance,
        };
        let scene = scene(vec![mesh], vec![lambert(RHO, false)], vec![light]);
        let camera = look_at(Vec3::new(-1.0, 3.0, 3.0), Vec3::ZERO, Vec3::Y, 0.9);
        let out = render_with(&scene, &camera, backend, &centre_settings(48, 48));
        let cos = -direction.as_dvec3().y;
        let want = RHO.as_dvec3() / PI * irradiance.as_dvec3() * cos;
        let seen = check(&out, &camera, exact, "directional", TOL, |_| {
            Some((want, 0.0))
        });
        assert!(seen > 48 * 48 / 3);
    }
}

#[test]
fn inverse_square_law_from_a_millimetre_to_ten_kilometres() {
    let intensity = Vec3::new(1.0, 2.0, 3.0);
    for &backend in BackendKind::available() {
        for exponent in -3..=4 {
            let d = 10f32.powi(exponent);
            // The scene scales with d so that f32 positions carry the same relative precision.
            let (exact, mesh) = plane_quad(2.0 * d);
            let light = Light::Point {
                position: Vec3::new(0.0, d, 0.0),
                intensity,
                range: None,
            };
            let scene = scene(vec![mesh], vec![lambert(RHO, false)], vec![light]);
            let camera = ortho(Vec3::new(0.0, 3.0 * d, 0.0), Vec3::ZERO, -Vec3::Z, d, d);
            let out = render_with(&scene, &camera, backend, &centre_settings(5, 5));
            // The centre pixel lies straight below the light: E = I / d², cosθ = 1.
            let centre = out.image.get(2, 2).unwrap();
            let want = RHO.as_dvec3() / PI * intensity.as_dvec3() / (d as f64 * d as f64);
            assert!(close(centre, want, TOL), "d = {d}: {centre} vs {want}");
            let light_at = DVec3::new(0.0, d as f64, 0.0);
            let seen = check(&out, &camera, exact, "inverse square", TOL, |p| {
                Some((
                    point_light_radiance(RHO, intensity, light_at, p, exact.normal()),
                    0.0,
                ))
            });
            assert_eq!(seen, 25, "d = {d}");
        }
    }
}

#[test]
fn range_window() {
    let range = 3.0f32;
    let position = Vec3::new(0.0, 1.0, 0.0);
    let intensity = Vec3::new(5.0, 5.0, 5.0);
    for &backend in BackendKind::available() {
        let (exact, mesh) = plane_quad(5.0);
        let light = Light::Point {
            position,
            intensity,
            range: Some(range),
        };
        let scene = scene(vec![mesh], vec![lambert(RHO, false)], vec![light]);
        let camera = ortho(Vec3::new(0.0, 4.0, 0.0), Vec3::ZERO, -Vec3::Z, 5.0, 5.0);
        let out = render_with(&scene, &camera, backend, &centre_settings(64, 64));
        let (mut inside, mut beyond) = (0, 0);
        let r = range as f64;
        check(&out, &camera, exact, "range", TOL, |p| {
            let dist = (position.as_dvec3() - p).length();
            if (dist - r).abs() < 1e-4 * r {
                return None;
            }
            let window = (1.0 - (dist / r).powi(4)).clamp(0.0, 1.0);
            if window == 0.0 {
                beyond += 1;
            } else {
                inside += 1;
            }
            let unwindowed =
                point_light_radiance(RHO, intensity, position.as_dvec3(), p, exact.normal());
            // 1 − (d/r)⁴ loses relative precision as it nears 0 at the range.
            let conditioning = 4.0 * 8.0 * f32::EPSILON as f64 / window.max(1e-30);
            Some((unwindowed * window, conditioning))
        });
        assert!(inside > 200 && beyond > 200, "{inside} {beyond}");
        assert_eq!(out.stats.rays.skipped_beyond_range, beyond as u64);
    }
}

#[test]
fn single_sided_back_faces_get_no_light() {
    let light_below = Vec3::new(0.3, -1.5, 0.2);
    let intensity = Vec3::new(4.0, 4.0, 4.0);
    for &backend in BackendKind::available() {
        for double_sided in [false, true] {
            let (exact, mesh) = plane_quad(2.0);
            let light = Light::Point {
                position: light_below,
                intensity,
                range: None,
            };
            let scene = scene(vec![mesh], vec![lambert(RHO, double_sided)], vec![light]);
            // Camera and light both on the back side (below the +Y face).
            let camera = look_at(Vec3::new(0.5, -3.0, 1.0), Vec3::ZERO, Vec3::Y, 0.9);
            let out = render_with(&scene, &camera, backend, &centre_settings(40, 40));
            let seen = check(&out, &camera, exact, "back face", TOL, |p| {
                Some((
                    if double_sided {
                        point_light_radiance(
                            RHO,
                            intensity,
                            light_below.as_dvec3(),
                            p,
                            -exact.normal(),
                        )
                    } else {
                        DVec3::ZERO
                    },
                    0.0,
                ))
            });
            assert!(seen > 400);
        }
        // Double-sided, camera below, light above: the light is on the other side: nothing.
        let (exact, mesh) = plane_quad(2.0);
        let light = Light::Point {
            position: -light_below,
            intensity,
            range: None,
        };
        let scene = scene(vec![mesh], vec![lambert(RHO, true)], vec![light]);
        let camera = look_at(Vec3::new(0.5, -3.0, 1.0), Vec3::ZERO, Vec3::Y, 0.9);
        let out = render_with(&scene, &camera, backend, &centre_settings(40, 40));
        check(&out, &camera, exact, "no leak", TOL, |_| {
            Some((DVec3::ZERO, 0.0))
        });
    }
}
