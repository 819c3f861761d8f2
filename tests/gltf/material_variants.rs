//! KHR_materials_variants and `glint info` (issue 35), end to end through the built binary,
//! on a file made here: a quad whose primitive maps the variants "red", "green" and "blue" to
//! three unlit materials (unlit: the pixels are the base colour exactly, no noise), its own
//! material white. Each `--variant` renders its colour (mean over the quad's pixels, both
//! backends); no `--variant` renders the default; a batch sweep over `variant` writes one
//! image per variant, each in its colour; an unknown name fails in one line that lists the
//! names, with a non-zero exit and no file; `glint info --json` lists the variants and sorts
//! the extensions into read, ignored and refused.

use crate::support::{Fixture, glint, stderr};
use glam::Vec3;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

const SIZE: usize = 16;

fn unlit(name: &str, color: [f32; 3]) -> Value {
    json!({
        "name": name,
        "pbrMetallicRoughness": {"baseColorFactor": [color[0], color[1], color[2], 1.0]},
        "extensions": {"KHR_materials_unlit": {}}
    })
}

/// The quad file, with `extra` merged into its root (e.g. more extensions), written to `dir`.
fn write_file(dir: &Path, extra: Value) -> PathBuf {
    let mut fixture = Fixture::new();
    let position = fixture.positions(&[
        [-1.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
    ]);
    let indices = fixture.indices_u16(&[0, 1, 2, 0, 2, 3]);
    let mut rest = json!({
        "extensionsUsed": ["KHR_materials_unlit", "KHR_materials_variants"],
        "extensions": {"KHR_materials_variants": {"variants": [
            {"name": "red"}, {"name": "green"}, {"name": "blue"}
        ]}},
        "scenes": [{"name": "stage", "nodes": [0, 1]}],
        "scene": 0,
        "nodes": [
            {"name": "quad", "mesh": 0},
            {"name": "eye", "camera": 0, "translation": [0.0, 0.0, 5.0]}
        ],
        "cameras": [{"type": "orthographic",
                     "orthographic": {"xmag": 2.0, "ymag": 2.0, "znear": 0.1, "zfar": 10.0}}],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": position},
            "indices": indices,
            "material": 0,
            "extensions": {"KHR_materials_variants": {"mappings": [
                {"material": 1, "variants": [0]},
                {"material": 2, "variants": [1]},
                {"material": 3, "variants": [2]}
            ]}}
        }]}],
        "materials": [
            unlit("white", [1.0, 1.0, 1.0]),
            unlit("red", [0.8, 0.1, 0.1]),
            unlit("green", [0.1, 0.7, 0.2]),
            unlit("blue", [0.1, 0.2, 0.9])
        ]
    });
    if let (Some(rest), Some(extra)) = (rest.as_object_mut(), extra.as_object()) {
        for (k, v) in extra {
            rest.insert(k.clone(), v.clone());
        }
    }
    let path = dir.join("variants.gltf");
    std::fs::write(&path, fixture.gltf_text(rest)).expect("write the file");
    path
}

/// The mean colour of the quad's pixels (the middle half of the image).
fn quad_mean(path: &Path) -> Vec3 {
    let image = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |size, _| vec![Vec3::ZERO; size.width() * size.height()],
        |pixels, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            pixels[pos.y() * SIZE + pos.x()] = Vec3::new(r, g, b);
        },
    )
    .expect("read the EXR");
    let pixels = image.layer_data.channel_data.pixels;
    let quarter = SIZE / 4;
    let mut sum = Vec3::ZERO;
    let mut n = 0.0;
    for y in quarter + 1..SIZE - quarter - 1 {
        for x in quarter + 1..SIZE - quarter - 1 {
            sum += pixels[y * SIZE + x];
            n += 1.0;
        }
    }
    sum / n
}

const COLORS: [(&str, [f32; 3]); 3] = [
    ("red", [0.8, 0.1, 0.1]),
    ("green", [0.1, 0.7, 0.2]),
    ("blue", [0.1, 0.2, 0.9]),
];

fn assert_color(got: Vec3, want: [f32; 3], what: &str) {
    assert!(
        (got - Vec3::from(want)).abs().max_element() < 1e-3,
        "{what}: mean {got:?}, expected {want:?}"
    );
}

#[test]
fn each_variant_renders_its_material_and_none_renders_the_default() {
    let dir = tempfile::tempdir().unwrap();
    let file = write_file(dir.path(), json!({}));
    let file = file.to_str().unwrap();
    let size = SIZE.to_string();
    for backend in ["embree", "bvh"] {
        let mut cases: Vec<(Option<&str>, [f32; 3])> =
            COLORS.iter().map(|(n, c)| (Some(*n), *c)).collect();
        cases.push((None, [1.0, 1.0, 1.0]));
        for (variant, color) in cases {
            let output = format!("{}-{backend}.exr", variant.unwrap_or("default"));
            let mut args = vec![
                "render",
                file,
                "-o",
                &output,
                "--width",
                &size,
                "--height",
                &size,
                "--spp",
                "2",
                "--backend",
                backend,
                "--quiet",
            ];
            if let Some(v) = variant {
                args.extend(["--variant", v]);
            }
            let out = glint(&args, dir.path());
            assert!(
                out.status.success(),
                "{backend} {variant:?}: {}",
                stderr(&out)
            );
            assert_color(
                quad_mean(&dir.path().join(&output)),
                color,
                &format!("{backend} {variant:?}"),
            );
        }
    }
}

#[test]
fn a_sweep_over_variants_writes_one_image_per_variant() {
    let dir = tempfile::tempdir().unwrap();
    let file = write_file(dir.path(), json!({}));
    let jobs = format!(
        r#"[[sweep]]
scene = "{}"
width = {SIZE}
height = {SIZE}
spp = 1
variant = ["red", "green", "blue"]
output = "out/quad-{{variant}}.exr"
"#,
        file.display()
    );
    std::fs::write(dir.path().join("jobs.toml"), jobs).unwrap();
    let out = glint(&["batch", "jobs.toml", "--quiet"], dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let mut written: Vec<String> = std::fs::read_dir(dir.path().join("out"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".exr"))
        .collect();
    written.sort();
    assert_eq!(
        written,
        ["quad-blue.exr", "quad-green.exr", "quad-red.exr"],
        "one image per variant"
    );
    for (name, color) in COLORS {
        let path = dir.path().join(format!("out/quad-{name}.exr"));
        assert_color(quad_mean(&path), color, name);
    }
}

#[test]
fn an_unknown_variant_is_one_line_listing_the_names_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let file = write_file(dir.path(), json!({}));
    let out = glint(
        &[
            "render",
            file.to_str().unwrap(),
            "-o",
            "x.exr",
            "--variant",
            "purple",
            "--quiet",
        ],
        dir.path(),
    );
    assert!(!out.status.success());
    let message = stderr(&out);
    assert_eq!(message.trim_end().lines().count(), 1, "one line: {message}");
    assert!(
        message.contains("\"purple\"") && message.contains("\"red\", \"green\", \"blue\""),
        "{message}"
    );
    assert!(!dir.path().join("x.exr").exists());
    // A file without variants says so.
    let plain = dir.path().join("plain");
    std::fs::create_dir(&plain).unwrap();
    let mut doc: Value = serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    doc.as_object_mut().unwrap().remove("extensions");
    std::fs::write(plain.join("plain.gltf"), doc.to_string()).unwrap();
    let out = glint(
        &[
            "render",
            "plain.gltf",
            "-o",
            "x.exr",
            "--variant",
            "red",
            "--quiet",
        ],
        &plain,
    );
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("no KHR_materials_variants"),
        "{}",
        stderr(&out)
    );
    assert!(!plain.join("x.exr").exists());
}

#[test]
fn info_lists_the_variants_cameras_and_extensions() {
    let dir = tempfile::tempdir().unwrap();
    let file = write_file(
        dir.path(),
        json!({
            "extensionsUsed": ["KHR_materials_unlit", "KHR_materials_variants", "EXT_foo", "EXT_bar"],
            "extensionsRequired": ["EXT_bar"]
        }),
    );
    let out = glint(&["info", "--json", file.to_str().unwrap()], dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let info: Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    assert_eq!(info["variants"], json!(["red", "green", "blue"]));
    assert_eq!(info["default_scene"], json!(0));
    assert_eq!(info["scenes"][0]["name"], json!("stage"));
    assert_eq!(info["scenes"][0]["nodes"], json!(2));
    assert_eq!(info["cameras"][0]["kind"], json!("orthographic"));
    assert_eq!(info["cameras"][0]["node"], json!(1));
    assert_eq!(info["triangles"], json!(2));
    assert_eq!(info["materials"], json!(4));
    assert_eq!(
        info["extensions"]["read"],
        json!(["KHR_materials_unlit", "KHR_materials_variants"])
    );
    assert_eq!(info["extensions"]["ignored"], json!(["EXT_foo"]));
    assert_eq!(info["extensions"]["refused"], json!(["EXT_bar"]));
    // The text form names them too; rendering the file is refused.
    let text = glint(&["info", file.to_str().unwrap()], dir.path());
    let text = String::from_utf8_lossy(&text.stdout).into_owned();
    assert!(
        text.contains("variants: \"red\", \"green\", \"blue\"")
            && text.contains("extensions refused: EXT_bar"),
        "{text}"
    );
    let render = glint(
        &["render", file.to_str().unwrap(), "-o", "x.exr", "--quiet"],
        dir.path(),
    );
    assert!(!render.status.success());
}
