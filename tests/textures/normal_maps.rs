//! Normal maps: closed forms on hand-built quads (through the glTF loader, with the normal
//! texture written as a PNG here), the tangent handedness, mirrored nodes, MikkTSpace against
//! the supplied tangents of a Khronos model, and the summary line of scenes without them.

use crate::support::{Fixture, data_uri, png};
use crate::support::{centre_settings, ortho, render_with};
use glam::{Vec3, Vec4};
use glint::accel::BackendKind;
use glint::render::{Integrator, RenderSettings};
use glint::scene::{Light, Scene};
use serde_json::{Value, json};
use std::path::Path;

/// Base colour of the test quads (white-ish, Lambertian).
const RHO: f32 = 0.8;
/// Irradiance of the directional light, W/m².
const E: f32 = 2.0;

/// The 8-bit texel that encodes the unit tangent-space normal `m`, and the normal the
/// renderer must decode from it with `scale` (the quantised value, so the closed form is
/// exact rather than off by the PNG's rounding).
fn texel_for(m: Vec3, scale: f32) -> ([u8; 3], Vec3) {
    let bytes = ((m + Vec3::ONE) * 0.5 * 255.0)
        .round()
        .to_array()
        .map(|c| c as u8);
    let decoded = Vec3::from(bytes.map(|b| b as f32 / 255.0)) * 2.0 - Vec3::ONE;
    (bytes, (decoded * Vec3::new(scale, scale, 1.0)).normalize())
}

/// A 2 m quad in the z = 0 plane facing +Z, u along +x and v along −y (glTF's v points down
/// the image, so this is the unmirrored mapping: tangent +X, bitangent +Y, w = +1), with a
/// constant 4×4 normal texture `texel`. `tangent_w` supplies TANGENT (1, 0, 0, w); `None`
/// leaves it to MikkTSpace. `node` is the node's JSON (its transform).
fn quad_document(
    texel: [u8; 3],
    scale: f32,
    tangent_w: Option<f32>,
    node: Value,
) -> (Fixture, Value) {
    let mut f = Fixture::new();
    let positions = f.positions(&[
        [-1.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
    ]);
    let normals = f.floats(&[0.0, 0.0, 1.0].repeat(4), "VEC3", 3);
    let uvs = f.floats(&[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0], "VEC2", 2);
    let indices = f.indices_u16(&[0, 1, 2, 0, 2, 3]);
    let mut attributes = json!({"POSITION": positions, "NORMAL": normals, "TEXCOORD_0": uvs});
    if let Some(w) = tangent_w {
        let tangents = f.floats(&[1.0, 0.0, 0.0, w].repeat(4), "VEC4", 4);
        attributes["TANGENT"] = json!(tangents);
    }
    let rgba: Vec<u8> = (0..16)
        .flat_map(|_| [texel[0], texel[1], texel[2], 255])
        .collect();
    let mut node = node;
    node["mesh"] = json!(0);
    let rest = json!({
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [node],
        "meshes": [{"primitives": [{"attributes": attributes, "indices": indices, "material": 0}]}],
        "materials": [{
            "pbrMetallicRoughness": {
                "baseColorFactor": [RHO, RHO, RHO, 1.0],
                "metallicFactor": 0.0,
                "roughnessFactor": 1.0
            },
            "normalTexture": {"index": 0, "scale": scale},
            // A pure Lambertian for the path tracer too (no dielectric specular lobe).
            "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}
        }],
        "extensionsUsed": ["KHR_materials_specular"],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": 9728, "minFilter": 9728}],
        "images": [{"uri": data_uri("image/png", &png(4, 4, &rgba))}]
    });
    (f, rest)
}

/// Loads the document, adds a directional light arriving from `to_light`, and renders it at
/// 1 spp through pixel centres with an orthographic camera looking down −Z; returns the
/// image's centre pixel (which sees the quad's middle) and the scene.
fn render_centre(
    f: &Fixture,
    rest: Value,
    to_light: Vec3,
    integrator: Integrator,
) -> (Vec3, Scene) {
    let loaded = f.load(rest).expect("fixture loads");
    let mut scene = loaded.scene;
    scene.lights = vec![Light::Directional {
        direction: -to_light.normalize(),
        irradiance: Vec3::splat(E),
    }];
    let camera = ortho(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y, 0.5, 0.5);
    let settings = RenderSettings {
        integrator,
        max_depth: 1,
        ..centre_settings(4, 4)
    };
    let out = render_with(&scene, &camera, BackendKind::Bvh, &settings);
    (out.image.pixels[4 + 1], scene)
}

/// The closed form: a Lambertian surface of normal `n` under the light, ρ/π · E · max(0, n·l).
fn lambert(n: Vec3, to_light: Vec3) -> f32 {
    RHO / std::f32::consts::PI * E * n.dot(to_light.normalize()).max(0.0)
}

fn assert_close(got: Vec3, want: f32, what: &str) {
    for c in got.to_array() {
        assert!(
            (c - want).abs() <= 2e-4 * want.max(1e-3),
            "{what}: rendered {got}, closed form {want}"
        );
    }
}

/// A constant normal map tilted by 35° (toward +x and +y) shades the flat quad exactly like
/// the closed form for a quad tilted that way, with supplied tangents and with MikkTSpace's,
/// in the direct integrator and the path tracer; and a geometrically tilted quad without a
/// normal map gives the same value.
#[test]
fn a_tilted_constant_normal_map_shades_like_a_tilted_quad() {
    let tilt = 35f32.to_radians();
    let m = Vec3::new(tilt.sin() * 0.8, tilt.sin() * 0.6, tilt.cos());
    let (texel, n) = texel_for(m, 1.0);
    let to_light = Vec3::new(0.5, 0.2, 1.0);
    let want = lambert(n, to_light);
    // The map must matter: the flat quad's value differs by far more than the tolerance.
    assert!((want - lambert(Vec3::Z, to_light)).abs() > 0.05 * want);
    for tangents in [Some(1.0), None] {
        for integrator in [Integrator::Direct, Integrator::Path] {
            let (f, rest) = quad_document(texel, 1.0, tangents, json!({}));
            let (got, scene) = render_centre(&f, rest, to_light, integrator);
            assert_close(got, want, &format!("tangents {tangents:?}, {integrator:?}"));
            assert!(scene.meshes[0].tangents.is_some());
        }
    }

    // The same normal as geometry: the quad rotated so that its face normal is n.
    let rotation = glam::Quat::from_rotation_arc(Vec3::Z, n);
    let (f, mut rest) = quad_document(
        texel,
        1.0,
        Some(1.0),
        json!({"rotation": rotation.to_array()}),
    );
    rest["materials"][0]
        .as_object_mut()
        .expect("material object")
        .remove("normalTexture");
    let (tilted, _) = render_centre(&f, rest, to_light, Integrator::Direct);
    assert_close(tilted, want, "geometrically tilted quad");
}

/// `scale` multiplies the decoded x and y before normalising.
#[test]
fn the_normal_scale_is_applied() {
    let m = Vec3::new(0.5, -0.3, 0.81).normalize();
    let scale = 0.4;
    let (texel, n) = texel_for(m, scale);
    let (_, unscaled) = texel_for(m, 1.0);
    let to_light = Vec3::new(-0.4, 0.3, 1.0);
    let (f, rest) = quad_document(texel, scale, Some(1.0), json!({}));
    let (got, _) = render_centre(&f, rest, to_light, Integrator::Direct);
    assert_close(got, lambert(n, to_light), "scale 0.4");
    assert!((lambert(n, to_light) - lambert(unscaled, to_light)).abs() > 0.02);
}

/// TANGENT w = −1 flips the bitangent: the green channel tilts the normal toward −Y. The
/// test fails if w is ignored: the two closed forms differ by more than half their value.
#[test]
fn tangent_handedness_is_honoured() {
    let m = Vec3::new(0.0, 0.5, 0.866).normalize();
    let (texel, n) = texel_for(m, 1.0);
    let flipped = Vec3::new(n.x, -n.y, n.z);
    let to_light = Vec3::new(0.0, 0.8, 1.0);
    let (right, left) = (lambert(n, to_light), lambert(flipped, to_light));
    assert!((right - left).abs() > 0.5 * right);
    for (w, want) in [(1.0, right), (-1.0, left)] {
        let (f, rest) = quad_document(texel, 1.0, Some(w), json!({}));
        let (got, _) = render_centre(&f, rest, to_light, Integrator::Direct);
        assert_close(got, want, &format!("w = {w}"));
    }
}

/// A mirroring node (scale −1 in x) mirrors the bump: the world normal is the object
/// normal with x negated, for supplied tangents (whose handedness the loader flips) and for
/// MikkTSpace's (generated on the mirrored world-space mesh).
#[test]
fn mirrored_nodes_mirror_the_normal_map() {
    let m = Vec3::new(0.45, 0.3, 0.84).normalize();
    let (texel, n) = texel_for(m, 1.0);
    let mirrored = Vec3::new(-n.x, n.y, n.z);
    let to_light = Vec3::new(-0.6, 0.3, 1.0);
    let want = lambert(mirrored, to_light);
    assert!((want - lambert(n, to_light)).abs() > 0.1 * want);
    for tangents in [Some(1.0), None] {
        let (f, rest) = quad_document(texel, 1.0, tangents, json!({"scale": [-1.0, 1.0, 1.0]}));
        let (got, _) = render_centre(&f, rest, to_light, Integrator::Direct);
        assert_close(got, want, &format!("mirrored, tangents {tangents:?}"));
    }
}

/// Meshes whose material has no normal map get no tangents, and the render's summary says
/// that no tangent frames were built; with a normal map it does not say so.
#[test]
fn scenes_without_normal_maps_build_no_tangent_frames() {
    let (texel, _) = texel_for(Vec3::Z, 1.0);
    let (f, mut rest) = quad_document(texel, 1.0, None, json!({}));
    rest["materials"][0]
        .as_object_mut()
        .expect("material object")
        .remove("normalTexture");
    let camera = ortho(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y, 0.5, 0.5);
    let scene = f.load(rest).expect("loads").scene;
    assert!(
        scene.meshes[0].tangents.is_none(),
        "no normal map, no tangents"
    );
    let out = render_with(&scene, &camera, BackendKind::Bvh, &centre_settings(4, 4));
    assert!(
        out.stats
            .summary()
            .contains("no normal maps: no tangent frames")
    );

    let (f, rest) = quad_document(texel, 1.0, None, json!({}));
    let scene = f.load(rest).expect("loads").scene;
    let out = render_with(&scene, &camera, BackendKind::Bvh, &centre_settings(4, 4));
    assert!(!out.stats.summary().contains("no normal maps"));
}

fn khronos(rel: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/khronos")
        .join(rel)
}

/// NormalTangentMirrorTest supplies its tangents (an exporter's MikkTSpace run, as glTF asks);
/// MikkTSpace regenerated here on the loaded mesh must reproduce them: the same handedness at
/// every triangle corner and tangent directions (projected onto the tangent plane) within
/// 0.5°. Measured: all 15 720 corners agree to 0.0° and in handedness. Generating with glTF's
/// v unflipped negates every handedness, which this test catches.
#[test]
fn generated_tangents_agree_with_the_supplied_ones_of_normal_tangent_mirror_test() {
    let scene = glint::scene::gltf::load(&khronos(
        "NormalTangentMirrorTest/glTF-Binary/NormalTangentMirrorTest.glb",
    ))
    .expect("load NormalTangentMirrorTest");
    let mut corners = 0usize;
    let mut close = 0usize;
    let mut same_w = 0usize;
    let mut worst = 0f32;
    for mesh in &scene.meshes {
        let supplied = mesh.tangents.clone().expect("the model supplies TANGENT");
        let normals = mesh.normals.clone().expect("the model supplies NORMAL");
        let mut regenerated = mesh.clone();
        regenerated.tangents = None;
        glint::scene::tangents::generate(&mut regenerated, 0).expect("MikkTSpace");
        let generated = regenerated.tangents.as_ref().expect("generated");
        for (old, new) in mesh.indices.iter().zip(&regenerated.indices) {
            for (&a, &b) in old.iter().zip(new) {
                let (s, g, n): (Vec4, Vec4, Vec3) = (
                    supplied[a as usize],
                    generated[b as usize],
                    normals[a as usize],
                );
                let project = |t: Vec3| (t - n * n.dot(t)).normalize_or_zero();
                let cos = project(s.truncate()).dot(project(g.truncate()));
                let angle = cos.clamp(-1.0, 1.0).acos().to_degrees();
                corners += 1;
                close += usize::from(angle <= 10.0);
                same_w += usize::from(s.w.signum() == g.w.signum());
                worst = worst.max(angle);
            }
        }
    }
    let close_fraction = close as f64 / corners as f64;
    let w_fraction = same_w as f64 / corners as f64;
    println!(
        "{corners} corners: {:.2} % within 10°, worst {worst:.1}°, handedness agrees at {:.2} %",
        100.0 * close_fraction,
        100.0 * w_fraction
    );
    assert!(corners > 1000);
    assert!(
        w_fraction >= 0.999,
        "handedness agrees at only {w_fraction:.4}"
    );
    assert!(
        close_fraction >= 0.95,
        "only {close_fraction:.4} of corners within 10°"
    );
}

/// The loader reads `normalTexture`'s scale and its KHR_texture_transform (offset and the
/// texCoord override), which the gltf crate leaves as raw JSON on a normalTextureInfo.
#[test]
fn the_normal_texture_reads_scale_and_texture_transform() {
    let (texel, _) = texel_for(Vec3::Z, 1.0);
    let (mut f, mut rest) = quad_document(texel, 0.25, Some(1.0), json!({}));
    let uv1 = f.floats(&[0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0], "VEC2", 2);
    rest["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] = json!(uv1);
    rest["materials"][0]["normalTexture"]["extensions"] = json!({
        "KHR_texture_transform": {"offset": [0.5, 0.25], "texCoord": 1}
    });
    rest["extensionsUsed"] = json!(["KHR_materials_specular", "KHR_texture_transform"]);
    let scene = f.load(rest).expect("loads").scene;
    let normal = scene.materials[0]
        .normal_texture
        .expect("normal texture read");
    assert_eq!(normal.scale, 0.25);
    assert_eq!(normal.texture.texcoord, 1);
    let moved = normal.texture.transform.transform_point2(glam::Vec2::ZERO);
    assert!(
        (moved - glam::Vec2::new(0.5, 0.25)).length() < 1e-6,
        "{moved}"
    );
}
