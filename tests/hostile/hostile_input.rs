//! Regression tests for hostile input (issue 11), through the `glint render` binary: each
//! input gives one error line naming the file and the item, a non-zero exit and no output
//! file; or, where a value is clamped, a render without inf or NaN.

use crate::mutate;

use crate::support::{Fixture, TempDir, data_uri, glint, png};
use serde_json::{Value, json};
use std::path::Path;
use std::process::{Command, Output};

/// A one-triangle scene with `extra` merged into the document's top level.
fn triangle_doc(positions: &[[f32; 3]], extra: Value) -> Value {
    let mut f = Fixture::new();
    let pos = f.positions(positions);
    let idx = f.indices_u16(&[0, 1, 2]);
    let mut doc = f.document(json!({
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos}, "indices": idx}]}]
    }));
    if let (Some(doc), Some(extra)) = (doc.as_object_mut(), extra.as_object()) {
        for (k, v) in extra {
            doc.insert(k.clone(), v.clone());
        }
    }
    doc
}

const TRIANGLE: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

/// Renders `file` (in `dir`) with `extra` options and checks the failure contract: non-zero
/// exit, no panic, one line naming the file and containing each of `expected`, no output or
/// temporary file.
fn render_fails(dir: &Path, file: &str, extra: &[&str], expected: &[&str]) {
    let out = glint(&render_args(file, extra), dir);
    assert_clean_failure(dir, file, &out, expected);
}

/// The arguments of a 16 × 16, one-sample render of `file` to `out.png`.
fn render_args<'a>(file: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "render", "--quiet", "--width", "16", "--height", "16", "--spp", "1", "-o", "out.png",
    ];
    args.extend_from_slice(extra);
    args.push(file);
    args
}

/// The address space a capped run may use: 4 GiB, in KiB for `ulimit -v`. Enough for a
/// small render; an allocation of gigabytes fails (an abort) instead of exhausting the machine.
const CAP_KIB: u64 = 4 << 20;

/// Most seconds a refusal of a tiny hostile input may take (a debug build, a busy machine).
const QUICK_SECONDS: u64 = 60;

/// Like [`render_fails`], with glint's address space capped at [`CAP_KIB`] and the run killed
/// after [`QUICK_SECONDS`]: a file of a few KB must not cost gigabytes or minutes.
fn render_fails_capped(dir: &Path, file: &str, extra: &[&str], expected: &[&str]) {
    let started = std::time::Instant::now();
    let out = Command::new("bash")
        .arg("-c")
        .arg(format!(
            "ulimit -v {CAP_KIB} && exec timeout -s KILL {QUICK_SECONDS} \"$0\" \"$@\""
        ))
        .arg(env!("CARGO_BIN_EXE_glint"))
        .args(render_args(file, extra))
        .args(["--threads", "1"])
        .env("MALLOC_ARENA_MAX", "2")
        .current_dir(dir)
        .output()
        .expect("run glint under ulimit");
    let seconds = started.elapsed().as_secs();
    assert!(seconds < QUICK_SECONDS, "{file}: took {seconds} s");
    assert_clean_failure(dir, file, &out, expected);
}

/// The failure contract: non-zero exit, no signal, no panic, one line naming the file and
/// containing each of `expected`, no output or temporary file.
fn assert_clean_failure(dir: &Path, file: &str, out: &Output, expected: &[&str]) {
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(
        !out.status.success(),
        "{file}: exit status {:?}",
        out.status
    );
    assert!(
        out.status.code().is_some(),
        "{file}: killed by a signal: {stderr}"
    );
    assert!(!stderr.contains("panicked"), "{file}: panic: {stderr}");
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{file}: expected one line, got: {stderr}");
    assert!(
        lines[0].contains(file),
        "{file}: error does not name the file: {stderr}"
    );
    for e in expected {
        assert!(
            lines[0].contains(e),
            "{file}: error lacks \"{e}\": {stderr}"
        );
    }
    let leftovers: Vec<_> = std::fs::read_dir(dir)
        .expect("list")
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().to_string())
        .filter(|n| n.starts_with("out") || n.contains(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{file}: left {leftovers:?}");
}

fn write_json(dir: &TempDir, name: &str, doc: &Value) {
    dir.write(name, serde_json::to_string(doc).expect("json").as_bytes());
}

#[test]
fn camera_without_its_projection_object() {
    let dir = TempDir::new("hostile-camera");
    let mut doc = triangle_doc(&TRIANGLE, json!({"cameras": [{"type": "perspective"}]}));
    doc["nodes"] = json!([{"mesh": 0}, {"camera": 0, "translation": [0, 0, 3]}]);
    doc["scenes"] = json!([{"nodes": [0, 1]}]);
    write_json(&dir, "camera.gltf", &doc);
    render_fails(dir.path(), "camera.gltf", &[], &["camera 0", "perspective"]);
}

#[test]
fn images_without_mime_type_or_source() {
    let dir = TempDir::new("hostile-image");
    let texel = png(1, 1, &[255, 0, 0, 255]);
    let mut fixture = Fixture::new();
    let pos = fixture.positions(&TRIANGLE);
    let uv = fixture.floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC2", 2);
    let view = fixture.view(&texel);
    let rest = |image: Value| {
        json!({
            "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": pos, "TEXCOORD_0": uv}, "material": 0}]}],
            "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
            "textures": [{"source": 0}],
            "images": [image]
        })
    };
    // A GLB whose image lives in a buffer view but has no mimeType.
    let mut doc = fixture.document(rest(json!({"bufferView": view})));
    doc["buffers"] = json!([{"byteLength": fixture.bin.len()}]);
    let glb = mutate::glb(
        serde_json::to_string(&doc).expect("json").as_bytes(),
        Some(&fixture.bin),
    );
    dir.write("no-mime.glb", &glb);
    render_fails(dir.path(), "no-mime.glb", &[], &["image 0", "mimeType"]);
    // An image with neither uri nor bufferView.
    write_json(
        &dir,
        "no-source.gltf",
        &fixture.document(rest(json!({"name": "x"}))),
    );
    render_fails(dir.path(), "no-source.gltf", &[], &["image 0", "neither"]);
}

/// A node at 1e30, and a node scaled by 1e30, are refused on both backends before any ray is
/// traced (Embree used to abort on the rays, obvhs to index out of bounds in its build).
#[test]
fn huge_node_translation_and_scale_on_both_backends() {
    let dir = TempDir::new("hostile-huge");
    let mut far = triangle_doc(&TRIANGLE, json!({}));
    far["nodes"][0]["translation"] = json!([1e30, 0, 0]);
    write_json(&dir, "far.gltf", &far);
    let mut scaled = triangle_doc(&TRIANGLE, json!({}));
    scaled["nodes"][0]["scale"] = json!([1e30, 1e30, 1e30]);
    write_json(&dir, "scaled.gltf", &scaled);
    let mut camera = triangle_doc(
        &TRIANGLE,
        json!({"cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}]}),
    );
    camera["nodes"] = json!([{"mesh": 0}, {"camera": 0, "translation": [0, 0, 1e30]}]);
    camera["scenes"] = json!([{"nodes": [0, 1]}]);
    write_json(&dir, "far-camera.gltf", &camera);
    for backend in glint::accel::BackendKind::available() {
        let b = ["--backend", backend.name()];
        render_fails(dir.path(), "far.gltf", &b, &["node 0", "precision"]);
        render_fails(dir.path(), "scaled.gltf", &b, &["node 0", "precision"]);
        render_fails(dir.path(), "far-camera.gltf", &b, &["camera", "precision"]);
    }
}

/// Zeroed geometry (200 000 triangles at the origin) builds on obvhs and renders: the
/// zero-area triangles stay out of its tree (the build used to take 9–20 s). A hang would
/// show as the test harness's timeout, not as a timing assertion.
#[test]
fn zeroed_geometry_on_obvhs() {
    let positions = vec![glam::Vec3::ZERO; 3];
    let indices = vec![[0u32, 1, 2]; 200_000];
    let mesh = glint::accel::TriangleMesh {
        positions: &positions,
        indices: &indices,
        instances: &[],
    };
    let accel = glint::accel::build(glint::accel::BackendKind::Bvh, &[mesh], Default::default())
        .expect("zeroed geometry builds");
    assert_eq!(accel.triangle_count(), 200_000);
    let ray = glint::accel::Ray::new(glam::Vec3::new(0.0, 0.0, 1.0), glam::Vec3::NEG_Z);
    assert!(accel.intersect(&ray).is_none());
    assert!(!accel.occluded(&ray));
}

/// CRC-32 (ISO-HDLC) for hand-made PNG chunks.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// A PNG header of `width`×`height` 1-bit grey texels followed by a short IDAT: enough for
/// the header check, which must refuse it before any texel memory is allocated.
fn huge_png(width: u32, height: u32) -> Vec<u8> {
    let chunk = |out: &mut Vec<u8>, ty: &[u8], data: &[u8]| {
        out.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let mut body = ty.to_vec();
        body.extend_from_slice(data);
        out.extend_from_slice(&body);
        out.extend_from_slice(&crc32(&body).to_be_bytes());
    };
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&width.to_be_bytes());
    ihdr.extend_from_slice(&height.to_be_bytes());
    ihdr.extend_from_slice(&[1, 0, 0, 0, 0]);
    chunk(&mut out, b"IHDR", &ihdr);
    chunk(&mut out, b"IDAT", &[0x78, 0x01, 0x03, 0x00]);
    chunk(&mut out, b"IEND", &[]);
    out
}

#[test]
fn texture_over_the_pixel_budget() {
    let dir = TempDir::new("hostile-png");
    let mut fixture = Fixture::new();
    let pos = fixture.positions(&TRIANGLE);
    let uv = fixture.floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC2", 2);
    let doc = fixture.document(json!({
        "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos, "TEXCOORD_0": uv}, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "textures": [{"source": 0}],
        "images": [{"uri": data_uri("image/png", &huge_png(20000, 20000))}]
    }));
    write_json(&dir, "huge-png.gltf", &doc);
    render_fails(
        dir.path(),
        "huge-png.gltf",
        &[],
        &["image 0", "20000×20000", "--max-texture-pixels"],
    );
    // A lower budget refuses a small image too, and names the option.
    let small = fixture.document(json!({
        "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos, "TEXCOORD_0": uv}, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "textures": [{"source": 0}],
        "images": [{"uri": data_uri("image/png", &png(4, 4, &[128; 64]))}]
    }));
    write_json(&dir, "small-png.gltf", &small);
    render_fails(
        dir.path(),
        "small-png.gltf",
        &["--max-texture-pixels", "15"],
        &["image 0", "--max-texture-pixels 16"],
    );
}

fn buffer_uri_doc(uri: &str) -> Value {
    let mut doc = triangle_doc(&TRIANGLE, json!({}));
    doc["buffers"][0]["uri"] = json!(uri);
    doc
}

#[test]
fn device_fifo_and_absolute_uris_are_refused_without_blocking() {
    let dir = TempDir::new("hostile-uri");
    write_json(
        &dir,
        "zero.gltf",
        &buffer_uri_doc("../../../../../../../../dev/zero"),
    );
    render_fails(
        dir.path(),
        "zero.gltf",
        &[],
        &["buffer 0", "not a regular file"],
    );
    write_json(&dir, "absolute.gltf", &buffer_uri_doc("/etc/passwd"));
    render_fails(dir.path(), "absolute.gltf", &[], &["buffer 0", "absolute"]);
    let fifo = dir.path().join("pipe.bin");
    let made = Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("run mkfifo");
    assert!(made.success(), "mkfifo failed");
    write_json(&dir, "fifo.gltf", &buffer_uri_doc("pipe.bin"));
    render_fails(
        dir.path(),
        "fifo.gltf",
        &[],
        &["buffer 0", "not a regular file"],
    );
    std::fs::remove_file(&fifo).expect("remove fifo");
    // The scene file itself may not be a device either.
    let out = glint(
        &["render", "--quiet", "-o", "out.png", "/dev/zero"],
        dir.path(),
    );
    assert!(!out.status.success() && out.status.code().is_some());
    assert!(String::from_utf8_lossy(&out.stderr).contains("not a regular file"));
}

#[test]
fn uris_outside_the_asset_root() {
    let dir = TempDir::new("hostile-root");
    std::fs::create_dir_all(dir.path().join("root")).expect("mkdir");
    let good = triangle_doc(&TRIANGLE, json!({}));
    let uri = good["buffers"][0]["uri"]
        .as_str()
        .expect("data uri")
        .to_string();
    let bytes = base64::Engine::decode(
        &base64::engine::general_purpose::STANDARD,
        uri.split_once(";base64,").expect("base64").1,
    )
    .expect("decode");
    dir.write("elsewhere.bin", &bytes);
    dir.write("root/inside.bin", &bytes);
    write_json(
        &dir,
        "root/escape.gltf",
        &buffer_uri_doc("../elsewhere.bin"),
    );
    write_json(
        &dir,
        "root/escape-pct.gltf",
        &buffer_uri_doc("..%2Felsewhere.bin"),
    );
    write_json(&dir, "root/inside.gltf", &buffer_uri_doc("inside.bin"));
    let root = ["--asset-root", "root"];
    render_fails(
        dir.path(),
        "root/escape.gltf",
        &root,
        &["buffer 0", "../elsewhere.bin", "outside the asset root"],
    );
    render_fails(
        dir.path(),
        "root/escape-pct.gltf",
        &root,
        &["buffer 0", "outside the asset root"],
    );
    // Inside the root it loads; without a root, relative `../` still resolves.
    for (file, args) in [
        ("root/inside.gltf", &root[..]),
        ("root/escape.gltf", &[][..]),
    ] {
        let mut a = vec![
            "render", "--quiet", "--width", "8", "--height", "8", "--spp", "1", "-o", "ok.png",
        ];
        a.extend_from_slice(args);
        a.push(file);
        let out = glint(&a, dir.path());
        assert!(
            out.status.success(),
            "{file}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

/// A material factor of 1e39 (+inf as f32) is clamped with a warning; the render holds no
/// inf or NaN.
#[test]
fn overflowing_material_factor_is_clamped() {
    let dir = TempDir::new("hostile-factor");
    let mut doc = triangle_doc(&TRIANGLE, json!({}));
    doc["materials"] = json!([{"emissiveFactor": [1e39, 1, 1], "pbrMetallicRoughness": {"baseColorFactor": [1e39, 0.5, 0.5, 1]}}]);
    doc["meshes"][0]["primitives"][0]["material"] = json!(0);
    write_json(&dir, "factor.gltf", &doc);
    let out = glint(
        &[
            "render",
            "--width",
            "16",
            "--height",
            "16",
            "--spp",
            "2",
            "-o",
            "out.exr",
            "factor.gltf",
        ],
        dir.path(),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("clamped"), "no clamping warning: {stderr}");
    let image = exr::prelude::read_first_rgba_layer_from_file(
        dir.path().join("out.exr"),
        |size, _| vec![[0.0f32; 4]; size.width() * size.height()],
        |pixels: &mut Vec<[f32; 4]>, pos, (r, g, b, a): (f32, f32, f32, f32)| {
            pixels[pos.y() * 16 + pos.x()] = [r, g, b, a];
        },
    )
    .expect("read exr");
    let pixels = &image.layer_data.channel_data.pixels;
    assert!(
        pixels.iter().flatten().all(|c| c.is_finite()),
        "inf or NaN pixels"
    );
    assert!(
        pixels.iter().any(|p| p[0] > 0.0),
        "the emitter is not visible"
    );
}

#[test]
fn spp_and_size_upper_bounds() {
    let dir = TempDir::new("hostile-spp");
    for args in [
        &["render", "--quiet", "--spp", "4294967295", "-o", "out.png"][..],
        &["render", "--quiet", "--width", "100000", "-o", "out.png"][..],
        &[
            "render", "--quiet", "--width", "60000", "--height", "60000", "-o", "out.png",
        ][..],
    ] {
        let out = glint(args, dir.path());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} accepted");
        assert!(stderr.contains("limit"), "{args:?}: {stderr}");
        assert!(!dir.path().join("out.png").exists());
    }
}

/// An image with a data `uri` and a `bufferView` but no `mimeType` (glTF allows exactly one
/// source): the `gltf` crate took the `bufferView` branch and unwrapped the missing
/// `mimeType`, a panic.
#[test]
fn image_with_both_uri_and_buffer_view() {
    let dir = TempDir::new("hostile-image-both");
    let texel = png(1, 1, &[255, 0, 0, 255]);
    let mut fixture = Fixture::new();
    let pos = fixture.positions(&TRIANGLE);
    let uv = fixture.floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC2", 2);
    let view = fixture.view(&texel);
    let doc = fixture.document(json!({
        "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos, "TEXCOORD_0": uv}, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "textures": [{"source": 0}],
        "images": [{"uri": data_uri("image/png", &texel), "bufferView": view}]
    }));
    write_json(&dir, "both.gltf", &doc);
    render_fails(
        dir.path(),
        "both.gltf",
        &[],
        &["image 0", "both", "exactly one"],
    );
}

/// A triangle whose node 0 is animated by one channel with `target` (translation keyframes at
/// t = 0 and 1).
fn animated_triangle(target: Value) -> Value {
    let mut f = Fixture::new();
    let pos = f.positions(&TRIANGLE);
    let times = f.floats(&[0.0, 1.0], "SCALAR", 1);
    let moves = f.floats(&[0.0, 0.0, 0.0, 0.5, 0.0, 0.0], "VEC3", 3);
    f.document(json!({
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.3, 0.3, 3]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos}}]}],
        "animations": [{
            "samplers": [{"input": times, "output": moves}],
            "channels": [
                {"sampler": 0, "target": {"node": 0, "path": "translation"}},
                {"sampler": 0, "target": target}
            ]
        }]
    }))
}

/// Renders `file` at `--time 0.5`, which must succeed with a warning naming `expected`.
fn renders_with_warning(dir: &Path, file: &str, expected: &[&str]) {
    let out = glint(
        &[
            "render", "--width", "16", "--height", "16", "--spp", "1", "--time", "0.5", "-o",
            "out.png", file,
        ],
        dir,
    );
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "{file}: {:?}: {stderr}", out.status);
    assert!(!stderr.contains("panicked"), "{file}: panic: {stderr}");
    let warning = stderr
        .lines()
        .find(|l| l.contains("animation 0 / channel 1"))
        .unwrap_or_else(|| panic!("{file}: no warning naming the channel: {stderr}"));
    for e in expected {
        assert!(
            warning.contains(e),
            "{file}: warning lacks \"{e}\": {warning}"
        );
    }
    assert!(dir.join("out.png").is_file(), "{file}: no image");
}

/// A channel whose target path is none of glTF's four (here KHR_animation_pointer's
/// `pointer`) panicked in the `gltf` crate when sampled; it is now ignored with a warning.
#[test]
fn animation_channel_with_an_unknown_target_path() {
    let dir = TempDir::new("hostile-anim-path");
    let doc = animated_triangle(json!({"node": 0, "path": "pointer"}));
    write_json(&dir, "path.gltf", &doc);
    renders_with_warning(
        dir.path(),
        "path.gltf",
        &["path.gltf", "target path", "ignored"],
    );
}

/// A channel whose target node is past the file's nodes panicked in the `gltf` crate when
/// sampled (its schema check leaves channel targets out); it is now ignored with a warning.
#[test]
fn animation_channel_with_a_target_node_out_of_range() {
    let dir = TempDir::new("hostile-anim-node");
    let doc = animated_triangle(json!({"node": 7, "path": "scale"}));
    write_json(&dir, "node.gltf", &doc);
    renders_with_warning(dir.path(), "node.gltf", &["node.gltf", "node 7", "ignored"]);
}

/// An EXT_meshopt_compression TRIANGLES view of 4 indices: meshoptimizer asserts that the
/// count is a multiple of 3, which aborted the process (SIGABRT).
#[cfg(feature = "meshopt")]
#[test]
fn meshopt_triangles_count_not_a_multiple_of_three() {
    let dir = TempDir::new("hostile-meshopt");
    let mut f = Fixture::new();
    let pos = f.positions(&TRIANGLE);
    // Index codec header (0xe1: version 1) and room for the tail; never decoded.
    let compressed = f.view(&[0xe1; 32]);
    let decoded = f.view(&[0; 8]);
    let mut doc = f.document(json!({
        "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos}}]}],
        "extensionsUsed": ["EXT_meshopt_compression"]
    }));
    let view = &doc["bufferViews"][compressed];
    let extension = json!({"EXT_meshopt_compression": {
        "buffer": 0, "byteOffset": view["byteOffset"], "byteLength": 32,
        "byteStride": 2, "count": 4, "mode": "TRIANGLES"
    }});
    doc["bufferViews"][decoded]["extensions"] = extension;
    write_json(&dir, "meshopt.gltf", &doc);
    render_fails(
        dir.path(),
        "meshopt.gltf",
        &[],
        &[
            &format!("buffer view {decoded}"),
            "count 4",
            "multiple of 3",
        ],
    );
}

/// A sparse accessor without a `bufferView`: one substituted element (index 0 → `value`)
/// in `count` zeros.
fn sparse_viewless(
    f: &mut Fixture,
    count: u64,
    component_type: u32,
    type_: &str,
    value: &[u8],
) -> usize {
    let indices = f.view(&0u32.to_le_bytes());
    let values = f.view(value);
    f.accessor(json!({
        "componentType": component_type, "count": count, "type": type_,
        "sparse": {"count": 1, "indices": {"bufferView": indices, "componentType": 5125},
                   "values": {"bufferView": values}}
    }))
}

/// Elements in each hostile view-less accessor: 2·10⁹, gigabytes from a file of 2 KB.
const HUGE_COUNT: u64 = 2_000_000_000;

/// A sparse accessor without a `bufferView` and a count of 2·10⁹ as a triangle's indices made
/// glint allocate 8 GB; it is now refused by its count, quickly, under a 4 GiB cap.
#[test]
fn sparse_indices_without_a_view_and_a_huge_count() {
    let dir = TempDir::new("hostile-sparse-indices");
    let mut f = Fixture::new();
    let pos = f.positions(&TRIANGLE);
    let idx = sparse_viewless(&mut f, HUGE_COUNT, 5125, "SCALAR", &1u32.to_le_bytes());
    let doc = f.document(json!({
        "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos}, "indices": idx}]}]
    }));
    write_json(&dir, "indices.gltf", &doc);
    // The geometry budget would refuse it first (below); raised, the view-less rule does.
    render_fails_capped(
        dir.path(),
        "indices.gltf",
        &["--max-geometry-bytes", "1000000000000000"],
        &[
            &format!("indices accessor {idx}"),
            "no bufferView",
            "count of 2000000000",
        ],
    );
}

/// The same as POSITION (24 GB).
#[test]
fn sparse_positions_without_a_view_and_a_huge_count() {
    let dir = TempDir::new("hostile-sparse-position");
    let mut f = Fixture::new();
    let one: Vec<u8> = [1.0f32, 0.0, 0.0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    let pos = sparse_viewless(&mut f, HUGE_COUNT, 5126, "VEC3", &one);
    f.accessors[pos]["min"] = json!([0.0, 0.0, 0.0]);
    f.accessors[pos]["max"] = json!([1.0, 0.0, 0.0]);
    let doc = f.document(json!({
        "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos}}]}]
    }));
    write_json(&dir, "position.gltf", &doc);
    render_fails_capped(
        dir.path(),
        "position.gltf",
        &["--max-geometry-bytes", "1000000000000000"],
        &[&format!("POSITION accessor {pos}"), "no bufferView"],
    );
    // Under the default geometry budget (4 GiB) it is refused before the primitive is built,
    // from the declared count.
    render_fails_capped(
        dir.path(),
        "position.gltf",
        &[],
        &[
            &format!("POSITION accessor {pos} declares 2000000000 vertices"),
            "geometry budget",
            "--max-geometry-bytes",
        ],
    );
}

/// The same as an animation's keyframe times, sampled with `--time` (8 GB).
#[test]
fn sparse_keyframe_times_without_a_view_and_a_huge_count() {
    let dir = TempDir::new("hostile-sparse-times");
    let mut f = Fixture::new();
    let pos = f.positions(&TRIANGLE);
    let times = sparse_viewless(&mut f, HUGE_COUNT, 5126, "SCALAR", &1.0f32.to_le_bytes());
    let moves = f.floats(&[0.0, 0.0, 0.0], "VEC3", 3);
    let doc = f.document(json!({
        "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos}}]}],
        "animations": [{
            "samplers": [{"input": times, "output": moves}],
            "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}]
        }]
    }));
    write_json(&dir, "times.gltf", &doc);
    render_fails_capped(
        dir.path(),
        "times.gltf",
        &["--time", "0.5"],
        &[
            "animation 0 / channel 0",
            &format!("input accessor {times}"),
            "no bufferView",
        ],
    );
}
