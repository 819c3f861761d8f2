//! glTF coverage: quantized and meshopt-compressed geometry, instancing, morph targets,
//! skins, scene selection and animation sampling, against the Khronos sample models in
//! `../shared/khronos` and small hand-built documents. Right answers come from the glTF
//! specification, computed here independently of the loader (the `gltf` crate reads the raw
//! float data; the interpolation formulas are written out again below).

use crate::support;

use crate::support::{Fixture, one_sided_hausdorff};
use glam::{Mat4, Quat, Vec3, Vec4};
use glint::scene::gltf::{SceneSelection, load_selected};
use glint::scene::{Mesh, Scene};
use serde_json::json;
use std::path::PathBuf;

fn khronos(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/khronos")
        .join(relative)
}

fn load_at(relative: &str, selection: SceneSelection) -> (Scene, Vec<String>) {
    let path = khronos(relative);
    let loaded = load_selected(&path, &selection).unwrap_or_else(|e| panic!("{e}"));
    (loaded.scene, loaded.warnings)
}

fn load(relative: &str) -> Scene {
    load_at(relative, SceneSelection::default()).0
}

fn triangles(scene: &Scene) -> usize {
    scene.meshes.iter().map(|m| m.indices.len()).sum()
}

fn bounds<'a>(meshes: impl IntoIterator<Item = &'a Mesh>) -> (Vec3, Vec3) {
    let mut lo = Vec3::INFINITY;
    let mut hi = Vec3::NEG_INFINITY;
    for mesh in meshes {
        for p in &mesh.positions {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
    }
    (lo, hi)
}

fn all_positions(scene: &Scene) -> Vec<Vec3> {
    scene
        .meshes
        .iter()
        .flat_map(|m| m.positions.iter().copied())
        .collect()
}

// ---------------------------------------------------------------------------------------
// Quantized and meshopt-compressed Duck against the uncompressed Duck.

#[test]
fn duck_variants_have_the_uncompressed_geometry_within_the_quantization_step() {
    let reference = load("Duck/glTF-Binary/Duck.glb");
    let reference_points = all_positions(&reference);
    let (lo, hi) = bounds(&reference.meshes);
    let extent = (hi - lo).max_element();
    for variant in [
        "Duck/glTF-Quantized/Duck.gltf",
        "Duck/glTF-quantized-gltfpack/Duck.glb",
        #[cfg(feature = "meshopt")]
        "Duck/glTF-meshopt/Duck.glb",
    ] {
        let scene = load(variant);
        assert_eq!(
            triangles(&scene),
            triangles(&reference),
            "{variant}: triangle count"
        );
        // gltfpack and the Khronos variant quantize positions to ≥ 14 bits over the
        // mesh's extent: one step is extent / (2¹⁴ − 1) (the files' dequantization scale).
        // Rounding to the nearest step moves each coordinate by at most half a step, so a
        // vertex by at most √3/2 steps; 1 % slack covers f32 rounding of the transforms.
        let step = extent / 16383.0;
        let (vlo, vhi) = bounds(&scene.meshes);
        assert!(
            (vlo - lo).abs().max_element() <= 0.505 * step
                && (vhi - hi).abs().max_element() <= 0.505 * step,
            "{variant}: bounds {vlo}..{vhi} vs {lo}..{hi} (step {step})"
        );
        let points = all_positions(&scene);
        let forward = one_sided_hausdorff(&points, &reference_points);
        let backward = one_sided_hausdorff(&reference_points, &points);
        eprintln!("{variant}: Hausdorff {forward:.3e} / {backward:.3e}, step {step:.3e}");
        assert!(
            forward <= 0.875 * step && backward <= 0.875 * step,
            "{variant}: vertices {forward} / {backward} from the uncompressed ones (step {step})"
        );
        // Normals survive quantization (and the meshopt octahedral filter) as unit vectors.
        for mesh in &scene.meshes {
            let normals = mesh.normals.as_ref().expect("the Duck has normals");
            assert!(
                normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-3),
                "{variant}"
            );
            assert!(mesh.texcoords[0].is_some(), "{variant}: TEXCOORD_0");
        }
    }
}

#[test]
fn integer_attributes_need_khr_mesh_quantization_and_follow_its_table() {
    let mut fixture = Fixture::new();
    // Three UNSIGNED_SHORT positions (not normalized): read as the integers themselves.
    let positions: Vec<u8> = [0u16, 0, 0, 1000, 0, 0, 0, 2000, 0, 0]
        .iter()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    let view = fixture.view(&positions[..18]);
    let position = fixture.accessor(json!({
        "bufferView": view, "componentType": 5123, "count": 3, "type": "VEC3",
        "min": [0, 0, 0], "max": [1000, 2000, 0]
    }));
    // Normalized BYTE normals, padded to 4 bytes a vertex as the spec requires: (0, 0, 127).
    let view = fixture.view(&[0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0]);
    fixture.views[view]["byteStride"] = json!(4);
    let normal = fixture.accessor(json!({
        "bufferView": view, "componentType": 5120, "normalized": true, "count": 3, "type": "VEC3"
    }));
    // BYTE texture coordinates, not normalized: −3 and 5 stay −3 and 5.
    let view = fixture.view(&[0xfd, 5, 0xfd, 5, 0xfd, 5]);
    let texcoord = fixture.accessor(json!({
        "bufferView": view, "componentType": 5120, "count": 3, "type": "VEC2"
    }));
    let rest = |extension: bool| {
        let mut doc = json!({
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0, "scale": [0.001, 0.001, 0.001]}],
            "meshes": [{"primitives": [{"attributes": {
                "POSITION": position, "NORMAL": normal, "TEXCOORD_0": texcoord
            }}]}]
        });
        if extension {
            doc["extensionsUsed"] = json!(["KHR_mesh_quantization"]);
            doc["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
        }
        doc
    };
    let loaded = fixture.load(rest(true)).unwrap_or_else(|e| panic!("{e}"));
    let mesh = &loaded.scene.meshes[0];
    assert_eq!(mesh.positions[1], Vec3::new(1.0, 0.0, 0.0)); // 1000 × 0.001
    assert_eq!(mesh.positions[2], Vec3::new(0.0, 2.0, 0.0));
    assert_eq!(mesh.normals.as_ref().unwrap()[0], Vec3::Z);
    assert_eq!(
        mesh.texcoords[0].as_ref().unwrap()[0],
        glam::Vec2::new(-3.0, 5.0)
    );
    // Without the extension the core spec's FLOAT-only rule holds.
    let refused = fixture.load(rest(false)).unwrap_err().to_string();
    assert!(
        refused.contains("POSITION") && refused.contains("FLOAT"),
        "{refused}"
    );
}

// ---------------------------------------------------------------------------------------
// Unsupported extensions.

#[test]
fn a_file_requiring_two_unsupported_extensions_names_both() {
    let mut fixture = Fixture::new();
    let position = fixture.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let rest = json!({
        "extensionsUsed": ["EXT_lights_image_based", "EXT_texture_avif", "KHR_mesh_quantization"],
        "extensionsRequired": ["EXT_lights_image_based", "EXT_texture_avif", "KHR_mesh_quantization"],
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": position}}]}]
    });
    let message = fixture.load(rest).unwrap_err().to_string();
    assert!(!message.contains('\n'), "one line: {message}");
    assert!(
        message.contains("extensions EXT_lights_image_based and EXT_texture_avif"),
        "{message}"
    );
    // The supported one is not listed as missing. (Draco, then specular-glossiness, were the
    // example until glint read them.)
    assert!(
        !message.contains("EXT_texture_avif and KHR_mesh_quantization"),
        "{message}"
    );
    assert!(message.contains("without the others"), "{message}");
}

// ---------------------------------------------------------------------------------------
// Instancing (flattened).

#[test]
fn simple_instancing_draws_every_instance_where_its_trs_puts_it() {
    let path = khronos("SimpleInstancing/glTF-Binary/SimpleInstancing.glb");
    let scene = load("SimpleInstancing/glTF-Binary/SimpleInstancing.glb");
    // Independently: the instance TRS from the accessors, with the gltf crate's reader.
    let (document, buffers, _) = gltf::import(&path).expect("gltf crate imports the sample");
    let node = document.nodes().next().expect("a node");
    let ext = node
        .extension_value("EXT_mesh_gpu_instancing")
        .expect("the node is instanced");
    let accessor = |name: &str| {
        let index = ext["attributes"][name].as_u64().expect(name) as usize;
        document.accessors().nth(index).expect("accessor")
    };
    let read = |name: &str| -> Vec<Vec<f32>> {
        let a = accessor(name);
        assert_eq!(a.data_type(), gltf::accessor::DataType::F32);
        let view = a.view().expect("view");
        let data = &buffers[view.buffer().index()];
        let n = a.dimensions().multiplicity();
        let stride = view.stride().unwrap_or(4 * n);
        (0..a.count())
            .map(|i| {
                let start = view.offset() + a.offset() + i * stride;
                (0..n)
                    .map(|c| {
                        let b = &data[start + 4 * c..start + 4 * c + 4];
                        f32::from_le_bytes([b[0], b[1], b[2], b[3]])
                    })
                    .collect()
            })
            .collect()
    };
    let (t, r, s) = (read("TRANSLATION"), read("ROTATION"), read("SCALE"));
    let primitives = node.mesh().expect("mesh").primitives().len();
    // One object-space mesh per primitive, placed once per instance: memory follows the
    // unique geometry.
    assert_eq!(scene.meshes.len(), primitives, "one mesh per primitive");
    let base = load_base_positions(&document, &buffers);
    for (i, mesh) in scene.meshes.iter().enumerate() {
        assert_eq!(mesh.instances.len(), t.len(), "one placement per instance");
        assert_eq!(mesh.positions.len(), base[i].len(), "stored once");
        for (k, placement) in mesh.instances.iter().enumerate() {
            let m = Mat4::from_scale_rotation_translation(
                Vec3::from_slice(&s[k]),
                Quat::from_slice(&r[k]).normalize(),
                Vec3::from_slice(&t[k]),
            );
            assert_eq!(placement.node, Some(node.index() as u32));
            for (object, want) in mesh.positions.iter().zip(&base[i]) {
                let (got, want) = (placement.point(*object), m.transform_point3(*want));
                assert!(got.distance(want) < 1e-4, "instance {k}: {got} vs {want}");
            }
        }
    }
    assert_eq!(
        scene.triangle_count(),
        scene.unique_triangle_count() * t.len()
    );
}

/// Object-space float POSITIONs of the first node's mesh primitives, via the gltf crate.
fn load_base_positions(
    document: &gltf::Document,
    buffers: &[gltf::buffer::Data],
) -> Vec<Vec<Vec3>> {
    let mesh = document
        .nodes()
        .next()
        .and_then(|n| n.mesh())
        .expect("mesh");
    mesh.primitives()
        .map(|p| {
            p.reader(|b| Some(&buffers[b.index()]))
                .read_positions()
                .expect("positions")
                .map(Vec3::from)
                .collect()
        })
        .collect()
}

// ---------------------------------------------------------------------------------------
// Morph targets, skins, scenes.

#[test]
fn simple_morph_uses_the_mesh_default_weights() {
    let path = khronos("SimpleMorph/glTF/SimpleMorph.gltf");
    let scene = load("SimpleMorph/glTF/SimpleMorph.gltf");
    let (document, buffers, _) = gltf::import(&path).expect("gltf crate imports the sample");
    let mesh = document.meshes().next().expect("mesh");
    let weights = mesh
        .weights()
        .expect("SimpleMorph has default weights")
        .to_vec();
    assert!(weights.iter().any(|&w| w != 0.0));
    let primitive = mesh.primitives().next().expect("primitive");
    let reader = primitive.reader(|b| Some(&buffers[b.index()]));
    let mut expected: Vec<Vec3> = reader
        .read_positions()
        .expect("positions")
        .map(Vec3::from)
        .collect();
    for (target, w) in reader.read_morph_targets().zip(&weights) {
        let deltas = target.0.expect("POSITION deltas");
        for (p, d) in expected.iter_mut().zip(deltas) {
            *p += *w * Vec3::from(d);
        }
    }
    let got = &scene.meshes[0].positions;
    assert_eq!(got.len(), expected.len());
    for (g, e) in got.iter().zip(&expected) {
        assert!(g.distance(*e) < 1e-6, "{g} vs {e}");
    }
    // And the morph changed the shape: the bounds differ from the base triangle's.
    let base_max = Vec3::new(1.0, 0.5, 0.0);
    assert!(bounds(&scene.meshes).1.distance(base_max) > 0.1);
}

/// glTF 3.7.2.2: "Attributes present in the base mesh primitive but not included in a given
/// morph target MUST retain their original values for the morph target." A quad with NORMAL
/// (+Z) and a POSITION-only target that tilts it (weight 0.5) keeps the file's normals while
/// its triangles tilt by 26.6°. (Blender's importer turns the normals with the geometry,
/// which Cycles' goldens show; three.js keeps them, as here. See docs/materials.md.)
#[test]
fn a_morph_without_normal_targets_keeps_the_files_normals() {
    let mut f = Fixture::new();
    let position = f.positions(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ]);
    let normal = f.floats(&[0.0, 0.0, 1.0].repeat(4), "VEC3", 3);
    let lift = f.positions(&[
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, 1.0],
    ]);
    let index = f.indices_u16(&[0, 1, 2, 0, 2, 3]);
    let scene = f
        .load(json!({
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "meshes": [{
                "primitives": [{
                    "attributes": {"POSITION": position, "NORMAL": normal},
                    "targets": [{"POSITION": lift}],
                    "indices": index,
                }],
                "weights": [0.5],
            }],
        }))
        .unwrap_or_else(|e| panic!("{e}"))
        .scene;
    let mesh = &scene.meshes[0];
    // The geometry is morphed: the far edge is lifted by half the delta.
    assert!((mesh.positions[2] - Vec3::new(1.0, 1.0, 0.5)).length() < 1e-6);
    let tilted = crate::support::triangle_normal(mesh, 0).normalize();
    assert!(
        tilted.dot(Vec3::Z) < 0.95,
        "the triangles must tilt ({tilted})"
    );
    for n in mesh.normals.as_ref().expect("NORMAL") {
        assert!(
            (*n - Vec3::Z).length() < 1e-6,
            "normal {n} must stay the file's +Z"
        );
    }
}

#[test]
fn multiple_scenes_scene_one_differs_from_scene_zero() {
    let pick = |scene| {
        load_at(
            "MultipleScenes/glTF/MultipleScenes.gltf",
            SceneSelection {
                scene: Some(scene),
                time: None,
                variant: None,
            },
        )
        .0
    };
    let (zero, one) = (pick(0), pick(1));
    assert_eq!(triangles(&zero), 1);
    assert_eq!(triangles(&one), 2);
    // The file's default scene is 1.
    assert_eq!(
        triangles(&load("MultipleScenes/glTF/MultipleScenes.gltf")),
        2
    );
    let missing = load_selected(
        &khronos("MultipleScenes/glTF/MultipleScenes.gltf"),
        &SceneSelection {
            scene: Some(2),
            time: None,
            variant: None,
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        missing.contains("scene 2") && missing.contains("2 scenes"),
        "{missing}"
    );
}

#[test]
fn skins_at_rest_reproduce_the_bind_pose() {
    // SimpleSkin: joints at rest are the bind pose, so skinning is the identity.
    let path = khronos("SimpleSkin/glTF/SimpleSkin.gltf");
    let (document, buffers, _) = gltf::import(&path).expect("gltf crate imports the sample");
    let primitive = document
        .meshes()
        .next()
        .unwrap()
        .primitives()
        .next()
        .unwrap();
    let bind: Vec<Vec3> = primitive
        .reader(|b| Some(&buffers[b.index()]))
        .read_positions()
        .unwrap()
        .map(Vec3::from)
        .collect();
    let scene = load("SimpleSkin/glTF/SimpleSkin.gltf");
    for (g, e) in scene.meshes[0].positions.iter().zip(&bind) {
        assert!(g.distance(*e) < 1e-5, "{g} vs {e}");
    }
    // Animated: at t = 1 s joint 1 is rotated about z, so the upper vertices move while the
    // bottom row (weighted to the root joint) stays.
    let (posed, _) = load_at(
        "SimpleSkin/glTF/SimpleSkin.gltf",
        SceneSelection {
            scene: None,
            time: Some(1.0),
            variant: None,
        },
    );
    let moved = posed.meshes[0]
        .positions
        .iter()
        .zip(&bind)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f32::max);
    assert!(moved > 0.05, "the animated skin moved by only {moved}");
    assert!(posed.meshes[0].positions[0].distance(bind[0]) < 1e-5);

    // CesiumMan: the skinned rest pose is the bind mesh placed by the skinned node's
    // parents (its inverse bind matrices invert the rest pose), a figure about 1.5 m tall.
    let cesium = load("CesiumMan/glTF-Binary/CesiumMan.glb");
    let (lo, hi) = bounds(&cesium.meshes);
    let size = hi - lo;
    assert!(
        size.is_finite() && size.max_element() > 1.0 && size.max_element() < 2.5,
        "{size}"
    );
}

// ---------------------------------------------------------------------------------------
// Animation sampling against the spec's formulas, written out independently.

/// Keyframes of one sampler, read with the gltf crate.
struct Track {
    times: Vec<f32>,
    values: Vec<Vec4>,
    interpolation: gltf::animation::Interpolation,
}

fn spec_sample(track: &Track, t: f32, rotation: bool) -> Vec4 {
    use gltf::animation::Interpolation::*;
    let cubic = track.interpolation == CubicSpline;
    let key = |k: usize| {
        if cubic {
            track.values[3 * k + 1]
        } else {
            track.values[k]
        }
    };
    let n = track.times.len();
    if t <= track.times[0] {
        return key(0);
    }
    if t >= track.times[n - 1] {
        return key(n - 1);
    }
    let k = (0..n - 1)
        .find(|&k| track.times[k] <= t && t < track.times[k + 1])
        .expect("t inside the keyframes");
    let td = track.times[k + 1] - track.times[k];
    let u = (t - track.times[k]) / td;
    match track.interpolation {
        Step => key(k),
        Linear if rotation => {
            // glTF's slerp with the shorter-arc sign.
            let (a, b) = (key(k), key(k + 1));
            let d = a.dot(b);
            let s = d.signum();
            let angle = d.abs().min(1.0).acos();
            if angle.abs() < 1e-6 {
                return a;
            }
            a * ((1.0 - u) * angle).sin() / angle.sin() + b * s * (u * angle).sin() / angle.sin()
        }
        Linear => key(k) * (1.0 - u) + key(k + 1) * u,
        CubicSpline => {
            let (v0, b0) = (track.values[3 * k + 1], track.values[3 * k + 2]);
            let (a1, v1) = (track.values[3 * (k + 1)], track.values[3 * (k + 1) + 1]);
            let p = v0 * (2.0 * u.powi(3) - 3.0 * u.powi(2) + 1.0)
                + b0 * td * (u.powi(3) - 2.0 * u.powi(2) + u)
                + v1 * (-2.0 * u.powi(3) + 3.0 * u.powi(2))
                + a1 * td * (u.powi(3) - u.powi(2));
            if rotation { p.normalize() } else { p }
        }
    }
}

#[test]
fn interpolation_test_matches_the_spec_formulas_at_chosen_times() {
    let relative = "InterpolationTest/glTF-Binary/InterpolationTest.glb";
    let (document, buffers, _) = gltf::import(khronos(relative)).expect("gltf crate imports it");
    let mut checked = 0;
    for time in [0.0f32, 0.3, 0.75, 1.1, 1.5, 2.25, 3.0, 10.0] {
        let (scene, _) = load_at(
            relative,
            SceneSelection {
                scene: None,
                time: Some(time),
                variant: None,
            },
        );
        for animation in document.animations() {
            let channel = animation.channels().next().expect("one channel");
            let node = channel.target().node();
            let reader = channel.reader(|b| Some(&buffers[b.index()]));
            let times: Vec<f32> = reader.read_inputs().expect("inputs").collect();
            use gltf::animation::util::ReadOutputs;
            let values: Vec<Vec4> = match reader.read_outputs().expect("outputs") {
                ReadOutputs::Translations(v) | ReadOutputs::Scales(v) => {
                    v.map(|x| Vec3::from(x).extend(0.0)).collect()
                }
                ReadOutputs::Rotations(r) => r.into_f32().map(Vec4::from).collect(),
                ReadOutputs::MorphTargetWeights(_) => panic!("no weights here"),
            };
            let track = Track {
                times,
                values,
                interpolation: channel.sampler().interpolation(),
            };
            let (mut t, mut r, mut s) = match node.transform() {
                gltf::scene::Transform::Decomposed {
                    translation,
                    rotation,
                    scale,
                } => (
                    Vec3::from(translation),
                    Quat::from_array(rotation),
                    Vec3::from(scale),
                ),
                gltf::scene::Transform::Matrix { .. } => panic!("animated nodes use TRS"),
            };
            use gltf::animation::Property;
            let property = channel.target().property();
            let v = spec_sample(&track, time, property == Property::Rotation);
            match property {
                Property::Translation => t = v.truncate(),
                Property::Scale => s = v.truncate(),
                Property::Rotation => r = Quat::from_vec4(v).normalize(),
                Property::MorphTargetWeights => unreachable!(),
            }
            let world = Mat4::from_scale_rotation_translation(s, r, t);
            // Every animated node is a root carrying one cube mesh.
            let name = match node.name() {
                Some(name) => format!("node \"{name}\" /"),
                None => format!("node {} /", node.index()),
            };
            let mesh = scene
                .meshes
                .iter()
                .find(|m| m.name.starts_with(&name))
                .unwrap_or_else(|| panic!("{name} has a mesh"));
            let primitive = node.mesh().unwrap().primitives().next().unwrap();
            let object: Vec<Vec3> = primitive
                .reader(|b| Some(&buffers[b.index()]))
                .read_positions()
                .unwrap()
                .map(Vec3::from)
                .collect();
            for (got, p) in mesh.positions.iter().zip(&object) {
                let want = world.transform_point3(*p);
                assert!(
                    got.distance(want) < 1e-4,
                    "{} at t = {time}: {got} vs {want}",
                    animation.name().unwrap_or("?")
                );
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 8 * 9, "nine animations at eight times");
}

#[test]
fn animations_without_a_time_are_one_warning() {
    let (_, warnings) = load_at(
        "BoxAnimated/glTF-Binary/BoxAnimated.glb",
        SceneSelection::default(),
    );
    let about: Vec<_> = warnings
        .iter()
        .filter(|w| w.contains("animation"))
        .collect();
    assert_eq!(about.len(), 1, "{warnings:?}");
    assert!(about[0].contains("--time"));
    let (rest, _) = load_at(
        "BoxAnimated/glTF-Binary/BoxAnimated.glb",
        SceneSelection::default(),
    );
    let (moved, warnings) = load_at(
        "BoxAnimated/glTF-Binary/BoxAnimated.glb",
        SceneSelection {
            scene: None,
            time: Some(1.5),
            variant: None,
        },
    );
    assert!(
        warnings.iter().all(|w| !w.contains("animation")),
        "{warnings:?}"
    );
    assert_ne!(bounds(&rest.meshes), bounds(&moved.meshes));
}

// ---------------------------------------------------------------------------------------
// Texture formats.

/// A one-triangle document whose material's base colour texture is `texture` over `images`.
fn textured_triangle(
    fixture: &mut Fixture,
    texture: serde_json::Value,
    images: serde_json::Value,
) -> serde_json::Value {
    let position = fixture.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let uv = fixture.floats(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0], "VEC2", 2);
    json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": position, "TEXCOORD_0": uv}, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "textures": [texture],
        "images": images,
        "extensionsUsed": ["EXT_texture_webp"],
        "extensionsRequired": ["EXT_texture_webp"]
    })
}

#[test]
fn ext_texture_webp_images_decode_in_place_of_the_fallback() {
    use image::ImageEncoder;
    // 2×1 texels, lossless: red and (encoded) mid grey.
    let rgba = [255u8, 0, 0, 255, 128, 128, 128, 255];
    let mut webp = Vec::new();
    image::codecs::webp::WebPEncoder::new_lossless(&mut webp)
        .write_image(&rgba, 2, 1, image::ExtendedColorType::Rgba8)
        .expect("encode WebP");
    // A black PNG fallback that must not be used.
    let fallback = support::png(1, 1, &[0, 0, 0, 255]);
    let images = json!([
        {"uri": support::data_uri("image/png", &fallback)},
        {"uri": support::data_uri("image/webp", &webp)}
    ]);
    for texture in [
        json!({"source": 0, "extensions": {"EXT_texture_webp": {"source": 1}}}),
        json!({"extensions": {"EXT_texture_webp": {"source": 1}}}),
    ] {
        let mut fixture = Fixture::new();
        let rest = textured_triangle(&mut fixture, texture, images.clone());
        let loaded = fixture.load(rest).unwrap_or_else(|e| panic!("{e}"));
        let texture = &loaded.scene.textures[0];
        assert_eq!((texture.width, texture.height), (2, 1));
        assert_eq!(texture.texels.texel(0), Vec4::new(1.0, 0.0, 0.0, 1.0));
        // sRGB 128/255 → linear 0.2158605.
        assert!(
            (texture.texels.texel(1).x - 0.215_860_5).abs() < 1e-5,
            "{}",
            texture.texels.texel(1)
        );
    }
}

#[test]
fn sixteen_bit_pngs_keep_sixteen_bits() {
    // Two texels one 16-bit step apart (values an 8-bit decode would merge).
    let (a, b) = (30000u16, 30001u16);
    let image = image::ImageBuffer::<image::Rgba<u16>, _>::from_fn(2, 1, |x, _| {
        let v = if x == 0 { a } else { b };
        image::Rgba([v, v, v, u16::MAX])
    });
    let mut png = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .expect("encode 16-bit PNG");
    let mut fixture = Fixture::new();
    let mut rest = textured_triangle(
        &mut fixture,
        json!({"source": 0}),
        json!([{"uri": support::data_uri("image/png", &png)}]),
    );
    rest.as_object_mut().unwrap().remove("extensionsUsed");
    rest.as_object_mut().unwrap().remove("extensionsRequired");
    let loaded = fixture.load(rest).unwrap_or_else(|e| panic!("{e}"));
    let texels = &loaded.scene.textures[0].texels;
    let linear = |v: u16| {
        let e = f64::from(v) / 65535.0;
        (((e + 0.055) / 1.055).powf(2.4)) as f32
    };
    for (texel, v) in texels.iter().zip([a, b]) {
        assert!(
            (texel.x - linear(v)).abs() < 2e-7,
            "{} vs {}",
            texel.x,
            linear(v)
        );
    }
    assert!(
        texels.texel(1).x > texels.texel(0).x,
        "one 16-bit step apart must stay apart"
    );
    assert_eq!(texels.bits(), 16, "16-bit codes are stored as 16 bits");
    assert_eq!(
        texels.bytes(),
        2 * 2,
        "grey and opaque: one 16-bit channel a texel"
    );
}

// ---------------------------------------------------------------------------------------
// Rendering: the compressed Ducks look like the uncompressed one.

/// Relative RMSE (over the reference's mean) and the fraction of pixels whose radiance
/// differs by more than 10 % of the reference's mean.
fn image_difference(reference: &[glam::Vec3], other: &[glam::Vec3]) -> (f64, f64) {
    let mean = reference
        .iter()
        .map(|p| f64::from(p.element_sum()) / 3.0)
        .sum::<f64>()
        / reference.len() as f64;
    let mse = reference
        .iter()
        .zip(other)
        .map(|(a, b)| f64::from((*a - *b).length_squared()) / 3.0)
        .sum::<f64>()
        / reference.len() as f64;
    let far = reference
        .iter()
        .zip(other)
        .filter(|(a, b)| f64::from((**a - **b).abs().max_element()) > 0.1 * mean)
        .count();
    (mse.sqrt() / mean, far as f64 / reference.len() as f64)
}

/// Bounds for the compressed Ducks against the uncompressed one, at 160×120, one sample at
/// each pixel centre, same camera and lights. The geometry differs by under 2·10⁻⁴ of the
/// model's size, but gltfpack also quantizes normals (8 bits) and texture coordinates (12
/// bits), which shifts shading by up to a few percent, and a pixel centre close to the
/// silhouette may hit one mesh and miss the other. Measured: rel. RMSE 0.0055 and no far-off
/// pixel for each of the three variants; a texture coordinate dequantized 9 % off gives rel.
/// RMSE 0.42 and 11 % far-off pixels.
const DUCK_REL_RMSE_MAX: f64 = 0.02;
const DUCK_FAR_PIXELS_MAX: f64 = 0.005;

#[test]
fn compressed_ducks_render_like_the_uncompressed_duck() {
    use glint::accel::{BackendKind, BuildOptions};
    use glint::render::{self, PixelSampling, RenderSettings};
    let reference_scene = load("Duck/glTF-Binary/Duck.glb");
    let camera = glint::scene::defaults::default_camera(&reference_scene);
    let lights = glint::scene::defaults::default_lights(&reference_scene, &camera);
    let settings = RenderSettings {
        integrator: glint::render::Integrator::Direct,
        width: 160,
        height: 120,
        spp: 1,
        sampling: PixelSampling::PixelCenter,
        ..RenderSettings::default()
    };
    let render = |mut scene: Scene| {
        scene.lights = lights.clone();
        let accel = render::prepare(&scene, BackendKind::Bvh, BuildOptions::default())
            .unwrap_or_else(|e| panic!("{e}"));
        render::render(&scene, accel.as_ref(), &camera, &settings, None)
            .unwrap_or_else(|e| panic!("{e}"))
            .image
            .pixels
    };
    let reference = render(reference_scene.clone());
    let lit = reference.iter().filter(|p| p.max_element() > 0.0).count();
    assert!(
        lit > reference.len() / 10,
        "the Duck fills the frame: {lit} lit pixels"
    );
    for variant in [
        "Duck/glTF-Quantized/Duck.gltf",
        "Duck/glTF-quantized-gltfpack/Duck.glb",
        #[cfg(feature = "meshopt")]
        "Duck/glTF-meshopt/Duck.glb",
    ] {
        let image = render(load(variant));
        let (rel_rmse, far) = image_difference(&reference, &image);
        eprintln!(
            "{variant}: rel. RMSE {rel_rmse:.6}, far-off pixels {:.3} %",
            100.0 * far
        );
        assert!(
            rel_rmse < DUCK_REL_RMSE_MAX && far < DUCK_FAR_PIXELS_MAX,
            "{variant}: rel. RMSE {rel_rmse}, far-off pixel fraction {far}"
        );
    }
}

#[test]
fn instancing_past_the_instance_limit_is_refused_before_reading() {
    let mut fixture = Fixture::new();
    let position = fixture.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    // No buffer view: glTF defines the data as zeros (plus one sparse value), so a huge count
    // costs the file nothing.
    let sparse_index = fixture.view(&0u32.to_le_bytes());
    let sparse_value = fixture.view(&[0u8; 12]);
    let translation = fixture.accessor(json!({
        "componentType": 5126, "count": 100_000_000, "type": "VEC3",
        "sparse": {"count": 1, "indices": {"bufferView": sparse_index, "componentType": 5125},
                   "values": {"bufferView": sparse_value}}
    }));
    let rest = json!({
        "extensionsUsed": ["EXT_mesh_gpu_instancing"],
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "extensions": {"EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": translation}}}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": position}}]}]
    });
    let message = fixture.load(rest).unwrap_err().to_string();
    assert!(
        message.contains("100000000 instances") && message.contains("EXT_mesh_gpu_instancing"),
        "{message}"
    );
}

#[test]
fn every_coverage_model_loads_and_renders_at_rest_and_animated() {
    use glint::accel::{BackendKind, BuildOptions};
    use glint::render::{self, PixelSampling, RenderSettings};
    let models = [
        "SimpleInstancing/glTF-Binary/SimpleInstancing.glb",
        "SimpleMorph/glTF/SimpleMorph.gltf",
        "SimpleSkin/glTF/SimpleSkin.gltf",
        "CesiumMan/glTF-Binary/CesiumMan.glb",
        "BoxAnimated/glTF-Binary/BoxAnimated.glb",
        "InterpolationTest/glTF-Binary/InterpolationTest.glb",
        "MultipleScenes/glTF/MultipleScenes.gltf",
        "Duck/glTF-Quantized/Duck.gltf",
        "Duck/glTF-quantized-gltfpack/Duck.glb",
        #[cfg(feature = "meshopt")]
        "Duck/glTF-meshopt/Duck.glb",
    ];
    let settings = RenderSettings {
        integrator: glint::render::Integrator::Direct,
        width: 48,
        height: 32,
        spp: 1,
        sampling: PixelSampling::PixelCenter,
        ..RenderSettings::default()
    };
    for model in models {
        for time in [None, Some(0.8)] {
            let (mut scene, _) = load_at(
                model,
                SceneSelection {
                    scene: None,
                    time,
                    variant: None,
                },
            );
            assert!(triangles(&scene) > 0, "{model}");
            // A file camera may look away from a posed mesh; the default camera frames it.
            let camera = glint::scene::defaults::default_camera(&scene);
            scene.lights = glint::scene::defaults::default_lights(&scene, &camera);
            let accel = render::prepare(&scene, BackendKind::Bvh, BuildOptions::default())
                .unwrap_or_else(|e| panic!("{model}: {e}"));
            let pixels = render::render(&scene, accel.as_ref(), &camera, &settings, None)
                .unwrap_or_else(|e| panic!("{model}: {e}"))
                .image
                .pixels;
            assert!(
                pixels
                    .iter()
                    .all(|p| p.is_finite() && p.min_element() >= 0.0),
                "{model}"
            );
            let lit = pixels.iter().filter(|p| p.max_element() > 0.0).count();
            assert!(
                lit > pixels.len() / 50,
                "{model} at {time:?}: {lit} lit pixels"
            );
        }
    }
}

#[test]
fn batch_jobs_carry_time_and_scene_index() {
    let text = r#"
        [[job]]
        scene = "a.glb"
        output = "a.png"
        scene_index = 1
        time = 0.25

        [[sweep]]
        scene = "b.glb"
        output = "b-{time}.png"
        time = [0.0, 0.5]
    "#;
    let options = glint::cli::job_options::RenderOptions;
    let jobs = glint::batch::jobs::parse(text, std::path::Path::new("/tmp/jobs.toml"), &options)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(jobs.len(), 3);
    assert_eq!(jobs[0].render.selection.scene, Some(1));
    assert_eq!(jobs[0].render.selection.time, Some(0.25));
    assert_eq!(jobs[1].render.selection.scene, None);
    let times: Vec<_> = jobs[1..].iter().map(|j| j.render.selection.time).collect();
    assert_eq!(times, vec![Some(0.0), Some(0.5)]);
}

#[cfg(not(feature = "meshopt"))]
#[test]
fn without_the_meshopt_feature_meshopt_files_are_refused_with_advice() {
    let path = khronos("Duck/glTF-meshopt/Duck.glb");
    let message = load_selected(&path, &SceneSelection::default())
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("EXT_meshopt_compression") && message.contains("`meshopt` feature"),
        "{message}"
    );
}

/// The default camera frames the vertices as drawn, not the boxes of shared meshes carried
/// through their nodes: a mesh two nodes rotate by 45° (so glint stores it once, placed
/// twice) gives the same eye, within 1e-5 of the scene's size, as the same triangles baked
/// into world space; and the eye is not the one the placed boxes would give (which grow
/// under rotation, as on a truck's wheels).
#[test]
fn the_default_camera_frames_rotated_nodes_like_the_same_geometry_baked() {
    // An octahedron: its box's corners lie far outside it, so placed boxes inflate.
    let corners: Vec<[f32; 3]> = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let indices: Vec<u16> = vec![
        0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5,
    ];
    let turn = |axis: Vec3| Quat::from_axis_angle(axis.normalize(), 45f32.to_radians());
    let nodes = [
        (turn(Vec3::Y), Vec3::new(2.0, 0.0, 0.0)),
        (turn(Vec3::new(1.0, 0.0, 1.0)), Vec3::new(-1.0, 1.5, 0.5)),
    ];
    // Rotated nodes over one shared mesh.
    let mut shared = Fixture::new();
    let position = shared.positions(&corners);
    let index = shared.indices_u16(&indices);
    let rotated = shared
        .load(json!({
            "scenes": [{"nodes": [0, 1]}],
            "nodes": nodes.iter().map(|(q, t)| json!({
                "mesh": 0,
                "rotation": [q.x, q.y, q.z, q.w],
                "translation": [t.x, t.y, t.z],
            })).collect::<Vec<_>>(),
            "meshes": [{"primitives": [{"attributes": {"POSITION": position}, "indices": index}]}],
        }))
        .unwrap_or_else(|e| panic!("{e}"))
        .scene;
    assert!(
        rotated.meshes.iter().any(|m| m.instances.len() == 2),
        "the shared mesh must be stored once and placed twice"
    );
    // The same triangles with the node transforms baked into the vertices.
    let mut baked = Fixture::new();
    let mut meshes = Vec::new();
    for (q, t) in &nodes {
        let world: Vec<[f32; 3]> = corners
            .iter()
            .map(|p| (*q * Vec3::from(*p) + *t).to_array())
            .collect();
        let position = baked.positions(&world);
        let index = baked.indices_u16(&indices);
        meshes.push(
            json!({"primitives": [{"attributes": {"POSITION": position}, "indices": index}]}),
        );
    }
    let baked = baked
        .load(json!({
            "scenes": [{"nodes": [0, 1]}],
            "nodes": [{"mesh": 0}, {"mesh": 1}],
            "meshes": meshes,
        }))
        .unwrap_or_else(|e| panic!("{e}"))
        .scene;
    let eye = |scene: &Scene| {
        glint::scene::defaults::default_camera(scene)
            .world_from_camera
            .w_axis
            .truncate()
    };
    let (lo, hi) = baked.exact_bounds().expect("vertices");
    let size = (hi - lo).length();
    let (a, b) = (eye(&rotated), eye(&baked));
    assert!(
        (a - b).length() <= 1e-5 * size,
        "rotated nodes: eye {a}, baked: eye {b} (scene size {size})"
    );
    // The placed boxes frame differently: the test would see a box-based camera.
    let (box_lo, box_hi) = rotated.bounds().expect("vertices");
    assert!(
        ((box_hi - box_lo) - (hi - lo)).length() > 0.05 * size,
        "the test needs rotations that inflate the placed boxes"
    );
}
