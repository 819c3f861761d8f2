//! The direct integrator shades the same BSDF as the path tracer (the surface front end does
//! not depend on the integrator): a clear coat adds its lobe and changes nothing else.
//!
//! A rough dielectric plane under a directional light, seen by a wide camera from the
//! light's mirror direction (so the coat's highlight is at the image centre), rendered at
//! pixel centres. With one directional light, one sample at pixel centres and `max_depth = 1`, the
//! path tracer's estimate is its light sample alone, the same number the direct integrator
//! computes: the two images must agree to rounding, for the plain and the coated material.

use crate::support::{centre_settings, look_at, quad, render_with, scene};
use glam::Vec3;
use glint::accel::BackendKind;
use glint::render::{Integrator, RenderSettings};
use glint::scene::layers::Clearcoat;
use glint::scene::{Light, Material};

fn plain() -> Material {
    Material {
        name: "plain".into(),
        base_color: Vec3::new(0.6, 0.4, 0.2).extend(1.0),
        metallic: 0.0,
        roughness: 0.5,
        ..Material::default()
    }
}

fn coated(factor: f32) -> Material {
    Material {
        name: "coated".into(),
        clearcoat: Some(Clearcoat {
            factor,
            roughness: 0.1,
            texture: None,
            roughness_texture: None,
            normal_texture: None,
        }),
        ..plain()
    }
}

fn render(material: Material, integrator: Integrator) -> Vec<Vec3> {
    let to_light = Vec3::new(0.0, 1.0, 0.6).normalize();
    let view = Vec3::new(0.0, 1.0, -0.6).normalize();
    let plane = quad(Vec3::ZERO, Vec3::X * 50.0, -Vec3::Z * 50.0, 0);
    let light = Light::Directional {
        direction: -to_light,
        irradiance: Vec3::splat(2.0),
    };
    let s = scene(vec![plane], vec![material], vec![light]);
    let camera = look_at(view * 5.0, Vec3::ZERO, Vec3::Y, 1.0);
    let settings = RenderSettings {
        integrator,
        max_depth: 1,
        ..centre_settings(24, 24)
    };
    render_with(&s, &camera, BackendKind::Bvh, &settings)
        .image
        .pixels
}

fn agree(a: &[Vec3], b: &[Vec3], tol: f32, what: &str) {
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (*x - *y).abs().max_element() <= tol * y.max_element().max(1e-3),
            "{what}: pixel {i}: {x} vs {y}"
        );
    }
}

#[test]
fn direct_and_path_shade_the_same_bsdf_with_and_without_a_coat() {
    for material in [plain(), coated(1.0)] {
        let name = material.name.clone();
        let direct = render(material.clone(), Integrator::Direct);
        let path = render(material, Integrator::Path);
        assert!(direct.iter().all(|p| p.max_element() > 0.0), "{name}");
        agree(&direct, &path, 1e-5, &name);
    }
}

#[test]
fn a_coat_adds_its_lobe_and_changes_nothing_else() {
    let plain_image = render(plain(), Integrator::Direct);
    // A coat of factor 0 is no coat.
    agree(
        &render(coated(0.0), Integrator::Direct),
        &plain_image,
        1e-5,
        "coat factor 0",
    );
    // A full coat: brighter where its highlight is (the image centre looks along the mirror
    // direction), and no brighter than the plain base where the coat reflects nothing
    // toward the camera (it only attenuates the base there).
    let coated_image = render(coated(1.0), Integrator::Direct);
    let centre = 12 * 24 + 12;
    assert!(
        coated_image[centre].max_element() > 1.5 * plain_image[centre].max_element(),
        "the coat's highlight: {} vs {}",
        coated_image[centre],
        plain_image[centre]
    );
    let corner = 0;
    assert!(
        coated_image[corner].max_element() <= plain_image[corner].max_element() * 1.0001,
        "{} vs {}",
        coated_image[corner],
        plain_image[corner]
    );
}
