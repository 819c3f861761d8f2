//! Bad input through the `glint render` binary: a clear one-line error naming the file and the
//! problem, a non-zero exit, no output file (and no temporary file), and no panic.

use crate::support::{Fixture, TempDir};
use serde_json::json;
use std::path::Path;
use std::process::Command;

/// A valid one-triangle document with the given positions.
fn triangle_doc(positions: &[[f32; 3]], extra: serde_json::Value) -> String {
    let mut f = Fixture::new();
    let pos = f.positions(positions);
    let idx = f.indices_u16(&[0, 1, 2]);
    let mut rest = json!({
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos}, "indices": idx}]}]
    });
    if let (Some(rest), Some(extra)) = (rest.as_object_mut(), extra.as_object()) {
        for (k, v) in extra {
            rest.insert(k.clone(), v.clone());
        }
    }
    f.gltf_text(rest)
}

/// Runs `glint render FILE -o out.png` in `dir` and checks the failure contract; returns the
/// error line.
fn render_fails(dir: &Path, file: &Path, why: &str) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_glint"))
        .args([
            "render", "--quiet", "--width", "32", "--spp", "1", "-o", "out.png",
        ])
        .arg(file)
        .current_dir(dir)
        .output()
        .expect("run glint");
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(!out.status.success(), "{why}: exit status {:?}", out.status);
    assert!(!stderr.contains("panicked"), "{why}: panic: {stderr}");
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{why}: expected one line, got: {stderr}");
    let name = file
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or_default();
    assert!(
        lines[0].contains(name),
        "{why}: error does not name {name}: {stderr}"
    );
    let leftovers: Vec<_> = std::fs::read_dir(dir)
        .expect("list")
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().to_string())
        .filter(|n| n.starts_with("out") || n.contains(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{why}: left {leftovers:?}");
    lines[0].to_string()
}

#[test]
fn bad_scenes_fail_cleanly() {
    let dir = TempDir::new("render-bad-input");
    let good = triangle_doc(
        &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        json!({}),
    );

    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "invalid.gltf",
            b"{ \"asset\": { \"version\": \"2.0\" ".to_vec(),
            "JSON",
        ),
        (
            "truncated.gltf",
            good.as_bytes()[..good.len() / 2].to_vec(),
            "JSON",
        ),
        (
            "truncated.glb",
            b"glTF\x02\x00\x00\x00\x40\x00\x00\x00".to_vec(),
            "GLB",
        ),
        (
            "nan.gltf",
            triangle_doc(
                &[[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]],
                json!({}),
            )
            .into_bytes(),
            "finite",
        ),
        (
            "inf.gltf",
            // JSON has no infinity: the accessor's max says 3e38, the data holds +inf.
            triangle_doc(
                &[[0.0, 0.0, 0.0], [f32::INFINITY, 0.0, 0.0], [0.0, 1.0, 0.0]],
                json!({}),
            )
            .replace("null", "3.0e38")
            .into_bytes(),
            "finite",
        ),
        (
            "required-ext.gltf",
            triangle_doc(
                &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
                json!({"extensionsUsed": ["EXT_lights_image_based"],
                       "extensionsRequired": ["EXT_lights_image_based"]}),
            )
            .into_bytes(),
            "EXT_lights_image_based",
        ),
        (
            "missing-bin.gltf",
            br#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":36,"uri":"nowhere.bin"}],
                "bufferViews":[{"buffer":0,"byteLength":36}],
                "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
                              "min":[0,0,0],"max":[1,1,0]}],
                "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
                "nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]}"#
                .to_vec(),
            "nowhere.bin",
        ),
        (
            "bad-accessor.gltf",
            good.replace("\"indices\":1", "\"indices\":7").into_bytes(),
            "accessor",
        ),
    ];
    for (name, bytes, expected) in cases {
        let file = dir.write(name, &bytes);
        let line = render_fails(dir.path(), &file, name);
        assert!(
            line.to_lowercase().contains(&expected.to_lowercase()),
            "{name}: error does not mention '{expected}': {line}"
        );
    }
    let missing = dir.path().join("does-not-exist.glb");
    render_fails(dir.path(), &missing, "missing file");
}
