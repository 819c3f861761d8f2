//! KHR_materials_diffuse_transmission through the glTF loader (issue 35): a file made here
//! with the factor, the colour factor and both textures loads into the material's
//! diffuse-transmission layer; `diffuseTransmissionTexture` is read linear (its alpha is
//! the strength) and `diffuseTransmissionColorTexture` as sRGB (its RGB decoded to linear); the
//! extension is not reported as ignored; a factor of 0 (or no extension) gives the same
//! material as a file without it; out-of-range factors are clamped with a warning.

use crate::support::{Fixture, data_uri, png};
use glam::Vec3;
use serde_json::{Value, json};

/// One quad whose material is `material`, with two 1×1 PNG textures: texture 0 of texel
/// (10, 20, 30, 64), texture 1 of texel (128, 64, 255, 255).
fn load(material: Value, used: &[&str]) -> glint::scene::gltf::Loaded {
    let mut fixture = Fixture::new();
    let position = fixture.positions(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ]);
    let uv = fixture.floats(&[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0], "VEC2", 2);
    let index = fixture.indices_u16(&[0, 1, 2, 0, 2, 3]);
    let images = json!([
        {"uri": data_uri("image/png", &png(1, 1, &[10, 20, 30, 64]))},
        {"uri": data_uri("image/png", &png(1, 1, &[128, 64, 255, 255]))}
    ]);
    fixture
        .load(json!({
            "extensionsUsed": used,
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": position, "TEXCOORD_0": uv},
                "indices": index, "material": 0}]}],
            "materials": [material],
            "images": images,
            "textures": [{"source": 0}, {"source": 1}]
        }))
        .expect("the fixture loads")
}

fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[test]
fn factors_and_textures_are_read_in_their_colour_spaces() {
    let loaded = load(
        json!({"pbrMetallicRoughness": {"metallicFactor": 0.0},
        "extensions": {"KHR_materials_diffuse_transmission": {
            "diffuseTransmissionFactor": 0.75,
            "diffuseTransmissionTexture": {"index": 0},
            "diffuseTransmissionColorFactor": [0.5, 1.0, 0.25],
            "diffuseTransmissionColorTexture": {"index": 1}
        }}}),
        &["KHR_materials_diffuse_transmission"],
    );
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let scene = &loaded.scene;
    let d = scene.materials[0]
        .diffuse_transmission
        .expect("the layer is read");
    assert_eq!(d.factor, 0.75);
    assert_eq!(d.color, Vec3::new(0.5, 1.0, 0.25));
    let strength = d.texture.expect("diffuseTransmissionTexture");
    let color = d.color_texture.expect("diffuseTransmissionColorTexture");
    // Linear: the alpha texel 64/255 as it is (the strength is factor × A).
    let a = scene.textures[strength.texture].texels.texel(0);
    assert!((a.w - 64.0 / 255.0).abs() < 1e-3, "strength texel {a}");
    // sRGB-decoded RGB.
    let c = scene.textures[color.texture].texels.texel(0);
    for (got, byte) in [(c.x, 128u8), (c.y, 64), (c.z, 255)] {
        let want = srgb_to_linear(f32::from(byte) / 255.0);
        assert!(
            (got - want).abs() < 2e-3,
            "colour texel {c}: {got} vs {want}"
        );
    }
}

#[test]
fn factor_zero_is_the_material_without_the_extension() {
    let plain = json!({"pbrMetallicRoughness": {"metallicFactor": 0.0}});
    let mut zero = plain.clone();
    zero["extensions"] = json!({"KHR_materials_diffuse_transmission": {
        "diffuseTransmissionColorFactor": [1.0, 0.0, 0.0],
        "diffuseTransmissionColorTexture": {"index": 1}}});
    let without = load(plain, &[]);
    let with_zero = load(zero, &["KHR_materials_diffuse_transmission"]);
    assert!(with_zero.warnings.is_empty(), "{:?}", with_zero.warnings);
    assert_eq!(with_zero.scene.materials[0].diffuse_transmission, None);
    // Every field the same (Material has no PartialEq; its Debug form lists them all).
    assert_eq!(
        format!("{:?}", with_zero.scene.materials),
        format!("{:?}", without.scene.materials)
    );
}

#[test]
fn out_of_range_factors_are_clamped_with_a_warning() {
    let loaded = load(
        json!({"extensions": {"KHR_materials_diffuse_transmission": {
            "diffuseTransmissionFactor": 1.5,
            "diffuseTransmissionColorFactor": [2.0, 0.5, -1.0]}}}),
        &["KHR_materials_diffuse_transmission"],
    );
    let d = loaded.scene.materials[0]
        .diffuse_transmission
        .expect("read");
    assert_eq!((d.factor, d.color), (1.0, Vec3::new(1.0, 0.5, 0.0)));
    assert_eq!(loaded.warnings.len(), 3, "{:?}", loaded.warnings);
    assert!(
        loaded
            .warnings
            .iter()
            .all(|w| w.contains("KHR_materials_diffuse_transmission")
                && !w.contains("not supported")),
        "{:?}",
        loaded.warnings
    );
}
