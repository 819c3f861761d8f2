//! KHR_draco_mesh_compression: the Draco variants of the Khronos Box and Duck (made with
//! Google's encoder, `tools/make-draco-assets.mjs`, kept in `tests/draco/`) load like their
//! uncompressed twins in `../shared/khronos` within the quantisation step, and render like
//! them; a corrupted Draco stream is one clean error; a stream larger than the geometry
//! budget is refused before it is decoded, from the counts its own header declares.

use crate::support;
use crate::support::one_sided_hausdorff as one_sided_distance;

use glam::Vec3;
use glint::accel::BackendKind;
use glint::scene::Scene;
use glint::scene::gltf::{LoadOptions, MemoryFiles, SceneSelection, load_from_memory};
use std::path::{Path, PathBuf};

fn here(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/draco")
        .join(name)
}

fn shared(model: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/khronos")
        .join(model)
        .join("glTF-Binary")
        .join(format!("{model}.glb"))
}

fn load(path: &Path) -> Scene {
    glint::scene::gltf::load_with_warnings(path)
        .unwrap_or_else(|e| panic!("{e}"))
        .scene
}

/// Every triangle's world-space corners.
fn triangles(scene: &Scene) -> Vec<[Vec3; 3]> {
    let mut out = Vec::new();
    for mesh in &scene.meshes {
        assert!(mesh.instances.is_empty(), "the twins are not instanced");
        for t in &mesh.indices {
            out.push(t.map(|i| mesh.positions[i as usize]));
        }
    }
    out
}

/// Position quantisation step of the variants: the encoder's default of 14 bits over the
/// largest extent of the bounding box.
fn quantisation_step(points: &[Vec3]) -> f32 {
    let (lo, hi) = points.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    (hi - lo).max_element() / ((1 << 14) - 1) as f32
}

fn check_twins(model: &str) -> (Scene, Scene) {
    let twin = load(&shared(model));
    let draco = load(&here(&format!("{model}-draco.glb")));
    let (a, b) = (triangles(&twin), triangles(&draco));
    assert_eq!(a.len(), b.len(), "{model}: triangle count");
    let points_a: Vec<Vec3> = a.iter().flatten().copied().collect();
    let points_b: Vec<Vec3> = b.iter().flatten().copied().collect();
    let step = quantisation_step(&points_a);
    // Each decoded vertex lies within one quantisation step of an original one, and back
    // (a symmetric Hausdorff distance over the vertices).
    let there = one_sided_distance(&points_b, &points_a);
    let back = one_sided_distance(&points_a, &points_b);
    eprintln!(
        "{model}: {} triangles, step {step:e}, distances {there:e} / {back:e}",
        a.len()
    );
    assert!(
        there <= step && back <= step,
        "{model}: {there} / {back} > step {step}"
    );
    // The surface is the same: the total area agrees to the quantisation's relative error.
    let area = |t: &[[Vec3; 3]]| -> f32 {
        t.iter()
            .map(|[p, q, r]| (*q - *p).cross(*r - *p).length() / 2.0)
            .sum()
    };
    let (area_a, area_b) = (area(&a), area(&b));
    assert!(
        (area_a - area_b).abs() <= 1e-3 * area_a,
        "{model}: area {area_a} vs {area_b}"
    );
    (twin, draco)
}

/// Renders `scene` with one grey Lambert material everywhere (the variants keep the geometry,
/// not the textures), under the default camera and lights of `framing`.
fn render_plain(scene: &Scene, framing: &Scene) -> Vec<Vec3> {
    let mut scene = scene.clone();
    scene.materials = vec![support::lambert(Vec3::splat(0.5), true)];
    for mesh in &mut scene.meshes {
        mesh.material = 0;
    }
    let mut framed = framing.clone();
    glint::scene::defaults::complete(&mut framed);
    scene.lights = framed.lights.clone();
    let camera = framed.cameras.first().cloned().expect("a default camera");
    let settings = support::centre_settings(96, 96);
    support::render_with(&scene, &camera, BackendKind::Bvh, &settings)
        .image
        .pixels
}

fn compare_images(model: &str, twin: &Scene, draco: &Scene) {
    let a = render_plain(twin, twin);
    let b = render_plain(draco, twin);
    let (mut diff, mut norm, mut differing) = (0.0f64, 0.0f64, 0usize);
    for (p, q) in a.iter().zip(&b) {
        diff += f64::from((*p - *q).length_squared());
        norm += f64::from(p.length_squared());
        differing += usize::from((*p - *q).abs().max_element() > 0.05 * p.max_element().max(1e-3));
    }
    let rmse = (diff / norm.max(1e-30)).sqrt();
    eprintln!(
        "{model}: relative RMSE {rmse:e}, {differing} of {} pixels differ by > 5 %",
        a.len()
    );
    // Quantised normals (10 bits) shift shading by well under a percent; silhouettes move by
    // under a quantisation step, so only the odd edge pixel differs.
    assert!(rmse < 0.02, "{model}: relative RMSE {rmse}");
    assert!(
        differing * 100 <= a.len(),
        "{model}: {differing} pixels differ"
    );
}

#[test]
fn the_draco_box_loads_and_renders_like_its_twin() {
    let (twin, draco) = check_twins("Box");
    compare_images("Box", &twin, &draco);
}

#[test]
fn the_draco_duck_loads_and_renders_like_its_twin() {
    let (twin, draco) = check_twins("Duck");
    compare_images("Duck", &twin, &draco);
}

/// The JSON and BIN chunks of a GLB.
fn chunks(glb: &[u8]) -> (Vec<u8>, Vec<u8>) {
    let word = |i: usize| u32::from_le_bytes(glb[i..i + 4].try_into().unwrap()) as usize;
    let json_len = word(12);
    let bin_len = word(20 + json_len);
    (
        glb[20..20 + json_len].to_vec(),
        glb[28 + json_len..28 + json_len + bin_len].to_vec(),
    )
}

fn glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let mut json = json.to_vec();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let mut out = b"glTF".to_vec();
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&((28 + json.len() + bin.len()) as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

fn load_bytes(bytes: &[u8], options: &LoadOptions) -> Result<Scene, String> {
    load_from_memory(
        bytes,
        "duck.glb",
        &MemoryFiles::new(),
        &SceneSelection::default(),
        options,
    )
    .map(|l| l.scene)
    .map_err(|e| e.to_string())
}

#[test]
fn a_corrupted_draco_stream_is_one_clean_error() {
    let original = std::fs::read(here("Duck-draco.glb")).unwrap();
    let (json, bin) = chunks(&original);
    let doc: serde_json::Value = serde_json::from_slice(&json).unwrap();
    let view =
        doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["bufferView"]
            .as_u64()
            .unwrap() as usize;
    let offset = doc["bufferViews"][view]["byteOffset"].as_u64().unwrap_or(0) as usize;
    let length = doc["bufferViews"][view]["byteLength"].as_u64().unwrap() as usize;
    let mut refused = 0;
    // Damage inside the stream: its header, its connectivity, its attributes; and cut short.
    for (at, value) in [
        (0, 0u8),
        (8, 0xff),
        (20, 0x55),
        (length / 3, 0xff),
        (length / 2, 0),
    ] {
        let mut bin = bin.clone();
        bin[offset + at] = value;
        match load_bytes(&glb(&json, &bin), &LoadOptions::default()) {
            Ok(_) => {} // Some damage decodes to other, valid geometry.
            Err(message) => {
                refused += 1;
                assert!(!message.contains('\n'), "{message}");
                assert!(message.starts_with("duck.glb"), "{message}");
            }
        }
    }
    assert!(refused >= 2, "most damage is refused");
    let mut cut = doc.clone();
    cut["bufferViews"][view]["byteLength"] = (length / 2).into();
    let message = load_bytes(
        &glb(cut.to_string().as_bytes(), &bin),
        &LoadOptions::default(),
    )
    .expect_err("half a stream");
    assert!(!message.contains('\n'), "{message}");
    assert!(
        message.contains("KHR_draco_mesh_compression") && message.contains("does not decode"),
        "{message}"
    );
}

#[test]
fn a_stream_over_the_geometry_budget_is_refused_before_decoding() {
    let bytes = std::fs::read(here("Duck-draco.glb")).unwrap();
    let options = LoadOptions {
        max_geometry_bytes: 10_000,
        ..LoadOptions::default()
    };
    let message = load_bytes(&bytes, &options).expect_err("over the budget");
    assert!(!message.contains('\n'), "{message}");
    assert!(message.contains("geometry"), "{message}");
}

/// The stream's own declared counts are charged against the geometry budget before the
/// decoder allocates: Google's 130-byte Box stream declares 24 points (NORMAL and POSITION,
/// 576 bytes decoded) and 12 faces; a 200-byte budget allows 16 points, and the first
/// attribute's 288 bytes already pass it. The JSON accessors
/// are made to claim 3 points and 3 indices, so the refusal can only come from the stream's
/// header. It is one line, says the decoder declined (not that the data is corrupt) and names
/// the budget; the same file with its own JSON loads under a budget that fits.
#[test]
fn a_draco_stream_declaring_more_points_than_the_budget_is_refused_before_decoding() {
    let original = std::fs::read(here("Box-draco.glb")).unwrap();
    let (json, bin) = chunks(&original);
    let mut doc: serde_json::Value = serde_json::from_slice(&json).unwrap();
    assert_eq!(doc["bufferViews"][0]["byteLength"], 130, "the Box's stream");
    for accessor in doc["accessors"].as_array_mut().unwrap() {
        accessor["count"] = 3.into();
    }
    let budget = 200;
    let options = LoadOptions {
        max_geometry_bytes: budget,
        ..LoadOptions::default()
    };
    let message = load_bytes(&glb(doc.to_string().as_bytes(), &bin), &options)
        .expect_err("24 declared points over a 16-point budget");
    eprintln!("{message}");
    assert!(!message.contains('\n'), "{message}");
    assert!(message.starts_with("duck.glb"), "{message}");
    assert!(
        message.contains("KHR_draco_mesh_compression")
            && message.contains(&format!(
                "decodes to more than the {budget} bytes left of the scene's geometry budget"
            ))
            // 24 declared points × one VEC3 of f32: the stream's count, not the JSON's 3.
            && message.contains("288 decoded attribute bytes, over the caller's ceiling")
            && message.contains("--max-geometry-bytes")
            && !message.contains("does not decode"),
        "{message}"
    );
    // The same stream under a budget that holds it (576 attribute bytes + 12 faces × 12).
    let fits = LoadOptions {
        max_geometry_bytes: 10_000,
        ..LoadOptions::default()
    };
    let scene = load_bytes(&original, &fits).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(triangles(&scene).len(), 12);
}
