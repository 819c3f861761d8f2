//! The glTF loader against the shared sample scenes and against small hand-built documents
//! whose right answers follow from the glTF specification.

use crate::support::{Fixture, TempDir, data_uri, png, scenes_dir, triangle_normal};
use glam::{Affine2, Mat3, Quat, Vec2, Vec3, Vec4};
use glint::scene::gltf::{load, load_slice_with_warnings};
use glint::scene::{Light, MagFilter, Projection, SceneFeatures, WrapMode};
use serde_json::json;
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4};

const SHARED: &[&str] = &[
    "2CylinderEngine/2CylinderEngine.glb",
    "BoxTextured/BoxTextured.gltf",
    "Cameras/Cameras.gltf",
    "DamagedHelmet/glTF/DamagedHelmet.gltf",
    "Suzanne/glTF/Suzanne.gltf",
];

/// Triangles of the default scene counted from accessor counts with the `gltf` crate alone,
/// walking the node tree itself (every shared asset uses TRIANGLES mode).
fn triangles_by_gltf_crate(path: &std::path::Path) -> (usize, usize) {
    let gltf = gltf::Gltf::open(path).expect("gltf crate opens the sample");
    let scene = gltf
        .default_scene()
        .or_else(|| gltf.scenes().next())
        .expect("a scene");
    let (mut triangles, mut primitives) = (0, 0);
    let mut stack: Vec<gltf::Node> = scene.nodes().collect();
    while let Some(node) = stack.pop() {
        if let Some(mesh) = node.mesh() {
            for primitive in mesh.primitives() {
                assert_eq!(primitive.mode(), gltf::mesh::Mode::Triangles);
                let count = match primitive.indices() {
                    Some(indices) => indices.count(),
                    None => primitive
                        .get(&gltf::Semantic::Positions)
                        .expect("POSITION")
                        .count(),
                };
                triangles += count / 3;
                primitives += 1;
            }
        }
        stack.extend(node.children());
    }
    (triangles, primitives)
}

#[test]
fn shared_assets_load_with_independently_counted_triangles() {
    for name in SHARED {
        let path = scenes_dir().join(name);
        let scene = load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let (triangles, primitives) = triangles_by_gltf_crate(&path);
        assert_eq!(scene.triangle_count(), triangles, "{name}");
        // One draw per (node, primitive); a mesh several nodes draw is stored once with a
        // placement per node.
        let draws: usize = scene.meshes.iter().map(|m| m.copies()).sum();
        assert_eq!(draws, primitives, "{name}");
        assert!(scene.meshes.len() <= primitives, "{name}");
        for mesh in &scene.meshes {
            assert!(
                mesh.positions.iter().all(|p| p.is_finite()),
                "{name}: {}",
                mesh.name
            );
            assert!(
                mesh.material < scene.materials.len(),
                "{name}: {}",
                mesh.name
            );
            if let Some(normals) = &mesh.normals {
                assert_eq!(normals.len(), mesh.positions.len());
                // Unit length after the inverse-transpose transform (zero only if the source
                // normal was zero).
                assert!(
                    normals
                        .iter()
                        .all(|n| (n.length() - 1.0).abs() < 1e-3 || *n == Vec3::ZERO)
                );
            }
        }
    }
    // Hard facts: a box is 12 triangles, the Cameras sample's square 2.
    assert_eq!(
        load(&scenes_dir().join("BoxTextured/BoxTextured.gltf"))
            .unwrap()
            .triangle_count(),
        12
    );
    assert_eq!(
        load(&scenes_dir().join("Cameras/Cameras.gltf"))
            .unwrap()
            .triangle_count(),
        2
    );
}

/// BoxTextured's root node has the matrix with columns (1,0,0), (0,0,−1), (0,1,0): it maps
/// (x, y, z) to (x, z, −y). Each loaded vertex must be the file's vertex mapped by hand.
#[test]
fn box_textured_node_matrix_is_applied() {
    let path = scenes_dir().join("BoxTextured/BoxTextured.gltf");
    let scene = load(&path).unwrap();
    let (document, buffers, _) = gltf::import(&path).unwrap();
    let mesh = document.meshes().next().unwrap();
    let primitive = mesh.primitives().next().unwrap();
    let reader = primitive.reader(|b| Some(&buffers[b.index()]));
    let file_positions: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
    let file_normals: Vec<[f32; 3]> = reader.read_normals().unwrap().collect();
    let loaded = &scene.meshes[0];
    assert_eq!(loaded.positions.len(), file_positions.len());
    for (i, [x, y, z]) in file_positions.iter().copied().enumerate() {
        let expected = Vec3::new(x, z, -y);
        assert!(
            (loaded.positions[i] - expected).length() < 1e-6,
            "vertex {i}"
        );
        let [nx, ny, nz] = file_normals[i];
        let normal = loaded.normals.as_ref().unwrap()[i];
        assert!(
            (normal - Vec3::new(nx, nz, -ny)).length() < 1e-5,
            "normal {i}"
        );
    }
    // A rotation keeps the winding: every face's geometric normal agrees with its shading
    // normals.
    for t in 0..loaded.indices.len() {
        let n = triangle_normal(loaded, t);
        let shading = loaded.normals.as_ref().unwrap()[loaded.indices[t][0] as usize];
        assert!(n.dot(shading) > 0.0, "triangle {t}");
    }
    // Its sampler: wrapS MIRRORED_REPEAT, wrapT CLAMP_TO_EDGE, magFilter LINEAR.
    let material = &scene.materials[loaded.material];
    let texture = &scene.textures[material.base_color_texture.unwrap().texture];
    assert_eq!(texture.wrap_s, WrapMode::MirroredRepeat);
    assert_eq!(texture.wrap_t, WrapMode::ClampToEdge);
    assert_eq!(texture.mag_filter, MagFilter::Linear);
    assert_eq!(
        texture.texels.len(),
        (texture.width * texture.height) as usize
    );
}

/// Cameras.gltf: node 1 holds a perspective camera (yfov 0.7, aspect 1), node 2 an
/// orthographic one (xmag = ymag = 1), both at (0.5, 0.5, 3) without rotation.
#[test]
fn cameras_file_gives_both_projections() {
    let scene = load(&scenes_dir().join("Cameras/Cameras.gltf")).unwrap();
    assert_eq!(scene.cameras.len(), 2);
    assert_eq!(
        scene.cameras[0].projection,
        Projection::Perspective {
            yfov: 0.7,
            aspect_ratio: Some(1.0)
        }
    );
    assert_eq!(
        scene.cameras[1].projection,
        Projection::Orthographic {
            xmag: 1.0,
            ymag: 1.0
        }
    );
    for camera in &scene.cameras {
        let m = camera.world_from_camera;
        assert!((m.w_axis.truncate() - Vec3::new(0.5, 0.5, 3.0)).length() < 1e-6);
        assert!((Mat3::from_mat4(m) - Mat3::IDENTITY).abs_diff_eq(Mat3::ZERO, 1e-6));
    }
}

/// A scaled, rotated camera node: the scale is removed and the viewing direction kept.
#[test]
fn camera_scale_is_removed() {
    let rotation = Quat::from_rotation_y(0.6) * Quat::from_rotation_x(-0.3);
    let loaded = Fixture::new()
        .load(json!({
            "scene": 0,
            "scenes": [{"nodes": [0]}],
            "nodes": [{"camera": 0, "translation": [1, 2, 3], "rotation": rotation.to_array(), "scale": [2, 3, 0.5]}],
            "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}]
        }))
        .unwrap();
    let m = loaded.scene.cameras[0].world_from_camera;
    let expected_forward = rotation * Vec3::NEG_Z;
    assert!((m.transform_vector3(Vec3::NEG_Z) - expected_forward).length() < 1e-5);
    assert!((m.transform_vector3(Vec3::Y) - rotation * Vec3::Y).length() < 1e-5);
    assert!(
        (Mat3::from_mat4(m).determinant() - 1.0).abs() < 1e-5,
        "rigid, unscaled"
    );
    assert!((m.w_axis.truncate() - Vec3::new(1.0, 2.0, 3.0)).length() < 1e-6);
}

/// A closed tetrahedron with outward winding and normals, instanced by a node.
fn tetrahedron(fixture: &mut Fixture) -> serde_json::Value {
    // Four faces with their own vertices (flat normals), wound counter-clockwise from outside.
    let corners = [
        [1.0, 1.0, 1.0],
        [1.0, -1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [-1.0, -1.0, 1.0],
    ];
    let faces = [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]];
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut tangents = Vec::new();
    for face in faces {
        let [a, b, c] = face.map(|i| Vec3::from(corners[i]));
        let n = (b - a).cross(c - a).normalize();
        assert!(n.dot(a + b + c) > 0.0, "fixture faces must wind outwards");
        for p in [a, b, c] {
            positions.push(p.to_array());
            normals.extend(n.to_array());
            tangents.extend((b - a).normalize().extend(1.0).to_array());
        }
    }
    let position = fixture.positions(&positions);
    let normal = fixture.floats(&normals, "VEC3", 3);
    let tangent = fixture.floats(&tangents, "VEC4", 4);
    json!({"primitives": [{"attributes": {"POSITION": position, "NORMAL": normal, "TANGENT": tangent}}]})
}

/// Under a mirroring node the triangles must still wind outwards, shading normals must
/// still point outwards, and the tangent frame's handedness must flip.
#[test]
fn negative_scale_keeps_outward_normals() {
    for (label, nodes) in [
        (
            "mirror x",
            json!([{"mesh": 0, "scale": [-1, 1, 1], "translation": [5, 0, 0]}]),
        ),
        (
            "mirror by matrix",
            json!([{"mesh": 0, "matrix": [2,0,0,0, 0,-1,0,0, 0,0,1,0, 0,0,0,1]}]),
        ),
        // Two mirrors cancel: parent mirrors x, child mirrors y.
        (
            "double mirror",
            json!([{"children": [1], "scale": [-1, 1, 1]}, {"mesh": 0, "scale": [1, -1, 1]}]),
        ),
    ] {
        let mut fixture = Fixture::new();
        let mesh = tetrahedron(&mut fixture);
        let loaded = fixture
            .load(json!({"scenes": [{"nodes": [0]}], "nodes": nodes, "meshes": [mesh]}))
            .unwrap();
        let mesh = &loaded.scene.meshes[0];
        let centre = mesh.positions.iter().copied().sum::<Vec3>() / mesh.positions.len() as f32;
        let mirrored = label != "double mirror";
        for t in 0..mesh.indices.len() {
            let [a, b, c] = mesh.indices[t].map(|i| mesh.positions[i as usize]);
            let outward = (a + b + c) / 3.0 - centre;
            let geometric = triangle_normal(mesh, t);
            assert!(
                geometric.dot(outward) > 0.0,
                "{label}: triangle {t} winds inwards"
            );
            for i in mesh.indices[t] {
                let shading = mesh.normals.as_ref().unwrap()[i as usize];
                assert!(
                    shading.dot(outward) > 0.0,
                    "{label}: normal of vertex {i} points inwards"
                );
                assert!((shading.length() - 1.0).abs() < 1e-5);
                let tangent = mesh.tangents.as_ref().unwrap()[i as usize];
                assert_eq!(tangent.w, if mirrored { -1.0 } else { 1.0 }, "{label}");
            }
        }
    }
}

/// Non-uniform scale: normals go through the inverse transpose and stay perpendicular to
/// the transformed surface.
#[test]
fn normals_stay_perpendicular_under_non_uniform_scale() {
    let mut fixture = Fixture::new();
    let positions = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 1.0]];
    let n = (Vec3::from(positions[1]) - Vec3::from(positions[0]))
        .cross(Vec3::from(positions[2]) - Vec3::from(positions[0]))
        .normalize();
    let position = fixture.positions(&positions);
    let normal = fixture.floats(&[n.to_array(); 3].concat(), "VEC3", 3);
    let loaded = fixture
        .load(json!({
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0, "scale": [1, 4, 0.5], "rotation": Quat::from_rotation_z(0.4).to_array()}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": position, "NORMAL": normal}}]}]
        }))
        .unwrap();
    let mesh = &loaded.scene.meshes[0];
    let normal = mesh.normals.as_ref().unwrap()[0];
    for edge in [
        mesh.positions[1] - mesh.positions[0],
        mesh.positions[2] - mesh.positions[0],
    ] {
        assert!(normal.dot(edge.normalize()).abs() < 1e-5);
    }
    assert!(normal.dot(triangle_normal(mesh, 0)) > 0.0);
}

/// Parent transforms apply after the child's: parent T(10,0,0)·R_y(90°) maps the child's
/// translation (1,0,0) to (10, 0, −1).
#[test]
fn hierarchy_composes_parent_after_child() {
    let mut fixture = Fixture::new();
    let position = fixture.positions(&[[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    let loaded = fixture
        .load(json!({
            "scenes": [{"nodes": [0]}],
            "nodes": [
                {"children": [1], "translation": [10, 0, 0], "rotation": Quat::from_rotation_y(FRAC_PI_2).to_array()},
                {"mesh": 0, "translation": [1, 0, 0]}
            ],
            "meshes": [{"primitives": [{"attributes": {"POSITION": position}}]}]
        }))
        .unwrap();
    let mesh = &loaded.scene.meshes[0];
    assert!((mesh.positions[0] - Vec3::new(10.0, 0.0, -1.0)).length() < 1e-5);
    // The child's local +Z (vertex 2) turns into world +X.
    assert!((mesh.positions[2] - mesh.positions[0] - Vec3::X).length() < 1e-5);
    assert_eq!(mesh.name, "node 1 / mesh 0 / primitive 0");
    assert_eq!(mesh.indices, vec![[0, 1, 2]], "non-indexed TRIANGLES");
}

/// Strips and fans become the triangles the glTF specification defines, all facing the
/// same way as the first.
#[test]
fn strip_and_fan_become_spec_triangles() {
    let mut fixture = Fixture::new();
    // A planar zig-zag (strip) and a planar fan around vertex 0, both counter-clockwise
    // seen from +Z.
    let strip = fixture.positions(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 2.0, 0.0],
    ]);
    let strip_indices = fixture.indices_u16(&[0, 1, 2, 3, 4]);
    let fan = fixture.positions(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
    ]);
    let loaded = fixture
        .load(json!({
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [
                {"attributes": {"POSITION": strip}, "indices": strip_indices, "mode": 5},
                {"attributes": {"POSITION": fan}, "mode": 6}
            ]}]
        }))
        .unwrap();
    let [strip, fan] = [&loaded.scene.meshes[0], &loaded.scene.meshes[1]];
    // Strip triangle i: (v_i, v_{i+1+i%2}, v_{i+2-i%2}); fan triangle i: (v_{i+1}, v_{i+2}, v_0).
    assert_eq!(strip.indices, vec![[0, 1, 2], [1, 3, 2], [2, 3, 4]]);
    assert_eq!(fan.indices, vec![[1, 2, 0], [2, 3, 0], [3, 4, 0]]);
    for mesh in [strip, fan] {
        for t in 0..mesh.indices.len() {
            assert!(
                triangle_normal(mesh, t).z > 0.0,
                "{}: triangle {t} flipped",
                mesh.name
            );
        }
    }
}

/// KHR_texture_transform's worked example (offset (0, 1), rotation π/2, scale ½) uses the
/// lower-left quadrant of the image rotated clockwise: uv (0,0) → (0,1), (1,0) → (0,½),
/// (0,1) → (½,1). Its texCoord overrides the textureInfo's.
#[test]
fn texture_transform_matches_the_spec_example() {
    let mut fixture = Fixture::new();
    let position = fixture.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let loaded = fixture
        .load(json!({
            "extensionsUsed": ["KHR_texture_transform"],
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": position}, "material": 0}]}],
            "materials": [{
                "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 0, "extensions": {
                    "KHR_texture_transform": {"offset": [0, 1], "rotation": FRAC_PI_2, "scale": [0.5, 0.5], "texCoord": 1}
                }}},
                "emissiveTexture": {"index": 0}
            }],
            "textures": [{"source": 0}],
            "images": [{"uri": data_uri("image/png", &png(1, 1, &[255, 255, 255, 255]))}]
        }))
        .unwrap();
    let material = &loaded.scene.materials[0];
    let base = material.base_color_texture.unwrap();
    assert_eq!(base.texcoord, 1);
    for (uv, expected) in [
        ((0.0, 0.0), (0.0, 1.0)),
        ((1.0, 0.0), (0.0, 0.5)),
        ((0.0, 1.0), (0.5, 1.0)),
    ] {
        let got = base.transform.transform_point2(Vec2::new(uv.0, uv.1));
        assert!(
            (got - Vec2::new(expected.0, expected.1)).length() < 1e-6,
            "{uv:?} → {got}"
        );
    }
    let emissive = material.emissive_texture.unwrap();
    assert_eq!(emissive.transform, Affine2::IDENTITY);
    assert_eq!(emissive.texcoord, 0);
    // Same image, same colour space: decoded once, shared.
    assert_eq!(emissive.texture, base.texture);
    assert_eq!(loaded.scene.textures.len(), 1);
}

/// Base colour textures are sRGB: code 128 decodes to ((128/255 + 0.055)/1.055)^2.4 =
/// 0.2158605, code 10 lies on the linear segment (10/255/12.92), alpha stays linear.
#[test]
fn srgb_texels_decode_with_the_exact_curve() {
    let mut fixture = Fixture::new();
    let position = fixture.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let image = png(2, 1, &[128, 10, 255, 128, 0, 0, 0, 255]);
    let loaded = fixture
        .load(json!({
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": position}, "material": 0}]}],
            "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
            "textures": [{"source": 0, "sampler": 0}],
            "samplers": [{"magFilter": 9728, "wrapS": 33071}],
            "images": [{"uri": data_uri("image/png", &image)}]
        }))
        .unwrap();
    let texture = &loaded.scene.textures[0];
    assert_eq!((texture.width, texture.height), (2, 1));
    let texel = texture.texels.texel(0);
    assert!((texel.x - 0.2158605).abs() < 1e-6, "{texel}");
    assert!((texel.y - 10.0 / 255.0 / 12.92).abs() < 1e-7, "{texel}");
    assert_eq!(texel.z, 1.0);
    assert!((texel.w - 128.0 / 255.0).abs() < 1e-7, "alpha is linear");
    assert_eq!(texture.texels.texel(1), Vec4::new(0.0, 0.0, 0.0, 1.0));
    assert_eq!(texture.mag_filter, MagFilter::Nearest);
    assert_eq!(
        (texture.wrap_s, texture.wrap_t),
        (WrapMode::ClampToEdge, WrapMode::Repeat)
    );
}

/// Point, spot and directional lights: positions from the composed transforms, directions
/// along world −Z, `intensity × color`, spot defaults 0 and π/4, range carried.
#[test]
fn punctual_lights_in_world_space() {
    // Rotating −Z onto −Y: a −90° turn about X.
    let down = Quat::from_rotation_x(-FRAC_PI_2);
    let loaded = Fixture::new()
        .load(json!({
            "extensionsUsed": ["KHR_lights_punctual"],
            "extensions": {"KHR_lights_punctual": {"lights": [
                {"type": "point", "intensity": 10, "color": [1, 0.5, 0.25], "range": 4},
                {"type": "spot", "intensity": 2, "spot": {}},
                {"type": "directional", "intensity": 3},
                {"type": "spot", "intensity": 1, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}
            ]}},
            "scenes": [{"nodes": [0, 2, 3, 5]}],
            "nodes": [
                {"children": [1], "translation": [10, 0, 0], "scale": [2, 2, 2]},
                {"translation": [1, 2, 3], "extensions": {"KHR_lights_punctual": {"light": 0}}},
                {"translation": [0, 5, 0], "rotation": down.to_array(), "extensions": {"KHR_lights_punctual": {"light": 1}}},
                {"children": [4], "rotation": Quat::from_rotation_z(0.3).to_array(), "scale": [3, 1, 1]},
                {"rotation": down.to_array(), "extensions": {"KHR_lights_punctual": {"light": 2}}},
                {"extensions": {"KHR_lights_punctual": {"light": 3}}}
            ]
        }))
        .unwrap();
    let lights = &loaded.scene.lights;
    assert_eq!(lights.len(), 4);
    assert_eq!(
        lights[0],
        Light::Point {
            position: Vec3::new(12.0, 4.0, 6.0),
            intensity: Vec3::new(10.0, 5.0, 2.5),
            range: Some(4.0)
        }
    );
    let Light::Spot {
        position,
        direction,
        intensity,
        range,
        cos_inner,
        cos_outer,
    } = lights[1]
    else {
        panic!("light 1 must be a spot: {:?}", lights[1])
    };
    assert!((position - Vec3::new(0.0, 5.0, 0.0)).length() < 1e-6);
    assert!((direction - Vec3::NEG_Y).length() < 1e-6);
    assert_eq!(intensity, Vec3::splat(2.0));
    assert_eq!(range, None);
    assert_eq!(cos_inner, 1.0);
    assert!((cos_outer - FRAC_PI_4.cos()).abs() < 1e-6);
    let Light::Directional {
        direction,
        irradiance,
    } = lights[2]
    else {
        panic!("light 2 must be directional: {:?}", lights[2])
    };
    // World −Z: parent R_z(0.3)·S(3,1,1) applied to the child's −Y, then normalised.
    let expected =
        (Quat::from_rotation_z(0.3) * (Vec3::new(3.0, 1.0, 1.0) * Vec3::NEG_Y)).normalize();
    assert!((direction - expected).length() < 1e-6);
    assert!((direction.length() - 1.0).abs() < 1e-6);
    assert_eq!(irradiance, Vec3::splat(3.0));
    let Light::Spot {
        direction,
        cos_inner,
        cos_outer,
        ..
    } = lights[3]
    else {
        panic!("light 3 must be a spot: {:?}", lights[3])
    };
    assert_eq!(direction, Vec3::NEG_Z, "an unrotated node points down −Z");
    assert_eq!((cos_inner, cos_outer), (0.2f32.cos(), 0.5f32.cos()));
}

/// COLOR_0 as normalized UNSIGNED_BYTE RGB and TEXCOORD_0 as normalized UNSIGNED_SHORT become
/// floats c / (2ⁿ − 1), with alpha 1 for RGB colours.
#[test]
fn normalized_integer_attributes_become_floats() {
    let mut fixture = Fixture::new();
    let position = fixture.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let colors = [255u8, 0, 51, 0, 128, 255, 10, 20, 30];
    let mut padded = Vec::new();
    for rgb in colors.chunks(3) {
        padded.extend_from_slice(rgb);
        padded.push(0); // vertex attributes are 4-byte aligned
    }
    let view = fixture.view(&padded);
    fixture.views[view]["byteStride"] = json!(4);
    let color = fixture.accessor(json!({"bufferView": view, "componentType": 5121, "normalized": true, "count": 3, "type": "VEC3"}));
    let uv: Vec<u8> = [0u16, 65535, 32768, 0, 65535, 65535]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    let view = fixture.view(&uv);
    let texcoord = fixture.accessor(json!({"bufferView": view, "componentType": 5123, "normalized": true, "count": 3, "type": "VEC2"}));
    let loaded = fixture
        .load(json!({
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": position, "COLOR_0": color, "TEXCOORD_0": texcoord}}]}]
        }))
        .unwrap();
    let mesh = &loaded.scene.meshes[0];
    let colors_out = mesh.colors.as_ref().unwrap();
    let close = |a: Vec4, b: Vec4| (a - b).abs().max_element() < 1e-6;
    assert!(
        close(colors_out[0], Vec4::new(1.0, 0.0, 51.0 / 255.0, 1.0)),
        "{}",
        colors_out[0]
    );
    assert!(
        close(
            colors_out[2],
            Vec4::new(10.0 / 255.0, 20.0 / 255.0, 30.0 / 255.0, 1.0)
        ),
        "{}",
        colors_out[2]
    );
    let uvs = mesh.texcoords[0].as_ref().unwrap();
    assert_eq!(uvs[0], Vec2::new(0.0, 1.0));
    assert!((uvs[1].x - 32768.0 / 65535.0).abs() < 1e-7);
    assert!(mesh.texcoords[1].is_none());
}

/// A primitive without a material gets glTF's default one (white, metallic 1, roughness 1,
/// single-sided), appended after the file's materials; emissive strength multiplies.
#[test]
fn default_material_and_emissive_strength() {
    let mut fixture = Fixture::new();
    let position = fixture.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let loaded = fixture
        .load(json!({
            "extensionsUsed": ["KHR_materials_emissive_strength"],
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [
                {"attributes": {"POSITION": position}},
                {"attributes": {"POSITION": position}, "material": 0}
            ]}],
            "materials": [{"name": "lamp", "emissiveFactor": [1, 0.5, 0.25], "doubleSided": true,
                "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.2, 0.3, 1], "metallicFactor": 0, "roughnessFactor": 0.5},
                "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}}}]
        }))
        .unwrap();
    let scene = &loaded.scene;
    assert_eq!(scene.materials.len(), 2);
    let default = &scene.materials[scene.meshes[0].material];
    assert_eq!(scene.meshes[0].material, 1);
    assert_eq!(
        (default.base_color, default.metallic, default.roughness),
        (Vec4::ONE, 1.0, 1.0)
    );
    assert!(!default.double_sided);
    let lamp = &scene.materials[scene.meshes[1].material];
    assert_eq!(lamp.name, "lamp");
    assert_eq!(lamp.emissive, Vec3::new(4.0, 2.0, 1.0));
    assert_eq!(lamp.base_color, Vec4::new(0.1, 0.2, 0.3, 1.0));
    assert_eq!(
        (lamp.metallic, lamp.roughness, lamp.double_sided),
        (0.0, 0.5, true)
    );
}

/// Line primitives are skipped with a warning naming the primitive; the triangles load.
#[test]
fn line_primitives_are_skipped_with_a_warning() {
    let mut fixture = Fixture::new();
    let position = fixture.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let loaded = fixture
        .load(json!({
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0, "name": "wire"}],
            "meshes": [{"primitives": [
                {"attributes": {"POSITION": position}, "mode": 1},
                {"attributes": {"POSITION": position}}
            ]}]
        }))
        .unwrap();
    assert_eq!(loaded.scene.meshes.len(), 1);
    assert_eq!(
        loaded.scene.meshes[0].name,
        "node \"wire\" / mesh 0 / primitive 1"
    );
    assert_eq!(loaded.warnings.len(), 1, "{:?}", loaded.warnings);
    let warning = &loaded.warnings[0];
    assert!(
        warning.contains("fixture.gltf")
            && warning.contains("node \"wire\" / mesh 0 / primitive 0"),
        "{warning}"
    );
    assert!(
        warning.contains("Lines") && warning.contains("skipped"),
        "{warning}"
    );
}

/// A `.gltf` with an external `.bin` (percent-escaped name) and an external PNG loads from
/// disk, and so does the same scene as `.glb`-free data URIs.
#[test]
fn external_files_resolve_next_to_the_scene() {
    let dir = TempDir::new("external");
    let mut fixture = Fixture::new();
    let position = fixture.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    dir.write("my data.bin", &fixture.bin);
    dir.write("tex.png", &png(1, 1, &[0, 255, 0, 255]));
    let mut doc = fixture.document(json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": position}, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "textures": [{"source": 0}],
        "images": [{"uri": "tex.png"}]
    }));
    doc["buffers"][0]["uri"] = json!("my%20data.bin");
    let path = dir.write(
        "scene.gltf",
        serde_json::to_string(&doc).unwrap().as_bytes(),
    );
    let scene = load(&path).unwrap();
    assert_eq!(scene.triangle_count(), 1);
    assert_eq!(
        scene.textures[0].texels.texel(0),
        Vec4::new(0.0, 1.0, 0.0, 1.0)
    );
}

/// The embedded demo scene shows every feature glint renders, loads without warnings, and
/// its lights give lit radiances in the intended 0.1–1 W/(m²·sr) range.
#[test]
fn demo_scene_has_every_feature() {
    let loaded = load_slice_with_warnings(glint::scene::demo::DEMO_GLB, "demo.glb", None).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let scene = glint::scene::demo::demo_scene().unwrap();
    assert!(glint::scene::demo::DEMO_GLB.len() < 300 * 1024);
    let features = SceneFeatures::of(&scene);
    assert!(features.point_lights && features.spot_lights && features.directional_lights);
    assert!(features.mirrors && features.textures && features.emission);
    // Issue 14's demo: a normal-mapped surface and an alpha-cut one, and metal-rough spheres
    // with metallic 0 and 1 each at several roughnesses.
    assert!(features.normal_maps && features.alpha, "{features:?}");
    for metallic in [0.0, 1.0] {
        let mut roughness: Vec<f32> = scene
            .materials
            .iter()
            .filter(|m| m.metallic == metallic)
            .map(|m| m.roughness)
            .collect();
        roughness.sort_by(f32::total_cmp);
        roughness.dedup();
        assert!(roughness.len() >= 5, "metallic {metallic}: {roughness:?}");
    }
    assert_eq!(scene.cameras.len(), 1);
    assert!(
        scene
            .materials
            .iter()
            .any(|m| m.metallic == 1.0 && m.roughness == 0.0)
    );
    // The camera sees every object: each mesh's centre lies inside its field of view.
    let camera = &scene.cameras[0];
    let Projection::Perspective { yfov, .. } = camera.projection else {
        panic!("the demo camera is perspective")
    };
    let eye = camera.world_from_camera.w_axis.truncate();
    let forward = camera.world_from_camera.transform_vector3(Vec3::NEG_Z);
    for mesh in &scene.meshes {
        let centre = mesh.positions.iter().copied().sum::<Vec3>() / mesh.positions.len() as f32;
        let angle = forward.angle_between(centre - eye);
        assert!(
            angle < 0.5 * yfov,
            "{} is out of view ({angle} rad)",
            mesh.name
        );
    }
    // Every object sits on or above the floor plane y = 0.
    let (lo, _) = scene.bounds().unwrap();
    assert!(lo.y > -1e-5, "{lo}");
    // The point light over the floor: L = ρ/π · I/d² with the floor's albedo.
    let floor = scene
        .meshes
        .iter()
        .find(|m| m.name.contains("\"floor\""))
        .expect("floor");
    let albedo = scene.materials[floor.material].base_color.x;
    for light in &scene.lights {
        if let Light::Point {
            position,
            intensity,
            ..
        } = light
        {
            let radiance =
                albedo / std::f32::consts::PI * intensity.max_element() / (position.y * position.y);
            assert!(
                (0.1..1.0).contains(&radiance),
                "floor radiance under the point light: {radiance}"
            );
        }
        if let Light::Directional { irradiance, .. } = light {
            let radiance = albedo / std::f32::consts::PI * irradiance.max_element();
            assert!(
                (0.1..1.0).contains(&radiance),
                "floor radiance under the sun: {radiance}"
            );
        }
    }
}

/// The demo's environment map (`scenes/demo-env.hdr`, passed by `scripts/demo.sh`) stays
/// small and is the shared studio HDRI averaged down: its mean radiance (solid-angle weighted)
/// matches the full-resolution original's within 1 % per channel (box-averaging 4×4 blocks
/// keeps the texel mean; the rest is RGBE rounding, ≤ 0.4 %, and the sin θ weight varying
/// inside a block).
#[test]
fn demo_environment_is_the_studio_hdri_downscaled() {
    use glint::light::EnvironmentLight;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let small_path = root.join("scenes/demo-env.hdr");
    assert!(std::fs::metadata(&small_path).unwrap().len() < 200 * 1024);
    assert!(root.join("scenes/demo-env-LICENSE.txt").exists());
    let small = EnvironmentLight::from_file(&small_path, 1.0, 0.0).unwrap();
    assert_eq!(small.size(), Some((256, 128)));
    let original = root.join("../shared/env/studio.hdr");
    if !original.exists() {
        eprintln!("skipping the comparison: {} is absent", original.display());
        return;
    }
    let full = EnvironmentLight::from_file(&original, 1.0, 0.0).unwrap();
    let (a, b) = (small.average_radiance(), full.average_radiance());
    for (x, y) in a.to_array().into_iter().zip(b.to_array()) {
        assert!((x / y - 1.0).abs() < 0.01, "{a} vs {b}");
    }
}

/// A sparse POSITION accessor replaces the listed vertices of its base data; a TRIANGLES
/// index count that is not a multiple of 3 drops the remainder with a warning.
#[test]
fn sparse_positions_and_leftover_indices() {
    let mut fixture = Fixture::new();
    let position = fixture.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let sparse_indices = fixture.view(&1u16.to_le_bytes());
    let sparse_values: Vec<u8> = [5.0f32, 0.0, 0.0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    let sparse_values = fixture.view(&sparse_values);
    fixture.accessors[position]["sparse"] = json!({
        "count": 1,
        "indices": {"bufferView": sparse_indices, "componentType": 5123},
        "values": {"bufferView": sparse_values}
    });
    fixture.accessors[position]["max"] = json!([5, 1, 0]);
    let indices = fixture.indices_u16(&[0, 1, 2, 2, 1]);
    let loaded = fixture
        .load(json!({
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": position}, "indices": indices}]}]
        }))
        .unwrap();
    let mesh = &loaded.scene.meshes[0];
    assert_eq!(
        mesh.positions,
        vec![Vec3::ZERO, Vec3::new(5.0, 0.0, 0.0), Vec3::Y]
    );
    assert_eq!(mesh.indices, vec![[0, 1, 2]]);
    assert_eq!(loaded.warnings.len(), 1, "{:?}", loaded.warnings);
    assert!(
        loaded.warnings[0].contains("5 indices are not a multiple of 3"),
        "{}",
        loaded.warnings[0]
    );
}
