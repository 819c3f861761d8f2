//! Interpolated vertex normals keep mirror reflections above the geometric surface
//! (docs/normal-maps.md, rule 1): a smooth white mirror whose vertex normals lean away from a
//! grazing viewer would mirror the view below its own plane, where the path tracer drops the
//! reflection (rule 2) and the pixel went black. With the normal bent, the mirror reflects the
//! uniform sky: radiance exactly 1 (white metal, Fresnel 1 at every angle), on both backends.

use crate::support::{centre_settings, mirror, ortho, quad, scene};
use glam::Vec3;
use glint::accel::{BackendKind, BuildOptions};
use glint::light::environment::EnvironmentLight;
use glint::render::{self, Integrator, RenderInputs, RenderSettings};
use glint::scene::Mesh;

/// The quad z = 0 (front +Z) with every vertex normal leaning `lean` radians toward −x, seen
/// by an orthographic camera from +x at `elevation` radians above the plane; the centre
/// pixel's radiance under a uniform sky of radiance 1.
fn centre_radiance(lean: f32, elevation: f32, backend: BackendKind) -> Vec3 {
    let normal = Vec3::new(-lean.sin(), 0.0, lean.cos());
    let mesh = Mesh {
        normals: Some(vec![normal; 4]),
        ..quad(Vec3::ZERO, Vec3::X, Vec3::Y, 0)
    };
    let scene = scene(vec![mesh], vec![mirror(Vec3::ONE, 1.0)], vec![]);
    let eye = Vec3::new(elevation.cos(), 0.0, elevation.sin()) * 5.0;
    let camera = ortho(eye, Vec3::ZERO, Vec3::Z, 0.05, 0.05);
    let env = EnvironmentLight::constant(Vec3::ONE);
    let accel = render::prepare(&scene, backend, BuildOptions::default()).expect("build");
    let mut inputs = RenderInputs::of_scene(&scene, accel.as_ref(), &camera);
    inputs.environment = Some(&env);
    let settings = RenderSettings {
        integrator: Integrator::Path,
        max_depth: 4,
        ..centre_settings(3, 3)
    };
    let (film, _) = render::render_film(&inputs, &settings, 0..1, None).expect("render");
    let (image, _) = film.resolve();
    image.pixels[4]
}

#[test]
fn a_smooth_mirror_seen_at_grazing_reflects_the_sky() {
    let (elevation, lean) = (10f32.to_radians(), 8f32.to_radians());
    // The premise: about the interpolated normal, the view mirrors below the plane.
    let (n, wo) = (
        Vec3::new(-lean.sin(), 0.0, lean.cos()),
        Vec3::new(elevation.cos(), 0.0, elevation.sin()),
    );
    assert!(n.dot(wo) > 0.0 && (2.0 * n.dot(wo) * n - wo).z < 0.0);
    for &backend in BackendKind::available() {
        let got = centre_radiance(lean, elevation, backend);
        assert!(
            (got - Vec3::ONE).abs().max_element() < 1e-4,
            "{backend}: the mirror shows {got}, want the sky's 1"
        );
        // A normal that already reflects above the plane is left alone: same answer.
        let upright = centre_radiance(-lean, elevation, backend);
        assert!(
            (upright - Vec3::ONE).abs().max_element() < 1e-4,
            "{backend}: {upright}"
        );
    }
}
