//! KHR_materials_pbrSpecularGlossiness, converted at load (issue 35): a sphere written as
//! specular-glossiness renders as its metallic-roughness equivalent does, within Monte Carlo
//! noise, for a dielectric (diffuse colour, F0 0.04) and a metal (black diffuse, F0 = its
//! colour), with factors and with the specular-glossiness texture (RGB sRGB F0, A linear
//! glossiness), on every backend. The files are made here. The sphere sits in a uniform
//! environment with a directional light (its highlight shows the roughness). Each pair is
//! rendered with different seeds; the mean of the pixel differences must be within 4 standard
//! errors of 0 per channel, and the test proves it can fail: a dielectric of the metal's
//! colour, or the metal at the wrong roughness, is rejected by the same check.

use crate::support::{Fixture, data_uri, png};
use crate::support::{Furnace, ortho, white_furnace};
use glam::Vec3;
use glint::accel::BackendKind;
use glint::render::BrdfModel;
use glint::scene::Scene;
use serde_json::{Value, json};

const SIZE: u32 = 40;
const SPP: u32 = 64;

/// A UV sphere of radius 1 (positions, normals, indices), its `primitive` JSON with `material` 0.
fn sphere(fixture: &mut Fixture) -> Value {
    let (stacks, slices) = (32u16, 64u16);
    let mut points = Vec::new();
    for i in 0..=stacks {
        let theta = std::f32::consts::PI * f32::from(i) / f32::from(stacks);
        for j in 0..=slices {
            let phi = std::f32::consts::TAU * f32::from(j) / f32::from(slices);
            points.push([
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ]);
        }
    }
    let row = slices + 1;
    let mut indices = Vec::new();
    for i in 0..stacks {
        for j in 0..slices {
            let (a, b) = (i * row + j, i * row + j + 1);
            let (c, d) = (a + row, b + row);
            indices.extend([a, c, b, b, c, d]);
        }
    }
    let flat: Vec<f32> = points.iter().flatten().copied().collect();
    let position = fixture.positions(&points);
    let normal = fixture.floats(&flat, "VEC3", 3);
    let index = fixture.indices_u16(&indices);
    json!({"attributes": {"POSITION": position, "NORMAL": normal}, "indices": index, "material": 0})
}

/// The sphere with `material` (and `textures`), lit by a directional light from above-left,
/// loaded through glint's glTF loader.
fn load(material: Value, images: Value, textures: Value) -> Scene {
    let mut fixture = Fixture::new();
    let primitive = sphere(&mut fixture);
    let mut rest = json!({
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_pbrSpecularGlossiness"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "directional", "color": [1.0, 1.0, 1.0], "intensity": 3.0}
        ]}},
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0},
            // Its −Z turned to (1, 1, −1)/√3: light from the camera's upper left.
            {"rotation": [0.3250576, -0.3250576, 0.0, 0.8880738],
             "extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "meshes": [{"primitives": [primitive]}],
        "materials": [material]
    });
    if images != Value::Null {
        rest["images"] = images;
        rest["textures"] = textures;
    }
    let loaded = fixture.load(rest).expect("the fixture loads");
    assert!(
        loaded.warnings.is_empty(),
        "no warnings: {:?}",
        loaded.warnings
    );
    loaded.scene
}

/// The sphere's pixels (those the sphere covers at their centre, inset from the silhouette).
fn render(scene: &Scene, backend: BackendKind, seed: u64, brdf: BrdfModel) -> Vec<Vec3> {
    let camera = ortho(Vec3::new(0.0, -4.0, 0.3), Vec3::ZERO, Vec3::Z, 1.05, 1.05);
    let furnace = Furnace {
        size: SIZE,
        spp: SPP,
        seed,
        max_depth: 16,
        brdf,
    };
    let image = white_furnace(scene, &camera, backend, &furnace);
    let mut inside = Vec::new();
    for y in 0..SIZE {
        for x in 0..SIZE {
            let u = ((x as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0) * 1.05;
            let v = ((y as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0) * 1.05;
            if u * u + v * v < 0.9 * 0.9 {
                inside.push(image.pixels[(y * SIZE + x) as usize]);
            }
        }
    }
    inside
}

/// The mean pixel difference of `a − b` per channel and its standard error.
fn difference(a: &[Vec3], b: &[Vec3]) -> (Vec3, Vec3) {
    let n = a.len() as f32;
    let d: Vec<Vec3> = a.iter().zip(b).map(|(a, b)| *a - *b).collect();
    let mean = d.iter().copied().sum::<Vec3>() / n;
    let var = d.iter().map(|x| (*x - mean) * (*x - mean)).sum::<Vec3>() / (n - 1.0);
    (mean, (var / n).powf(0.5))
}

/// Whether two renders agree within 4 standard errors in every channel.
fn agree(a: &[Vec3], b: &[Vec3]) -> (bool, String) {
    let (mean, se) = difference(a, b);
    let ok = (mean.abs() - 4.0 * se).max_element() <= 0.0;
    (
        ok,
        format!("mean difference {mean:?}, standard error {se:?}"),
    )
}

fn metallic_roughness(base: [f32; 3], metallic: f32, roughness: f32) -> Value {
    json!({"pbrMetallicRoughness": {
        "baseColorFactor": [base[0], base[1], base[2], 1.0],
        "metallicFactor": metallic,
        "roughnessFactor": roughness
    }})
}

fn specular_glossiness(diffuse: [f32; 3], specular: [f32; 3], glossiness: f32) -> Value {
    json!({"extensions": {"KHR_materials_pbrSpecularGlossiness": {
        "diffuseFactor": [diffuse[0], diffuse[1], diffuse[2], 1.0],
        "specularFactor": specular,
        "glossinessFactor": glossiness
    }}})
}

const GOLD: [f32; 3] = [1.0, 0.766, 0.336];
const RED_CLAY: [f32; 3] = [0.8, 0.3, 0.2];

#[test]
fn a_dielectric_and_a_metal_render_as_their_metallic_roughness_equivalents() {
    // The metal's file also carries a contradictory metallic-roughness block (a rough blue
    // dielectric, the fallback for viewers without the extension): the extension wins.
    let mut gold_with_fallback = specular_glossiness([0.0; 3], GOLD, 0.6);
    gold_with_fallback["pbrMetallicRoughness"] = json!({"baseColorFactor": [0.1, 0.2, 0.9, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0});
    let cases = [
        (
            "dielectric",
            specular_glossiness(RED_CLAY, [0.04; 3], 0.6),
            metallic_roughness(RED_CLAY, 0.0, 0.4),
        ),
        (
            "metal",
            gold_with_fallback,
            metallic_roughness(GOLD, 1.0, 0.4),
        ),
    ];
    for &backend in BackendKind::available() {
        for (what, sg, mr) in &cases {
            let sg = load(sg.clone(), Value::Null, Value::Null);
            let mr = load(mr.clone(), Value::Null, Value::Null);
            // The metal's equality holds exactly in the specification's BRDF; the dielectric's
            // in both models (see the metal note in docs/gltf.md for the compensated one).
            let models: &[BrdfModel] = if *what == "metal" {
                &[BrdfModel::Spec]
            } else {
                &[BrdfModel::Spec, BrdfModel::Compensated]
            };
            for &brdf in models {
                let a = render(&sg, backend, 1, brdf);
                let b = render(&mr, backend, 2, brdf);
                let (ok, detail) = agree(&a, &b);
                assert!(ok, "{backend:?} {brdf}: {what}: {detail}");
            }
        }
        // The check has power: the metal's colour as a dielectric, and the metal with
        // glossiness mistaken for roughness, are told apart.
        let gold = load(
            specular_glossiness([0.0; 3], GOLD, 0.6),
            Value::Null,
            Value::Null,
        );
        let reference = render(&gold, backend, 1, BrdfModel::Spec);
        for (wrong, material) in [
            ("dielectric", metallic_roughness(GOLD, 0.0, 0.4)),
            ("roughness 0.6", metallic_roughness(GOLD, 1.0, 0.6)),
        ] {
            let other = render(
                &load(material, Value::Null, Value::Null),
                backend,
                2,
                BrdfModel::Spec,
            );
            let (ok, detail) = agree(&reference, &other);
            assert!(
                !ok,
                "{backend:?}: the {wrong} passed for the metal: {detail}"
            );
        }
    }
}

#[test]
fn the_specular_glossiness_texture_gives_f0_in_rgb_and_glossiness_in_alpha() {
    // One texel: F0 sRGB-encoded in RGB, glossiness 0.6 (153/255) linear in A.
    let texel = [255u8, 226, 156, 153];
    let f0 = Vec3::new(
        glint::scene::texture_decode::srgb_to_linear(texel[0] as f32 / 255.0),
        glint::scene::texture_decode::srgb_to_linear(texel[1] as f32 / 255.0),
        glint::scene::texture_decode::srgb_to_linear(texel[2] as f32 / 255.0),
    );
    let images = json!([{"uri": data_uri("image/png", &png(1, 1, &texel))}]);
    let textures = json!([{"source": 0}]);
    let textured = json!({"extensions": {"KHR_materials_pbrSpecularGlossiness": {
        "diffuseFactor": [0.0, 0.0, 0.0, 1.0],
        "specularGlossinessTexture": {"index": 0}
    }}});
    let sg = load(textured, images, textures);
    let mr = load(
        metallic_roughness(f0.to_array(), 1.0, 1.0 - 0.6),
        Value::Null,
        Value::Null,
    );
    for &backend in BackendKind::available() {
        let a = render(&sg, backend, 1, BrdfModel::Spec);
        let b = render(&mr, backend, 2, BrdfModel::Spec);
        let (ok, detail) = agree(&a, &b);
        assert!(ok, "{backend:?}: textured metal: {detail}");
    }
}
