//! Pixel filters: each integrates to 1 (a constant scene renders to that constant at every
//! pixel, borders included), and a step edge renders to the filter's cumulative profile.

use crate::support::{emitter, ortho, quad, render_with};
use glam::Vec3;
use glint::accel::BackendKind;
use glint::render::{FilterKind, FilterSpec, PixelSampling, RenderSettings};
use glint::scene::Scene;

/// An orthographic camera over a `width × height` image with one scene unit per pixel,
/// centred on the origin, looking down −Z.
fn pixel_camera(width: u32, height: u32) -> glint::scene::Camera {
    ortho(
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::ZERO,
        Vec3::Y,
        width as f32 / 2.0,
        height as f32 / 2.0,
    )
}

fn settings(width: u32, height: u32, spp: u32, filter: FilterSpec) -> RenderSettings {
    RenderSettings {
        integrator: glint::render::Integrator::Direct,
        width,
        height,
        spp,
        filter,
        sampling: PixelSampling::Sobol,
        threads: 2,
        ..RenderSettings::default()
    }
}

#[test]
fn every_filter_renders_a_constant_scene_to_that_constant_at_every_pixel() {
    let le = Vec3::new(0.3, 1.7, 5.0);
    // An emitter far larger than the view, so rays leaving the image (wide filters at the
    // border) still see it.
    let scene = Scene {
        meshes: vec![quad(Vec3::ZERO, Vec3::X * 100.0, Vec3::Y * 100.0, 0)],
        materials: vec![emitter(le)],
        ..Scene::default()
    };
    let (width, height) = (13, 9);
    let camera = pixel_camera(width, height);
    for kind in FilterKind::ALL {
        for radius_px in [kind.default_radius(), 0.8, 3.0] {
            let filter = FilterSpec { kind, radius_px };
            // Odd counts: with ±1 weights an odd count can never cancel to Σw = 0, which
            // Mitchell's negative lobes allow at even counts (such a pixel is 0; see
            // docs/convergence.md).
            for spp in [1, 5] {
                let out = render_with(
                    &scene,
                    &camera,
                    BackendKind::Bvh,
                    &settings(width, height, spp, filter),
                );
                for (i, p) in out.image.pixels.iter().enumerate() {
                    let rel = ((*p - le) / le).abs().max_element();
                    assert!(rel < 1e-5, "{filter}, {spp} spp, pixel {i}: {p} vs {le}");
                }
            }
        }
    }
}

/// `∫_{t > a} f₁(t) dt / ∫ f₁(t) dt` by a fine midpoint rule.
fn tail_fraction(kind: FilterKind, r: f32, a: f64) -> f64 {
    let n = 100_000;
    let h = 2.0 * r as f64 / n as f64;
    let (mut tail, mut total) = (0.0, 0.0);
    for i in 0..n {
        let t = -r as f64 + (i as f64 + 0.5) * h;
        let f = kind.eval_1d(t as f32, r) as f64;
        total += f;
        if t > a {
            tail += f;
        }
    }
    tail / total
}

#[test]
fn a_step_edge_renders_to_each_filters_cumulative_profile() {
    // Emitter (radiance 1) on x > EDGE, nothing on the other side. A pixel whose centre is
    // at c sees ∫ f(t) [c + t > EDGE] dt / ∫ f: the filter's tail beyond EDGE − c.
    const EDGE: f32 = 0.3;
    let scene = Scene {
        meshes: vec![quad(
            Vec3::new(EDGE + 100.0, 0.0, 0.0),
            Vec3::X * 100.0,
            Vec3::Y * 100.0,
            0,
        )],
        materials: vec![emitter(Vec3::ONE)],
        ..Scene::default()
    };
    let (width, height) = (12, 2);
    let camera = pixel_camera(width, height);
    for kind in FilterKind::ALL {
        let filter = FilterSpec::new(kind);
        let out = render_with(
            &scene,
            &camera,
            BackendKind::Bvh,
            &settings(width, height, 1024, filter),
        );
        for x in 0..width {
            let centre = x as f64 + 0.5 - width as f64 / 2.0;
            let expected = tail_fraction(kind, filter.radius_px, EDGE as f64 - centre);
            for y in 0..height {
                let got = out.image.get(x, y).unwrap().x as f64;
                assert!(
                    (got - expected).abs() < 0.01,
                    "{filter}: pixel ({x}, {y}) centre {centre}: {got} vs {expected}"
                );
            }
        }
    }
}
