//! `glint render` end to end, through the built binary.

use std::path::{Path, PathBuf};

use crate::support::{files_in, glint, stderr};

#[test]
fn unknown_output_extension_fails_without_writing() {
    let dir = tempfile::tempdir().unwrap();
    let out = glint(&["render", "-o", "picture.jpg", "--quiet"], dir.path());
    assert!(!out.status.success());
    let message = stderr(&out);
    assert!(
        message.contains("picture.jpg") && message.contains(".png or .exr"),
        "{message}"
    );
    assert!(files_in(dir.path()).is_empty());
}

#[test]
fn output_in_a_missing_folder_fails_without_writing() {
    let dir = tempfile::tempdir().unwrap();
    let out = glint(&["render", "-o", "missing/dir/out.png"], dir.path());
    assert!(!out.status.success());
    assert!(stderr(&out).contains("does not exist"), "{}", stderr(&out));
    assert!(files_in(dir.path()).is_empty());
}

#[test]
fn conflicting_options_fail_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let aov_png = glint(
        &["render", "-o", "a.png", "--aov", "albedo,depth"],
        dir.path(),
    );
    assert!(!aov_png.status.success());
    assert!(stderr(&aov_png).contains("EXR"), "{}", stderr(&aov_png));
    let png16_exr = glint(&["render", "-o", "a.exr", "--png16"], dir.path());
    assert!(!png16_exr.status.success());
    let zero_spp = glint(&["render", "-o", "a.png", "--spp", "0"], dir.path());
    assert!(!zero_spp.status.success());
    let bad_backend = glint(&["render", "-o", "a.png", "--backend", "optix"], dir.path());
    assert!(!bad_backend.status.success());
    assert!(files_in(dir.path()).is_empty());
}

/// A 2×2 quad at y = 0 facing +Y, a camera at (0, 3, 3) looking at the origin, and a 20 W/sr
/// point light 2 above the origin, as .gltf + .bin in `dir`.
fn write_quad_scene(dir: &Path) -> PathBuf {
    let positions: [[f32; 3]; 4] = [
        [-1.0, 0.0, -1.0],
        [1.0, 0.0, -1.0],
        [1.0, 0.0, 1.0],
        [-1.0, 0.0, 1.0],
    ];
    let indices: [u16; 6] = [0, 3, 2, 0, 2, 1];
    let mut bin = Vec::new();
    positions
        .iter()
        .flatten()
        .for_each(|v| bin.extend(v.to_le_bytes()));
    indices.iter().for_each(|i| bin.extend(i.to_le_bytes()));
    std::fs::write(dir.join("quad.bin"), &bin).unwrap();
    let gltf = r#"{
  "asset": {"version": "2.0"},
  "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular"],
  "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 20.0}]}},
  "scene": 0,
  "scenes": [{"nodes": [0, 1, 2]}],
  "nodes": [
    {"mesh": 0},
    {"camera": 0, "translation": [0, 3, 3], "rotation": [-0.38268343, 0, 0, 0.9238795]},
    {"translation": [0, 2, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}}
  ],
  "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
  "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 1}, "extensions": {"KHR_materials_specular": {"specularFactor": 0}}}],
  "buffers": [{"uri": "quad.bin", "byteLength": 60}],
  "bufferViews": [
    {"buffer": 0, "byteOffset": 0, "byteLength": 48},
    {"buffer": 0, "byteOffset": 48, "byteLength": 12}
  ],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, 0, -1], "max": [1, 0, 1]},
    {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}
  ]
}"#;
    let path = dir.join("quad.gltf");
    std::fs::write(&path, gltf).unwrap();
    path
}

#[test]
fn renders_a_gltf_scene_to_exr_with_the_closed_form_at_the_centre() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_quad_scene(dir.path());
    let scene = scene.to_str().unwrap();
    for backend in ["embree", "bvh"] {
        let out = glint(
            &[
                "render",
                scene,
                "-o",
                "quad.exr",
                "--width",
                "33",
                "--height",
                "33",
                "--spp",
                "4",
                "--backend",
                backend,
                "--aov",
                "albedo,normal,depth",
                "--quiet",
                // The material has no specular lobe (KHR_materials_specular factor 0), so its
                // glTF BRDF is Lambertian: the closed form below. Direct light only.
                "--integrator",
                "direct",
            ],
            dir.path(),
        );
        assert!(out.status.success(), "{backend}: {}", stderr(&out));
        assert!(out.stderr.is_empty(), "--quiet printed: {}", stderr(&out));
        let image =
            exr::prelude::read_first_flat_layer_from_file(dir.path().join("quad.exr")).unwrap();
        let layer = &image.layer_data;
        let red = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.eq("R"))
            .unwrap();
        let centre: f32 = red.sample_data.values_as_f32().nth(16 * 33 + 16).unwrap();
        // ρ/π · I / d² with d = 2 straight above: 0.8/π · 20/4. The pixel spans a little of
        // the falloff around the centre.
        let want = 0.8 / std::f32::consts::PI * 5.0;
        assert!(
            (centre / want - 1.0).abs() < 5e-3,
            "{backend}: {centre} vs {want}"
        );
        // R, G, B, A and the albedo, normal and depth AOVs.
        assert_eq!(layer.channel_data.list.len(), 11);
    }
    assert_eq!(files_in(dir.path()), ["quad.bin", "quad.exr", "quad.gltf"]);
}

#[test]
fn renders_png_with_the_camera_aspect_and_reports_on_stderr() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_quad_scene(dir.path());
    let out = glint(
        &[
            "render",
            scene.to_str().unwrap(),
            "-o",
            "quad.png",
            "--width",
            "64",
            "--png16",
            "--integrator",
            "direct",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let message = stderr(&out);
    assert!(
        message.contains("Mrays/s") && message.contains("shadow"),
        "{message}"
    );
    assert!(
        message.contains("no emitters: no area-light sampling"),
        "{message}"
    );
    // The path tracer says which light sampling the scene did not need.
    let path = glint(
        &[
            "render",
            scene.to_str().unwrap(),
            "-o",
            "path.png",
            "--width",
            "16",
        ],
        dir.path(),
    );
    assert!(path.status.success(), "{}", stderr(&path));
    let message = stderr(&path);
    assert!(
        message.contains("bounce rays")
            && message.contains("no emitters: no area-light sampling")
            && message.contains("no environment: no environment sampling"),
        "{message}"
    );
    let png = image::open(dir.path().join("quad.png")).unwrap();
    // No aspectRatio in the file: 16:9.
    assert_eq!((png.width(), png.height()), (64, 36));
    assert_eq!(png.color(), image::ColorType::Rgb16);
}

/// The summary line and the EXR header (`glint.brdf`) say which metallic-roughness model
/// rendered: the energy-compensated default or `--brdf spec`.
#[test]
fn the_summary_and_the_exr_header_name_the_brdf() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_quad_scene(dir.path());
    for (args, name) in [(&[][..], "compensated"), (&["--brdf", "spec"][..], "spec")] {
        let mut all = vec![
            "render",
            scene.to_str().unwrap(),
            "-o",
            "b.exr",
            "--width",
            "8",
            "--height",
            "8",
            "--spp",
            "1",
        ];
        all.extend_from_slice(args);
        let out = glint(&all, dir.path());
        assert!(out.status.success(), "{}", stderr(&out));
        let message = stderr(&out);
        assert!(message.contains(&format!("BRDF {name}")), "{message}");
        let image =
            exr::prelude::read_first_flat_layer_from_file(dir.path().join("b.exr")).unwrap();
        let value = image
            .layer_data
            .attributes
            .other
            .iter()
            .find(|(k, _)| **k == *"glint.brdf")
            .map(|(_, v)| format!("{v:?}"))
            .unwrap_or_default();
        assert!(value.contains(name), "glint.brdf is '{value}', want {name}");
    }
}

#[test]
fn a_missing_camera_index_fails_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_quad_scene(dir.path());
    let out = glint(
        &[
            "render",
            scene.to_str().unwrap(),
            "-o",
            "x.png",
            "--camera",
            "3",
        ],
        dir.path(),
    );
    assert!(!out.status.success());
    assert!(stderr(&out).contains("--camera 3"), "{}", stderr(&out));
    assert!(!dir.path().join("x.png").exists());
}

#[test]
fn renders_the_demo_scene_without_arguments() {
    let dir = tempfile::tempdir().unwrap();
    let out = glint(&["render", "--width", "64", "--spp", "1"], dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let png = image::open(dir.path().join("glint-demo.png")).unwrap();
    assert_eq!(png.width(), 64);
    assert_eq!(files_in(dir.path()), ["glint-demo.png"]);
}
