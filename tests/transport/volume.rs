//! KHR_materials_volume's Beer-Lambert attenuation in a render: a slab of index-matched
//! (ior 1, so no Fresnel and no bending) transmitting material, thickness `d`, in front of an
//! emitter. Every camera ray enters the slab, crosses it along `d` and leaves, so the pixel
//! is exactly `Le · exp(−σ d)` with `σ = −ln(attenuationColor) / attenuationDistance`; without
//! the volume (thin-walled) it is `Le`.

use crate::support::{centre_settings, emitter, ortho, quad, render_with, scene};
use glam::Vec3;
use glint::accel::BackendKind;
use glint::render::{Integrator, RenderSettings};
use glint::scene::Material;
use glint::scene::layers::{Transmission, Volume};

fn glass(volume: Option<Volume>) -> Material {
    Material {
        name: "index-matched glass".into(),
        base_color: glam::Vec4::ONE,
        metallic: 0.0,
        roughness: 0.0,
        ior: 1.0,
        transmission: Some(Transmission {
            factor: 1.0,
            texture: None,
        }),
        volume,
        ..Material::default()
    }
}

fn render_slab(volume: Option<Volume>, d: f32, le: Vec3) -> Vec<Vec3> {
    let s = 1.0;
    let meshes = vec![
        // Front face toward +Z (the camera), back face toward −Z: a closed slab as far as
        // the camera's rays can tell.
        quad(Vec3::Z * (d / 2.0), Vec3::X * s, Vec3::Y * s, 0),
        quad(-Vec3::Z * (d / 2.0), Vec3::Y * s, Vec3::X * s, 0),
        // The emitter faces +Z.
        quad(-Vec3::Z * 1.0, Vec3::X * 2.0, Vec3::Y * 2.0, 1),
    ];
    let sc = scene(meshes, vec![glass(volume), emitter(le)], vec![]);
    let camera = ortho(Vec3::Z * 3.0, Vec3::ZERO, Vec3::Y, 0.5, 0.5);
    let settings = RenderSettings {
        integrator: Integrator::Path,
        max_depth: 8,
        ..centre_settings(4, 4)
    };
    let out = render_with(&sc, &camera, BackendKind::Bvh, &settings);
    out.image.pixels.clone()
}

#[test]
fn a_slab_attenuates_by_beer_lambert() {
    let le = Vec3::new(2.0, 3.0, 4.0);
    let d = 0.5;
    let volume = Volume {
        thickness: d,
        attenuation_color: Vec3::new(0.5, 0.8, 1.0),
        attenuation_distance: 1.0,
    };
    let want = le * Vec3::new(0.5f32.powf(d), 0.8f32.powf(d), 1.0);
    for p in render_slab(Some(volume), d, le) {
        assert!(
            (p - want).abs().max_element() < 1e-4 * le.max_element(),
            "{p} vs {want}"
        );
    }
    // Thin-walled (no volume): no attenuation at all.
    for p in render_slab(None, d, le) {
        assert!(
            (p - le).abs().max_element() < 1e-4 * le.max_element(),
            "{p} vs {le}"
        );
    }
}
