//! The geometric ground truth (`docs/ground-truth.md`): the camera sidecar, `z`, `position`,
//! `uv` and the flows, checked against closed forms and against each other.
//!
//! - Reprojection: `z` carried back with the sidecar's K and pose equals `position` to 1e-4
//!   of the scene's scale, for a perspective and an orthographic camera; `depth` (the
//!   distance along the ray, from a centre sample) equals |position − camera|.
//! - Flow: a quad translating and rotating by node animation, seen by a moving camera, moves
//!   by the analytic displacement to 1e-3 px; points hidden at the other time are NaN;
//!   forward then backward returns to the start within 1e-3 px (an orthographic view of a
//!   motion in its image plane, whose flow is affine, so interpolating it is exact).
//! - Flow under alpha: through the holes of an alpha-MASK quad the flow and `z` are those of
//!   the surface behind (the visibility ray at the other time follows cut-outs), where the
//!   mask is opaque the quad's.
//! - Skinned and morphing Khronos models: flows nonzero and round-trip consistent; `z`
//!   reprojects.
//! - Determinism and backends: 1 and 2 threads give the same bits; Embree and obvhs the same
//!   positions to 1e-5.

use base64::Engine;
use glam::{DMat4, DQuat, DVec2, DVec3};
use glint::accel::BackendKind;
use glint::gt_check::{self, GroundTruthFile};
use glint::job::{self, CameraChoice, Job, OutputSpec, PreparedScene, RunOptions, SceneSource};
use glint::render::{AovSelection, PixelSampling, RenderSettings};
use glint::scene::gltf::SceneSelection;
use serde_json::json;
use std::path::{Path, PathBuf};

const W: u32 = 64;
const H: u32 = 48;
const YFOV: f64 = 0.9;
/// The quad's animation: translation from `T0` to `T1` and rotation about +z from 0 to
/// `ANGLE` over 0..1 s; the perspective camera moves from `C0` to `C1`.
const T0: [f64; 3] = [-0.6, -0.2, 0.0];
const T1: [f64; 3] = [0.9, 0.5, 0.4];
const ANGLE: f64 = 1.2;
const C0: [f64; 3] = [0.0, 0.0, 6.0];
const C1: [f64; 3] = [0.8, -0.4, 6.5];
const ORTHO_MAG: (f64, f64) = (4.0, 3.0);

fn f32_bytes(values: &[f64]) -> Vec<u8> {
    values
        .iter()
        .flat_map(|&v| (v as f32).to_le_bytes())
        .collect()
}

/// A scene: an animated unit quad (node 0) in front of a static backdrop (node 1), a moving
/// perspective camera (node 2) and a static orthographic one (node 3) looking down −z.
fn write_scene(dir: &Path) -> PathBuf {
    let quad: Vec<f64> = vec![
        -1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0,
    ];
    let backdrop: Vec<f64> = quad
        .chunks(3)
        .flat_map(|p| [p[0] * 8.0, p[1] * 8.0, -3.0])
        .collect();
    let uvs = [0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
    let indices: Vec<u8> = [0u16, 1, 2, 0, 2, 3, 0]
        .iter()
        .flat_map(|i| i.to_le_bytes())
        .collect();
    let half = ANGLE / 2.0;
    let sections: Vec<Vec<u8>> = vec![
        f32_bytes(&quad),
        f32_bytes(&backdrop),
        f32_bytes(&uvs),
        indices,
        f32_bytes(&[0.0, 1.0]),
        f32_bytes(&[T0, T1].concat()),
        f32_bytes(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, half.sin(), half.cos()]),
        f32_bytes(&[C0, C1].concat()),
    ];
    let mut buffer = Vec::new();
    let mut views = Vec::new();
    for s in &sections {
        views.push(json!({"buffer": 0, "byteOffset": buffer.len(), "byteLength": s.len()}));
        buffer.extend_from_slice(s);
        while buffer.len() % 4 != 0 {
            buffer.push(0);
        }
    }
    let acc = |view: usize, count: usize, kind: &str, ctype: u32| json!({"bufferView": view, "count": count, "type": kind, "componentType": ctype});
    let mut quad_pos = acc(0, 4, "VEC3", 5126);
    quad_pos["min"] = json!([-1.0, -1.0, 0.0]);
    quad_pos["max"] = json!([1.0, 1.0, 0.0]);
    let mut back_pos = acc(1, 4, "VEC3", 5126);
    back_pos["min"] = json!([-8.0, -8.0, -3.0]);
    back_pos["max"] = json!([8.0, 8.0, -3.0]);
    let mut times = acc(4, 2, "SCALAR", 5126);
    times["min"] = json!([0.0]);
    times["max"] = json!([1.0]);
    let gltf = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"name": "quad", "mesh": 0, "translation": T0},
            {"name": "backdrop", "mesh": 1},
            {"name": "eye", "camera": 0, "translation": C0},
            {"name": "plan", "camera": 1, "translation": [0.0, 0.0, 6.0]}
        ],
        "cameras": [
            {"type": "perspective", "perspective": {"yfov": YFOV, "znear": 0.1, "zfar": 100.0}},
            {"type": "orthographic", "orthographic": {"xmag": ORTHO_MAG.0, "ymag": ORTHO_MAG.1, "znear": 0.0, "zfar": 20.0}}
        ],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 2}, "indices": 3}]},
            {"primitives": [{"attributes": {"POSITION": 1}, "indices": 3}]}
        ],
        "materials": [],
        "accessors": [quad_pos, back_pos, acc(2, 4, "VEC2", 5126), acc(3, 6, "SCALAR", 5123),
                      times, acc(5, 2, "VEC3", 5126), acc(6, 2, "VEC4", 5126), acc(7, 2, "VEC3", 5126)],
        "bufferViews": views,
        "buffers": [{"byteLength": buffer.len(), "uri": format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&buffer))}],
        "animations": [{
            "samplers": [
                {"input": 4, "output": 5, "interpolation": "LINEAR"},
                {"input": 4, "output": 6, "interpolation": "LINEAR"},
                {"input": 4, "output": 7, "interpolation": "LINEAR"}
            ],
            "channels": [
                {"sampler": 0, "target": {"node": 0, "path": "translation"}},
                {"sampler": 1, "target": {"node": 0, "path": "rotation"}},
                {"sampler": 2, "target": {"node": 2, "path": "translation"}}
            ]
        }]
    });
    let path = dir.join("moving.gltf");
    std::fs::write(&path, serde_json::to_vec_pretty(&gltf).unwrap()).unwrap();
    path
}

fn aovs(names: &[&str]) -> AovSelection {
    let has = |n: &str| names.contains(&n);
    AovSelection {
        depth: has("depth"),
        z: has("z"),
        position: has("position"),
        uv: has("uv"),
        flow: has("flow"),
        flow_backward: has("flow_backward"),
        ..AovSelection::default()
    }
}

struct Render {
    scene: SceneSource,
    camera: CameraChoice,
    time: Option<f32>,
    flow_dt: Option<f32>,
    aovs: AovSelection,
    backend: BackendKind,
    threads: usize,
    size: Option<(u32, u32)>,
}

impl Render {
    fn new(scene: &Path, aov_names: &[&str]) -> Self {
        Self {
            scene: SceneSource::File(scene.to_path_buf()),
            camera: CameraChoice::Index(0),
            time: Some(0.3),
            flow_dt: Some(0.1),
            aovs: aovs(aov_names),
            backend: BackendKind::Bvh,
            threads: 1,
            size: Some((W, H)),
        }
    }

    /// Renders to `out` (an EXR, with its sidecar) and returns the job's output.
    fn run(&self, out: &Path) -> job::JobOutput {
        let job = Job {
            scene: self.scene.clone(),
            selection: SceneSelection {
                scene: None,
                time: self.time,
                variant: None,
            },
            backend: self.backend,
            camera: self.camera.clone(),
            width: self.size.map(|s| s.0),
            height: self.size.map(|s| s.1),
            settings: RenderSettings {
                spp: 1,
                threads: self.threads,
                sampling: PixelSampling::PixelCenter,
                aovs: self.aovs,
                ..Job::default().settings
            },
            output: Some(OutputSpec {
                path: out.to_path_buf(),
                sidecar: true,
                ..OutputSpec::default()
            }),
            flow_dt: self.flow_dt,
            ..Job::default()
        };
        let prepared =
            PreparedScene::load(&job.scene, &job.selection, &job.load_options, job.backend)
                .unwrap();
        job::run(&job, &prepared, RunOptions::default()).unwrap()
    }
}

/// The quad's node matrix at time `t` (the animation's closed form: linear translation,
/// rotation by `ANGLE·t` about +z).
fn quad_at(t: f64) -> DMat4 {
    let tr = DVec3::from(T0).lerp(DVec3::from(T1), t);
    DMat4::from_rotation_translation(DQuat::from_rotation_z(ANGLE * t), tr)
}

/// The perspective camera's film position of `p` at time `t` (glint's film: pixel centres at
/// half-integers), in closed form.
fn film_at(p: DVec3, t: f64) -> Option<DVec2> {
    let c = DVec3::from(C0).lerp(DVec3::from(C1), t);
    let v = p - c;
    let depth = -v.z;
    if depth <= 0.0 {
        return None;
    }
    let tan = (YFOV / 2.0).tan();
    let aspect = f64::from(W) / f64::from(H);
    let ndc = DVec2::new(v.x / (depth * aspect * tan), v.y / (depth * tan));
    Some(DVec2::new(
        (ndc.x + 1.0) * f64::from(W) / 2.0,
        (1.0 - ndc.y) * f64::from(H) / 2.0,
    ))
}

fn images(out: &job::JobOutput) -> &glint::render::Aovs {
    &out.images.as_ref().unwrap().aovs
}

#[test]
fn z_reprojects_to_position_for_perspective_and_orthographic_cameras() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path());
    for camera in [0, 1] {
        let mut render = Render::new(&scene, &["z", "position", "depth", "uv"]);
        render.camera = CameraChoice::Index(camera);
        let path = dir.path().join(format!("camera{camera}.exr"));
        let out = render.run(&path);
        let file = GroundTruthFile::read(&path).unwrap();
        let check = gt_check::reprojection(&file).unwrap();
        eprintln!("camera {camera}: reprojection {check:?}");
        assert!(
            check.largest < 1e-4 && check.compared == (W * H) as usize,
            "camera {camera}: {check:?}"
        );
        // The sidecar's camera, K and planes are the glTF camera's.
        let sidecar = &file.sidecar;
        assert_eq!(sidecar.camera.node, Some(2 + camera as u32));
        assert_eq!(
            (sidecar.width, sidecar.height, sidecar.time),
            (W, H, Some(0.3))
        );
        let k = sidecar.camera.k;
        assert_eq!(
            (k[0][2], k[1][2]),
            (31.5, 23.5),
            "principal point, centres at integers"
        );
        if camera == 0 {
            let f = f64::from(H) / (2.0 * (YFOV / 2.0).tan());
            // yfov is an f32 in the file.
            assert!((k[0][0] - f).abs() < 1e-4 * f && (k[1][1] - f).abs() < 1e-4 * f);
            assert_eq!(
                (sidecar.camera.znear, sidecar.camera.zfar),
                (0.1f32 as f64, Some(100.0))
            );
        } else {
            assert_eq!(k[0][0], f64::from(W) / (2.0 * ORTHO_MAG.0));
        }
        // depth (the centre sample's distance along its ray) = |position − camera| for the
        // perspective camera; for the orthographic one it is z itself.
        let aovs = images(&out);
        let (z, depth, position) = (
            aovs.z.as_ref().unwrap(),
            aovs.depth.as_ref().unwrap(),
            aovs.position.as_ref().unwrap(),
        );
        let eye = DVec3::from(sidecar.camera.position);
        for i in 0..(W * H) as usize {
            let p = position.pixels[i].as_dvec3();
            let expected = if camera == 0 {
                (p - eye).length()
            } else {
                f64::from(z.pixels[i])
            };
            let got = f64::from(depth.pixels[i]);
            assert!(
                (got - expected).abs() <= 1e-4 * expected,
                "camera {camera} pixel {i}: depth {got} vs {expected}"
            );
        }
        // uv: the quad's texture coordinates, NaN on the backdrop (which has none).
        let uv = aovs.uv.as_ref().unwrap();
        assert!(uv.pixels.iter().any(|v| v.is_nan()) && uv.pixels.iter().any(|v| v.is_finite()));
        assert!(
            uv.pixels
                .iter()
                .filter(|v| v.is_finite())
                .all(|v| v.min_element() >= -1e-6 && v.max_element() <= 1.0 + 1e-6)
        );
    }
}

#[test]
fn flow_of_an_animated_quad_and_a_moving_camera_is_the_analytic_displacement() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path());
    let (t, dt) = (0.3f64, 0.1f64);
    let path = dir.path().join("flow.exr");
    let out = Render::new(&scene, &["position", "flow", "flow_backward"]).run(&path);
    let aovs = images(&out);
    let (position, forward, backward) = (
        aovs.position.as_ref().unwrap(),
        aovs.flow.as_ref().unwrap(),
        aovs.flow_backward.as_ref().unwrap(),
    );
    let (mut compared, mut hidden, mut largest) = (0, 0, 0.0f64);
    for (flow, other) in [(forward, t + dt), (backward, t - dt)] {
        for i in 0..(W * H) as usize {
            let (x, y) = ((i as u32 % W) as f64 + 0.5, (i as u32 / W) as f64 + 0.5);
            let p = position.pixels[i].as_dvec3();
            let on_quad = quad_at(t).inverse().transform_point3(p).z.abs() < 1e-4;
            let moved = if on_quad {
                quad_at(other) * quad_at(t).inverse()
            } else {
                DMat4::IDENTITY
            };
            let then = moved.transform_point3(p);
            let landing = film_at(then, other).unwrap();
            // Hidden then: a backdrop point behind the quad as it is then.
            let eye = DVec3::from(C0).lerp(DVec3::from(C1), other);
            let local = quad_at(other).inverse();
            let (a, b) = (local.transform_point3(eye), local.transform_point3(then));
            let s = a.z / (a.z - b.z);
            let cross = a + (b - a) * s;
            let inside = cross.x.abs().max(cross.y.abs());
            if !on_quad && (inside - 1.0).abs() < 1e-3 {
                continue; // on the quad's silhouette: either answer is right
            }
            let occluded = !on_quad && s > 0.0 && s < 1.0 && inside < 1.0;
            let off = landing.x < 0.0
                || landing.y < 0.0
                || landing.x >= f64::from(W)
                || landing.y >= f64::from(H);
            let got = flow.pixels[i];
            if occluded || off {
                assert!(
                    got.is_nan(),
                    "pixel {i}: hidden or off the image then, flow {got}"
                );
                hidden += 1;
                continue;
            }
            let expected = landing - DVec2::new(x, y);
            let error = (got.as_dvec2() - expected).length();
            largest = largest.max(error);
            assert!(
                error < 1e-3,
                "pixel {i} (quad: {on_quad}): flow {got} vs {expected}"
            );
            compared += 1;
        }
    }
    eprintln!(
        "flow against the closed form: largest error {largest:.3e} px over {compared} pixels, {hidden} NaN as expected"
    );
    assert!(
        compared > 4000 && hidden > 20,
        "{compared} compared, {hidden} hidden"
    );
}

/// Half-size of the alpha-masked quad of [`write_cut_out_scene`].
const CUT_HALF: f64 = 2.0;

/// A static alpha-MASK quad (z = 0, x and y in ±`CUT_HALF`, cutoff 0.5) whose COLOR_0 alpha
/// runs from 0 at x = −`CUT_HALF` to 1 at x = +`CUT_HALF` (alpha (x + 2)/4: a hole for
/// x < 0, opaque for x ≥ 0), in front of a static backdrop at z = −3, seen by the moving
/// perspective camera of [`write_scene`] (node 2, `C0` to `C1`).
fn write_cut_out_scene(dir: &Path) -> PathBuf {
    let h = CUT_HALF;
    let quad: Vec<f64> = vec![-h, -h, 0.0, h, -h, 0.0, h, h, 0.0, -h, h, 0.0];
    let colours: Vec<f64> = [0.0, 1.0, 1.0, 0.0]
        .iter()
        .flat_map(|&a| [1.0, 1.0, 1.0, a])
        .collect();
    let backdrop: Vec<f64> = [-1.0, -1.0, 1.0, -1.0, 1.0, 1.0, -1.0, 1.0]
        .chunks(2)
        .flat_map(|p| [p[0] * 8.0, p[1] * 8.0, -3.0])
        .collect();
    let indices: Vec<u8> = [0u16, 1, 2, 0, 2, 3]
        .iter()
        .flat_map(|i| i.to_le_bytes())
        .collect();
    let sections: Vec<Vec<u8>> = vec![
        f32_bytes(&quad),
        f32_bytes(&colours),
        f32_bytes(&backdrop),
        indices,
        f32_bytes(&[0.0, 1.0]),
        f32_bytes(&[C0, C1].concat()),
    ];
    let mut buffer = Vec::new();
    let mut views = Vec::new();
    for s in &sections {
        views.push(json!({"buffer": 0, "byteOffset": buffer.len(), "byteLength": s.len()}));
        buffer.extend_from_slice(s);
        while buffer.len() % 4 != 0 {
            buffer.push(0);
        }
    }
    let acc = |view: usize, count: usize, kind: &str, ctype: u32| json!({"bufferView": view, "count": count, "type": kind, "componentType": ctype});
    let mut quad_pos = acc(0, 4, "VEC3", 5126);
    quad_pos["min"] = json!([-h, -h, 0.0]);
    quad_pos["max"] = json!([h, h, 0.0]);
    let mut back_pos = acc(2, 4, "VEC3", 5126);
    back_pos["min"] = json!([-8.0, -8.0, -3.0]);
    back_pos["max"] = json!([8.0, 8.0, -3.0]);
    let mut times = acc(4, 2, "SCALAR", 5126);
    times["min"] = json!([0.0]);
    times["max"] = json!([1.0]);
    let gltf = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"name": "cut-out", "mesh": 0},
            {"name": "backdrop", "mesh": 1},
            {"name": "eye", "camera": 0, "translation": C0}
        ],
        "cameras": [
            {"type": "perspective", "perspective": {"yfov": YFOV, "znear": 0.1, "zfar": 100.0}}
        ],
        "materials": [{
            "name": "mask",
            "alphaMode": "MASK",
            "alphaCutoff": 0.5,
            "doubleSided": true,
            "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0]}
        }],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 0, "COLOR_0": 1}, "indices": 3, "material": 0}]},
            {"primitives": [{"attributes": {"POSITION": 2}, "indices": 3}]}
        ],
        "accessors": [quad_pos, acc(1, 4, "VEC4", 5126), back_pos, acc(3, 6, "SCALAR", 5123),
                      times, acc(5, 2, "VEC3", 5126)],
        "bufferViews": views,
        "buffers": [{"byteLength": buffer.len(), "uri": format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&buffer))}],
        "animations": [{
            "samplers": [{"input": 4, "output": 5, "interpolation": "LINEAR"}],
            "channels": [{"sampler": 0, "target": {"node": 2, "path": "translation"}}]
        }]
    });
    let path = dir.join("cut-out.gltf");
    std::fs::write(&path, serde_json::to_vec_pretty(&gltf).unwrap()).unwrap();
    path
}

/// Where the ray from `eye` towards `towards` crosses the cut-out quad's plane z = 0, and
/// whether the quad is opaque there (`Some(true)`), a hole (`Some(false)`), or too close to
/// its alpha edge or outline for either answer to be right (`None`). Misses are holes.
fn cut_out_at(eye: DVec3, towards: DVec3) -> Option<(DVec3, bool)> {
    let s = eye.z / (eye.z - towards.z);
    let cross = eye + (towards - eye) * s;
    let margin = 0.05;
    let outline = (cross.x.abs() - CUT_HALF)
        .abs()
        .min((cross.y.abs() - CUT_HALF).abs());
    if cross.x.abs() < margin || outline < margin {
        return None;
    }
    let inside = cross.x.abs() < CUT_HALF && cross.y.abs() < CUT_HALF;
    Some((cross, inside && cross.x > 0.0 && s > 0.0))
}

/// The flow's visibility ray follows alpha cut-outs: through the holes of an alpha-MASK quad
/// the flow (and `z`) are the backdrop's, where the mask is opaque the quad's, both against
/// the closed form to 1e-3 px (z to 1e-5 relative). A backdrop point seen through a hole at
/// both times has a flow; one the opaque part hides at the other time is NaN. The old rule
/// (the raw first hit of the visibility ray, the hole included) called every point seen
/// through a hole hidden, NaN.
#[test]
fn flow_and_z_show_the_surface_behind_an_alpha_cut_out() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_cut_out_scene(dir.path());
    // The camera's whole path (times 0 and 1 are the animation's keys, so the closed form
    // holds): enough motion that some backdrop points seen through a hole now are hidden by
    // the opaque part then.
    let (t, dt) = (0.5f64, 0.5f64);
    let eye_at = |t: f64| DVec3::from(C0).lerp(DVec3::from(C1), t);
    let tan = (YFOV / 2.0).tan();
    let aspect = f64::from(W) / f64::from(H);
    for &backend in BackendKind::available() {
        let mut render = Render::new(&scene, &["z", "flow", "flow_backward"]);
        render.backend = backend;
        render.time = Some(t as f32);
        render.flow_dt = Some(dt as f32);
        let out = render.run(&dir.path().join(format!("cut-out-{backend}.exr")));
        let aovs = images(&out);
        let (z, forward, backward) = (
            aovs.z.as_ref().unwrap(),
            aovs.flow.as_ref().unwrap(),
            aovs.flow_backward.as_ref().unwrap(),
        );
        let (mut front, mut through, mut hidden) = (0, 0, 0);
        for i in 0..(W * H) as usize {
            let film = DVec2::new((i as u32 % W) as f64 + 0.5, (i as u32 / W) as f64 + 0.5);
            // The centre ray at time t, in closed form (the camera looks down −z unrotated).
            let ndc = DVec2::new(
                2.0 * film.x / f64::from(W) - 1.0,
                1.0 - 2.0 * film.y / f64::from(H),
            );
            let eye = eye_at(t);
            let dir = DVec3::new(ndc.x * aspect * tan, ndc.y * tan, -1.0);
            let Some((cross, opaque)) = cut_out_at(eye, eye + dir) else {
                continue;
            };
            let point = if opaque {
                cross
            } else {
                eye + dir * (eye.z + 3.0)
            };
            let want_z = eye.z - point.z;
            let got_z = f64::from(z.pixels[i]);
            assert!(
                (got_z - want_z).abs() <= 1e-5 * want_z,
                "{backend} pixel {i} (opaque: {opaque}): z {got_z} vs {want_z}"
            );
            for (flow, other) in [(forward, t + dt), (backward, t - dt)] {
                let got = flow.pixels[i];
                let landing = film_at(point, other).unwrap();
                let off = landing.x < 0.0
                    || landing.y < 0.0
                    || landing.x >= f64::from(W)
                    || landing.y >= f64::from(H);
                let then = if opaque {
                    Some((cross, false))
                } else {
                    cut_out_at(eye_at(other), point)
                };
                let Some((_, hidden_then)) = then else {
                    continue; // the ray then grazes the alpha edge: either answer is right
                };
                if off || hidden_then {
                    assert!(
                        got.is_nan(),
                        "{backend} pixel {i}: hidden or off the image then, flow {got}"
                    );
                    hidden += usize::from(hidden_then && !off);
                    continue;
                }
                let expected = landing - film;
                let error = (got.as_dvec2() - expected).length();
                assert!(
                    error < 1e-3,
                    "{backend} pixel {i} (opaque: {opaque}): flow {got} vs {expected}"
                );
                if opaque {
                    front += 1;
                } else {
                    through += 1;
                }
            }
        }
        eprintln!(
            "{backend}: {front} front flows, {through} through the hole, {hidden} hidden by the opaque part then"
        );
        assert!(
            front > 200 && through > 200 && hidden > 0,
            "{backend}: {front} front, {through} through, {hidden} hidden"
        );
    }
}

#[test]
fn forward_then_backward_flow_returns_to_the_start() {
    // The orthographic camera is static and the quad moves in its image plane up to a
    // translation along z the projection ignores: the flow is affine, so the bilinear
    // interpolation of the next frame's backward flow is exact.
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path());
    let (now, next) = (dir.path().join("now.exr"), dir.path().join("next.exr"));
    let mut render = Render::new(&scene, &["z", "position", "flow", "flow_backward"]);
    render.aovs.instance_id = true;
    render.camera = CameraChoice::Index(1);
    render.run(&now);
    render.time = Some(0.4);
    render.run(&next);
    let wrong = dir.path().join("wrong.exr");
    render.time = Some(0.5);
    render.run(&wrong);
    let (a, b) = (
        GroundTruthFile::read(&now).unwrap(),
        GroundTruthFile::read(&next).unwrap(),
    );
    let check = gt_check::flow_round_trip(&a, &b).unwrap();
    eprintln!("orthographic round trip: {check:?}");
    assert!(check.largest < 1e-3 && check.compared > 1500, "{check:?}");
    // `glint check-gt` says the same.
    let args = glint::cli::check_gt::CheckGtArgs {
        output: now.clone(),
        next: Some(next.clone()),
        tolerance: 1e-4,
        flow_tolerance: 1e-3,
    };
    glint::cli::check_gt::run(args).unwrap();
    // A wrong next frame (one step too far) fails it.
    let args = glint::cli::check_gt::CheckGtArgs {
        output: now.clone(),
        next: Some(wrong),
        tolerance: 1e-4,
        flow_tolerance: 1e-3,
    };
    assert!(glint::cli::check_gt::run(args).is_err());
}

fn khronos(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/khronos")
        .join(rel)
}

#[test]
fn skinned_and_morphing_models_flow_consistently() {
    for (model, t) in [
        ("SimpleSkin/glTF/SimpleSkin.gltf", 1.5f32),
        ("SimpleMorph/glTF/SimpleMorph.gltf", 1.5),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let (now, next) = (dir.path().join("now.exr"), dir.path().join("next.exr"));
        let mut render = Render::new(&khronos(model), &["z", "position", "flow", "flow_backward"]);
        render.aovs.instance_id = true;
        // The models have no camera: one framing the first frame, kept for both frames (a
        // default camera would reframe each frame).
        let selection = SceneSelection {
            scene: None,
            time: Some(t),
            variant: None,
        };
        let first = glint::scene::gltf::load_with(&khronos(model), &selection).unwrap();
        render.camera = CameraChoice::Given(glint::scene::defaults::default_camera(&first));
        render.time = Some(t);
        render.flow_dt = Some(0.05);
        let out = render.run(&now);
        render.time = Some(t + 0.05);
        render.run(&next);
        let (a, b) = (
            GroundTruthFile::read(&now).unwrap(),
            GroundTruthFile::read(&next).unwrap(),
        );
        let reprojection = gt_check::reprojection(&a).unwrap();
        assert!(reprojection.largest < 1e-4, "{model}: {reprojection:?}");
        let flow = images(&out).flow.as_ref().unwrap();
        let largest = flow
            .pixels
            .iter()
            .filter(|f| f.is_finite())
            .map(|f| f.length())
            .fold(0.0, f32::max);
        assert!(
            largest > 0.5,
            "{model}: the deformation must move pixels ({largest} px)"
        );
        let round = gt_check::flow_round_trip(&a, &b).unwrap();
        eprintln!(
            "{model}: reprojection {reprojection:?}, largest flow {largest} px, round trip {round:?}"
        );
        // Bilinear interpolation of the next frame's backward flow is first-order across
        // the bends between a deforming mesh's triangles: a tenth of a pixel.
        assert!(
            round.largest < 0.1 && round.compared > 100,
            "{model}: {round:?}"
        );
    }
}

#[test]
fn geometric_aovs_are_the_same_for_any_thread_count_and_both_backends_agree() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path());
    let names = ["z", "position", "uv", "flow", "flow_backward"];
    let mut render = Render::new(&scene, &names);
    let one = render.run(&dir.path().join("one.exr"));
    render.threads = 2;
    let two = render.run(&dir.path().join("two.exr"));
    let bits = |o: &job::JobOutput| {
        let a = images(o);
        let mut v: Vec<u32> =
            a.z.as_ref()
                .unwrap()
                .pixels
                .iter()
                .map(|x| x.to_bits())
                .collect();
        let position = a.position.as_ref().unwrap();
        v.extend(
            position
                .pixels
                .iter()
                .flat_map(|p| p.to_array().map(f32::to_bits)),
        );
        for img in [
            a.uv.as_ref().unwrap(),
            a.flow.as_ref().unwrap(),
            a.flow_backward.as_ref().unwrap(),
        ] {
            v.extend(
                img.pixels
                    .iter()
                    .flat_map(|p| p.to_array().map(f32::to_bits)),
            );
        }
        v
    };
    assert!(bits(&one) == bits(&two), "1 and 2 threads differ");
    if !cfg!(feature = "embree") {
        return;
    }
    render.backend = BackendKind::Embree;
    let embree = render.run(&dir.path().join("embree.exr"));
    let (a, b) = (images(&one), images(&embree));
    let (pa, pb) = (a.position.as_ref().unwrap(), b.position.as_ref().unwrap());
    let scale = 10.0;
    for (i, (x, y)) in pa.pixels.iter().zip(&pb.pixels).enumerate() {
        assert_eq!(x.is_nan(), y.is_nan(), "pixel {i}");
        if x.is_finite() {
            assert!((*x - *y).length() <= 1e-5 * scale, "pixel {i}: {x} vs {y}");
        }
    }
    let (fa, fb) = (a.flow.as_ref().unwrap(), b.flow.as_ref().unwrap());
    for (i, (x, y)) in fa.pixels.iter().zip(&fb.pixels).enumerate() {
        assert_eq!(x.is_nan(), y.is_nan(), "flow pixel {i}");
        if x.is_finite() {
            assert!((*x - *y).length() <= 1e-3, "flow pixel {i}: {x} vs {y}");
        }
    }
}

#[test]
fn flow_without_a_time_is_refused_and_aovs_stay_off_by_default() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path());
    let mut render = Render::new(&scene, &["flow"]);
    render.time = None;
    let job = Job {
        scene: render.scene.clone(),
        settings: RenderSettings {
            aovs: render.aovs,
            ..Job::default().settings
        },
        output: Some(OutputSpec {
            path: dir.path().join("x.exr"),
            ..OutputSpec::default()
        }),
        ..Job::default()
    };
    let err = job.check().unwrap_err().to_string();
    assert!(err.contains("--time"), "{err}");
    // Without --sidecar no JSON is written, and without geometric AOVs no centre hits kept.
    let plain = Job {
        width: Some(8),
        height: Some(6),
        backend: BackendKind::Bvh,
        settings: RenderSettings {
            spp: 1,
            ..Job::default().settings
        },
        output: Some(OutputSpec {
            path: dir.path().join("plain.exr"),
            ..OutputSpec::default()
        }),
        ..Job::default()
    };
    let prepared = PreparedScene::load(
        &plain.scene,
        &plain.selection,
        &plain.load_options,
        plain.backend,
    )
    .unwrap();
    let out = job::run(&plain, &prepared, RunOptions::default()).unwrap();
    assert!(!dir.path().join("plain.json").exists());
    assert!(images(&out).centre_hits.is_none() && images(&out).z.is_none());
}
