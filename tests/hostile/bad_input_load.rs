//! Bad input never panics the loader: each gives an error naming the file and the specific
//! problem.

use crate::support::{Fixture, TempDir, data_uri, scenes_dir};
use glint::scene::gltf::{LoadError, load, load_slice_with_warnings};
use rand::{Rng, SeedableRng};
use serde_json::{Value, json};
use std::path::Path;

/// Asserts that loading failed with a message containing the file's name and every
/// `expected` fragment.
fn assert_error(result: Result<impl std::fmt::Debug, LoadError>, file: &str, expected: &[&str]) {
    let err = result.expect_err("bad input must be an error");
    let message = err.to_string();
    assert!(
        message.contains(file),
        "message should name {file}: {message}"
    );
    for fragment in expected {
        assert!(
            message.contains(fragment),
            "message should say {fragment:?}: {message}"
        );
    }
    assert!(!message.contains('\n'), "one line: {message}");
}

/// A triangle's worth of valid data and a document using it, for tests to break.
fn triangle_fixture() -> (Fixture, Value) {
    let mut fixture = Fixture::new();
    let position = fixture.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let indices = fixture.indices_u16(&[0, 1, 2]);
    let rest = json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": position}, "indices": indices}]}]
    });
    (fixture, rest)
}

#[test]
fn the_unbroken_fixture_loads() {
    // Guards the tests below: each breaks exactly one thing of this document.
    let (fixture, rest) = triangle_fixture();
    assert_eq!(fixture.load(rest).unwrap().scene.triangle_count(), 1);
}

#[test]
fn missing_file() {
    assert_error(
        load(Path::new("/nonexistent/scene.gltf")),
        "/nonexistent/scene.gltf",
        &["cannot read"],
    );
}

#[test]
fn empty_truncated_and_invalid_json() {
    let dir = TempDir::new("json");
    let empty = dir.write("empty.gltf", b"");
    assert_error(load(&empty), "empty.gltf", &["empty"]);
    let text = std::fs::read(scenes_dir().join("BoxTextured/BoxTextured.gltf")).unwrap();
    let truncated = dir.write("truncated.gltf", &text[..text.len() / 2]);
    assert_error(
        load(&truncated),
        "truncated.gltf",
        &["not valid glTF JSON", "EOF"],
    );
    let garbage = dir.write("garbage.gltf", b"hello, I am not glTF");
    assert_error(
        load(&garbage),
        "garbage.gltf",
        &["not valid glTF JSON", "line 1"],
    );
}

#[test]
fn truncated_glb_at_every_length_is_an_error() {
    let glb = glint::scene::demo::DEMO_GLB;
    // Every cut within the header and the JSON chunk, and a spread of cuts in the binary.
    let cuts = (0..2048).chain((2048..glb.len()).step_by(509));
    for cut in cuts {
        let result = load_slice_with_warnings(&glb[..cut], "cut.glb", None);
        let message = result
            .expect_err("a truncated GLB must not load")
            .to_string();
        assert!(message.starts_with("cut.glb: "), "{cut}: {message}");
        if cut >= 12 {
            assert!(message.contains("truncated"), "{cut}: {message}");
        }
    }
}

#[test]
fn glb_header_lies() {
    let mut header = b"glTF".to_vec();
    header.extend(2u32.to_le_bytes());
    header.extend(4u32.to_le_bytes()); // a total length smaller than the header
    assert_error(
        load_slice_with_warnings(&header, "short.glb", None),
        "short.glb",
        &["invalid GLB", "length of 4"],
    );
    let mut version = glint::scene::demo::DEMO_GLB.to_vec();
    version[4] = 1;
    assert_error(
        load_slice_with_warnings(&version, "v1.glb", None),
        "v1.glb",
        &["GLB version 1"],
    );
}

/// Copies BoxTextured's files except `omit` into a temporary folder.
fn box_textured_without(omit: &str) -> (TempDir, std::path::PathBuf) {
    let dir = TempDir::new("box");
    for name in ["BoxTextured.gltf", "BoxTextured0.bin", "CesiumLogoFlat.png"] {
        if name != omit {
            dir.write(
                name,
                &std::fs::read(scenes_dir().join("BoxTextured").join(name)).unwrap(),
            );
        }
    }
    let path = dir.path().join("BoxTextured.gltf");
    (dir, path)
}

#[test]
fn missing_bin_file_is_named() {
    let (_dir, path) = box_textured_without("BoxTextured0.bin");
    assert_error(
        load(&path),
        "BoxTextured.gltf",
        &["buffer 0", "\"BoxTextured0.bin\"", "cannot be read"],
    );
}

#[test]
fn missing_texture_file_is_named() {
    let (_dir, path) = box_textured_without("CesiumLogoFlat.png");
    assert_error(
        load(&path),
        "BoxTextured.gltf",
        &["image 0", "\"CesiumLogoFlat.png\"", "cannot be read"],
    );
}

#[test]
fn external_reference_from_memory() {
    let (fixture, rest) = triangle_fixture();
    let mut doc = fixture.document(rest);
    doc["buffers"][0]["uri"] = json!("data.bin");
    let text = serde_json::to_vec(&doc).unwrap();
    assert_error(
        load_slice_with_warnings(&text, "memory.gltf", None),
        "memory.gltf",
        &["buffer 0", "\"data.bin\"", "from memory"],
    );
}

#[test]
fn bad_data_uri() {
    let (fixture, rest) = triangle_fixture();
    let mut doc = fixture.document(rest);
    doc["buffers"][0]["uri"] = json!("data:application/octet-stream;base64,@@@@");
    let text = serde_json::to_vec(&doc).unwrap();
    assert_error(
        load_slice_with_warnings(&text, "b64.gltf", None),
        "b64.gltf",
        &["buffer 0", "invalid base64"],
    );
}

#[test]
fn buffer_shorter_than_declared() {
    let (fixture, rest) = triangle_fixture();
    let mut doc = fixture.document(rest);
    doc["buffers"][0]["byteLength"] = json!(fixture.bin.len() + 100);
    let text = serde_json::to_vec(&doc).unwrap();
    assert_error(
        load_slice_with_warnings(&text, "short.gltf", None),
        "short.gltf",
        &["buffer 0", "truncated"],
    );
}

#[test]
fn accessor_index_out_of_range() {
    let (fixture, mut rest) = triangle_fixture();
    rest["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = json!(99);
    assert_error(
        fixture.load(rest),
        "fixture.gltf",
        &[
            "mesh 0 / primitive 0",
            "NORMAL refers to accessor 99",
            "only 2 accessors",
        ],
    );
}

#[test]
fn other_schema_errors_give_the_json_path() {
    let (fixture, mut rest) = triangle_fixture();
    rest["nodes"][0]["mesh"] = json!(7);
    assert_error(
        fixture.load(rest),
        "fixture.gltf",
        &["invalid glTF", "nodes[0].mesh"],
    );
}

#[test]
fn accessor_bytes_past_its_buffer_view() {
    let (mut fixture, rest) = triangle_fixture();
    fixture.accessors[0]["count"] = json!(30);
    assert_error(
        fixture.load(rest),
        "fixture.gltf",
        &[
            "node 0 / mesh 0 / primitive 0",
            "POSITION accessor 0",
            "needs 360 bytes of buffer view 0, which has 36",
        ],
    );
}

#[test]
fn buffer_view_past_its_buffer() {
    let (mut fixture, rest) = triangle_fixture();
    fixture.views[1]["byteLength"] = json!(1000);
    assert_error(
        fixture.load(rest),
        "fixture.gltf",
        &["buffer view 1", "outside buffer 0"],
    );
}

#[test]
fn accessor_with_count_zero_or_short_stride_or_wrong_type() {
    let (mut fixture, rest) = triangle_fixture();
    fixture.accessors[1]["count"] = json!(0);
    assert_error(
        fixture.load(rest.clone()),
        "fixture.gltf",
        &["indices accessor 1", "count 0"],
    );

    let (mut fixture, rest2) = triangle_fixture();
    fixture.views[0]["byteStride"] = json!(4);
    assert_error(
        fixture.load(rest2),
        "fixture.gltf",
        &["POSITION accessor 0", "byteStride 4", "12-byte element"],
    );

    let (mut fixture, rest3) = triangle_fixture();
    fixture.accessors[0]["type"] = json!("VEC2");
    assert_error(
        fixture.load(rest3),
        "fixture.gltf",
        &["POSITION accessor 0", "has type VEC2 FLOAT", "VEC3 FLOAT"],
    );

    let (mut fixture, rest4) = triangle_fixture();
    fixture.accessors[1]["componentType"] = json!(5126);
    assert_error(
        fixture.load(rest4),
        "fixture.gltf",
        &["indices accessor 1", "SCALAR FLOAT"],
    );
}

#[test]
fn index_past_the_vertex_count() {
    let mut fixture = Fixture::new();
    let position = fixture.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let indices = fixture.indices_u16(&[0, 1, 2, 0, 2, 5]);
    let result = fixture.load(json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "lid"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": position}, "indices": indices}]}]
    }));
    assert_error(
        result,
        "fixture.gltf",
        &[
            "node \"lid\" / mesh 0 / primitive 0",
            "indices accessor 1",
            "index 5 is 5, past the 3 vertices",
        ],
    );
}

#[test]
fn nan_and_infinite_positions() {
    for bad in [f32::NAN, f32::INFINITY] {
        let mut fixture = Fixture::new();
        let position = fixture.floats(&[0.0, 0.0, 0.0, bad, 0.0, 0.0, 0.0, 1.0, 0.0], "VEC3", 3);
        fixture.accessors[position]["min"] = json!([0, 0, 0]);
        fixture.accessors[position]["max"] = json!([1, 1, 0]);
        let result = fixture.load(json!({
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": position}}]}]
        }));
        assert_error(
            result,
            "fixture.gltf",
            &["POSITION accessor 0", "vertex 1", "not finite"],
        );
    }
}

#[test]
fn unsupported_required_extension_is_named() {
    let (fixture, mut rest) = triangle_fixture();
    rest["extensionsUsed"] = json!(["EXT_lights_image_based"]);
    rest["extensionsRequired"] = json!(["EXT_lights_image_based"]);
    assert_error(
        fixture.load(rest),
        "fixture.gltf",
        &[
            "requires extension EXT_lights_image_based",
            "supported: KHR_lights_punctual",
        ],
    );
}

#[test]
fn used_but_unsupported_extension_is_a_warning() {
    let (fixture, mut rest) = triangle_fixture();
    // (KHR_materials_clearcoat was the example until glint read it.)
    rest["extensionsUsed"] = json!(["KHR_materials_iridescence"]);
    let loaded = fixture.load(rest).unwrap();
    assert_eq!(loaded.warnings.len(), 1);
    assert!(
        loaded.warnings[0].contains("KHR_materials_iridescence")
            && loaded.warnings[0].contains("ignored")
    );
}

/// Malformed layer factors fall back to their defaults with a warning naming the material,
/// the extension and the field; out-of-range ones are clamped; a texture index the file lacks
/// is named and ignored.
#[test]
fn bad_material_layer_fields_are_warned_about() {
    let (fixture, mut rest) = triangle_fixture();
    rest["extensionsUsed"] = json!(["KHR_materials_clearcoat", "KHR_materials_sheen"]);
    rest["meshes"][0]["primitives"][0]["material"] = json!(0);
    rest["materials"] = json!([{
        "name": "coated",
        "extensions": {
            "KHR_materials_clearcoat": {
                "clearcoatFactor": 7.0,
                "clearcoatRoughnessFactor": "rough",
                "clearcoatNormalTexture": {"index": 0}
            },
            "KHR_materials_sheen": {"sheenColorFactor": [1, 2]}
        }
    }]);
    let loaded = fixture.load(rest).unwrap();
    let all = loaded.warnings.join("\n");
    for part in [
        "coated",
        "KHR_materials_clearcoat.clearcoatFactor is 7, outside [0, 1]; clamped to 1",
        "KHR_materials_clearcoat.clearcoatRoughnessFactor is not a number",
        "clearcoatNormalTexture names texture 0, but the file has 0; the texture is ignored",
        "KHR_materials_sheen.sheenColorFactor is not an array of three numbers",
    ] {
        assert!(all.contains(part), "no {part:?} in:\n{all}");
    }
    let m = &loaded.scene.materials[0];
    assert_eq!(
        m.clearcoat.map(|c| (c.factor, c.roughness)),
        Some((1.0, 0.0))
    );
    // Sheen colour defaults to black: no sheen layer.
    assert!(m.sheen.is_none());
}

#[test]
fn texture_that_does_not_decode() {
    let (fixture, mut rest) = triangle_fixture();
    rest["meshes"][0]["primitives"][0]["material"] = json!(0);
    rest["materials"] = json!([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]);
    rest["textures"] = json!([{"source": 0}]);
    rest["images"] =
        json!([{"uri": data_uri("image/png", b"\x89PNG but not really"), "name": "broken"}]);
    assert_error(
        fixture.load(rest),
        "fixture.gltf",
        &["image 0 \"broken\"", "cannot decode"],
    );
}

#[test]
fn node_cycle() {
    let (fixture, mut rest) = triangle_fixture();
    rest["nodes"] = json!([{"mesh": 0, "children": [1]}, {"children": [0]}]);
    assert_error(
        fixture.load(rest),
        "fixture.gltf",
        &["node", "reached twice"],
    );
}

#[test]
fn bad_light_and_camera_values() {
    let (fixture, mut rest) = triangle_fixture();
    rest["extensions"] = json!({"KHR_lights_punctual": {"lights": [{"type": "spot", "intensity": 1,
        "spot": {"innerConeAngle": 0.8, "outerConeAngle": 0.4}}]}});
    rest["nodes"][0]["extensions"] = json!({"KHR_lights_punctual": {"light": 0}});
    assert_error(
        fixture.load(rest),
        "fixture.gltf",
        &["node 0 / light 0", "cone angles"],
    );

    let (fixture, mut rest) = triangle_fixture();
    rest["cameras"] = json!([{"type": "perspective", "perspective": {"yfov": 0, "znear": 0.1}}]);
    rest["nodes"][0]["camera"] = json!(0);
    assert_error(
        fixture.load(rest),
        "fixture.gltf",
        &["node 0 / camera 0", "yfov is 0"],
    );

    let (fixture, mut rest) = triangle_fixture();
    rest["nodes"][0]["rotation"] = json!([0, 0, 0, 0]);
    assert_error(
        fixture.load(rest),
        "fixture.gltf",
        &["node 0", "zero or NaN rotation"],
    );
}

/// Random byte corruption of a valid GLB: whatever the damage, the loader returns (Ok or a
/// one-line Err naming the file) and never panics.
#[test]
fn random_corruption_never_panics() {
    let original = glint::scene::demo::DEMO_GLB;
    let mut rng = rand_pcg::Pcg64::seed_from_u64(7);
    for round in 0..200 {
        let mut bytes = original.to_vec();
        // Aim most flips at the header and JSON chunk, where structure lives.
        for _ in 0..rng.random_range(1..8) {
            let at = if rng.random_bool(0.8) {
                rng.random_range(0..4096.min(bytes.len()))
            } else {
                rng.random_range(0..bytes.len())
            };
            bytes[at] = rng.random();
        }
        let outcome =
            std::panic::catch_unwind(|| load_slice_with_warnings(&bytes, "corrupt.glb", None));
        match outcome {
            Ok(Ok(_)) => {}
            Ok(Err(err)) => {
                let message = err.to_string();
                assert!(
                    message.starts_with("corrupt.glb: ") && !message.contains('\n'),
                    "round {round}: {message}"
                );
            }
            Err(_) => panic!("round {round}: the loader panicked"),
        }
    }
}

#[test]
fn bad_sparse_accessor() {
    let (mut fixture, rest) = triangle_fixture();
    let sparse_indices = fixture.view(&[0u8; 4]);
    let sparse_values = fixture.view(&[0u8; 12]);
    fixture.accessors[0]["sparse"] = json!({
        "count": 0,
        "indices": {"bufferView": sparse_indices, "componentType": 5123},
        "values": {"bufferView": sparse_values}
    });
    assert_error(
        fixture.load(rest.clone()),
        "fixture.gltf",
        &["POSITION accessor 0", "sparse count of 0"],
    );

    let (mut fixture, rest) = triangle_fixture();
    let sparse_indices = fixture.view(&[0u8; 4]);
    let sparse_values = fixture.view(&[0u8; 12]);
    fixture.accessors[0]["sparse"] = json!({
        "count": 3,
        "indices": {"bufferView": sparse_indices, "componentType": 5123},
        "values": {"bufferView": sparse_values}
    });
    assert_error(
        fixture.load(rest),
        "fixture.gltf",
        &["POSITION accessor 0", "sparse indices need 6 bytes"],
    );
}
