//! Two-level instancing: a mesh stored once in object space and drawn at several placements
//! must look exactly like its copies baked into world space, in both backends and both
//! integrators, and the loader must share the meshes glTF draws more than once.

use crate::support;

use crate::support::Fixture;
use crate::support::SplitMix;
use crate::support::{emitter, lambert, look_at, quad, render_with};
use glam::{Affine3A, Mat3, Mat4, Quat, Vec3};
use glint::accel::{self, BackendKind, BuildOptions, Placement, Ray};
use glint::render::{self, AovSelection, Integrator, PixelSampling, RenderSettings};
use glint::scene::{Camera, Light, Mesh, Scene};
use serde_json::json;
use std::path::Path;

fn khronos(rel: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/khronos")
        .join(rel)
}

/// The scene with every placed mesh replaced by one world-space copy per placement, baked the
/// way the loader bakes a node transform: positions through the matrix, normals through its
/// inverse transpose, tangents through its linear part with the handedness flipped by a
/// mirror, and a mirror's triangles re-wound.
fn flattened(scene: &Scene) -> Scene {
    let mut out = scene.clone();
    out.meshes.clear();
    for mesh in &scene.meshes {
        if mesh.instances.is_empty() {
            out.meshes.push(mesh.clone());
            continue;
        }
        for placement in &mesh.instances {
            let m = Mat4::from(*placement.world_from_object());
            let linear = Mat3::from_mat4(m);
            let normal = glint::scene::gltf::normal_transform(linear);
            let mirrored = linear.determinant() < 0.0;
            let mut copy = mesh.clone();
            copy.instances.clear();
            copy.node = placement.node;
            copy.positions = mesh
                .positions
                .iter()
                .map(|p| m.transform_point3(*p))
                .collect();
            copy.normals = mesh.normals.as_ref().map(|ns| {
                ns.iter()
                    .map(|n| (normal * *n).normalize_or_zero())
                    .collect()
            });
            copy.tangents = mesh.tangents.as_ref().map(|ts| {
                ts.iter()
                    .map(|t| {
                        let w = if mirrored { -t.w } else { t.w };
                        (linear * t.truncate()).normalize_or_zero().extend(w)
                    })
                    .collect()
            });
            if mirrored {
                for tri in &mut copy.indices {
                    tri.swap(1, 2);
                }
            }
            out.meshes.push(copy);
        }
    }
    out
}

/// Three placements: a plain shift, a rotation with non-uniform scale, and a mirror.
fn placements(size: f32) -> Vec<Mat4> {
    vec![
        Mat4::from_translation(Vec3::new(-1.2 * size, 0.0, 0.0)),
        Mat4::from_scale_rotation_translation(
            Vec3::new(0.7, 1.3, 0.9),
            Quat::from_rotation_y(0.8) * Quat::from_rotation_x(-0.3),
            Vec3::new(0.0, 0.1 * size, -0.4 * size),
        ),
        Mat4::from_translation(Vec3::new(1.2 * size, 0.0, 0.0))
            * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)),
    ]
}

/// The scene with its world-space meshes made object-space meshes at `transforms`, each
/// placement named by a node id of its own.
fn placed(mut scene: Scene, transforms: &[Mat4]) -> Scene {
    for mesh in &mut scene.meshes {
        assert!(mesh.instances.is_empty());
        mesh.instances = transforms
            .iter()
            .enumerate()
            .map(|(i, m)| Placement::new(Affine3A::from_mat4(*m), Some(100 + i as u32)).unwrap())
            .collect();
    }
    scene
}

/// A camera that sees the whole scene from the front and above.
fn framing(scene: &Scene) -> Camera {
    let (lo, hi) = scene.bounds().unwrap();
    let centre = (lo + hi) * 0.5;
    let radius = (hi - lo).length() * 0.5;
    look_at(
        centre + Vec3::new(0.3, 0.5, 1.0).normalize() * radius * 2.2,
        centre,
        Vec3::Y,
        0.9,
    )
}

fn settings(integrator: Integrator, spp: u32) -> RenderSettings {
    RenderSettings {
        width: 64,
        height: 48,
        spp,
        sampling: if spp == 1 {
            PixelSampling::PixelCenter
        } else {
            PixelSampling::default()
        },
        threads: 2,
        integrator,
        aovs: AovSelection {
            instance_id: true,
            ..AovSelection::default()
        },
        ..RenderSettings::default()
    }
}

/// Compares two renders of the same picture: at most `outliers` of the pixels (silhouette
/// pixels whose centre ray grazes an edge the two layouts round differently) may differ by
/// more than 1 % + 1e-4, and the mean radiance must agree to `mean_tolerance`.
fn assert_same_picture(
    label: &str,
    placed: &render::RenderOutput,
    flat: &render::RenderOutput,
    outliers: f64,
    mean_tolerance: f32,
) {
    let (a, b) = (&placed.image.pixels, &flat.image.pixels);
    let differing = a
        .iter()
        .zip(b)
        .filter(|(x, y)| (**x - **y).abs().max_element() > 0.01 * x.max(**y).max_element() + 1e-4)
        .count();
    let mean = |v: &[Vec3]| v.iter().copied().sum::<Vec3>() / v.len() as f32;
    let (ma, mb) = (mean(a), mean(b));
    eprintln!(
        "{label}: {differing} of {} pixels differ; means {ma} vs {mb}",
        a.len()
    );
    assert!(mb.max_element() > 0.0, "{label}: the picture is black");
    assert!(
        (differing as f64) <= outliers * a.len() as f64,
        "{label}: {differing} of {} pixels differ",
        a.len()
    );
    assert!(
        (ma - mb).abs().max_element() <= mean_tolerance * mb.max_element(),
        "{label}: mean {ma} vs {mb}"
    );
    let ids = |o: &render::RenderOutput| o.aovs.instance_id.clone().unwrap().pixels;
    let same_ids = ids(placed)
        .iter()
        .zip(ids(flat))
        .filter(|(x, y)| **x == *y)
        .count();
    assert!(
        same_ids as f64 >= (1.0 - outliers) * a.len() as f64,
        "{label}: instance ids differ in {} pixels",
        a.len() - same_ids
    );
}

fn lit(mut scene: Scene) -> Scene {
    let (lo, hi) = scene.bounds().unwrap();
    scene.lights = vec![
        Light::Point {
            position: hi + (hi - lo) * 0.5,
            intensity: Vec3::splat(4.0 * (hi - lo).length_squared()),
            range: None,
        },
        Light::Directional {
            direction: Vec3::new(-0.3, -1.0, -0.5).normalize(),
            irradiance: Vec3::splat(1.5),
        },
    ];
    scene
}

/// Textured, normal-mapped and mirrored sample models drawn at three placements render like
/// their baked copies, in both backends, with the direct integrator at pixel centres.
#[test]
fn placed_models_render_like_their_baked_copies() {
    for model in [
        "Duck/glTF-Binary/Duck.glb",
        "NormalTangentMirrorTest/glTF-Binary/NormalTangentMirrorTest.glb",
    ] {
        let path = khronos(model);
        if !path.exists() {
            panic!("missing shared model {}", path.display());
        }
        let base = glint::scene::gltf::load(&path).expect("load");
        let (lo, hi) = base.bounds().unwrap();
        let scene = lit(placed(base, &placements((hi - lo).max_element())));
        let flat = flattened(&scene);
        let camera = framing(&scene);
        for backend in BackendKind::available() {
            let s = settings(Integrator::Direct, 1);
            let a = render_with(&scene, &camera, *backend, &s);
            let b = render_with(&flat, &camera, *backend, &s);
            assert_same_picture(&format!("{model} {backend}"), &a, &b, 0.01, 2e-3);
        }
    }
}

/// 2CylinderEngine draws 34 meshes 115 times: loaded with sharing, it renders like the same
/// scene with every placement baked, in both backends.
#[test]
fn a_file_with_shared_meshes_renders_like_its_baked_copy() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/scenes/2CylinderEngine/2CylinderEngine.glb");
    let scene = lit(glint::scene::gltf::load(&path).expect("load"));
    assert!(
        scene.meshes.iter().any(|m| m.instances.len() > 1),
        "meshes are shared"
    );
    let flat = flattened(&scene);
    assert!(flat.meshes.len() > scene.meshes.len());
    let camera = framing(&scene);
    for backend in BackendKind::available() {
        let s = settings(Integrator::Direct, 1);
        let a = render_with(&scene, &camera, *backend, &s);
        let b = render_with(&flat, &camera, *backend, &s);
        assert_same_picture(&format!("2CylinderEngine {backend}"), &a, &b, 0.01, 2e-3);
    }
}

/// A placed emitter lights the floor as its baked copies do (path tracer, next-event
/// estimation on the placed triangles, one copy mirrored so its front face is carried over).
///
/// The baked mirror re-winds its triangles, so the same random numbers land on other points
/// of it: the pictures agree in distribution, not pixel for pixel. At 64 spp each 8×8 block's
/// mean has a relative standard error under 1 % here; blocks must agree to 5 %, the whole
/// image to 1 %.
#[test]
fn placed_emitters_light_like_their_baked_copies() {
    let floor = quad(Vec3::ZERO, Vec3::X * 4.0, Vec3::Z * -4.0, 0);
    // A panel facing down (u × v = X × Z = −Y), emitting from its front only.
    let panel = quad(Vec3::ZERO, Vec3::X * 0.5, Vec3::Z * 0.5, 1);
    let mut scene = support::scene(
        vec![floor, panel],
        vec![lambert(Vec3::splat(0.7), false), emitter(Vec3::splat(5.0))],
        vec![],
    );
    scene.meshes[1].instances = [
        Mat4::from_translation(Vec3::new(-1.0, 1.5, 0.0)),
        Mat4::from_translation(Vec3::new(1.0, 1.2, 0.3))
            * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.3)),
    ]
    .iter()
    .map(|m| Placement::new(Affine3A::from_mat4(*m), None).unwrap())
    .collect();
    let flat = flattened(&scene);
    let camera = look_at(Vec3::new(0.0, 4.0, 5.0), Vec3::ZERO, Vec3::Y, 0.8);
    for backend in BackendKind::available() {
        let s = RenderSettings {
            max_depth: 3,
            ..settings(Integrator::Path, 64)
        };
        let a = render_with(&scene, &camera, *backend, &s);
        let b = render_with(&flat, &camera, *backend, &s);
        let blocks = |o: &render::RenderOutput| {
            let w = o.image.width as usize;
            let mut sums = vec![0.0f64; (w / 8) * (o.image.height as usize / 8)];
            for (i, p) in o.image.pixels.iter().enumerate() {
                let (x, y) = (i % w / 8, i / w / 8);
                sums[y * (w / 8) + x] += f64::from(p.x + p.y + p.z);
            }
            sums
        };
        let (ba, bb) = (blocks(&a), blocks(&b));
        let (ta, tb) = (ba.iter().sum::<f64>(), bb.iter().sum::<f64>());
        assert!(tb > 0.0, "{backend}: black");
        assert!(
            (ta - tb).abs() <= 0.01 * tb,
            "{backend}: total {ta} vs {tb}"
        );
        let brightest = bb.iter().copied().fold(0.0, f64::max);
        for (k, (x, y)) in ba.iter().zip(&bb).enumerate() {
            assert!(
                (x - y).abs() <= 0.05 * y + 0.01 * brightest,
                "{backend}: block {k}: {x} vs {y}"
            );
        }
    }
}

/// Rays against many placed copies of a bumpy sphere (mirrors and shears among them): both
/// backends find the same copy, triangle, distance and world normal as a baked scene.
#[test]
fn backends_agree_with_baked_copies_on_every_ray() {
    let sphere = glint::procedural::displaced_sphere(3, 0.2, 7);
    let mut rng = SplitMix(12345);
    let mut next = || rng.unit();
    let mut transforms = Vec::new();
    for i in 0..40 {
        let scale = Vec3::new(0.5 + next(), 0.5 + next(), 0.5 + next())
            * if i % 3 == 0 {
                Vec3::new(-1.0, 1.0, 1.0)
            } else {
                Vec3::ONE
            };
        let rotation = Quat::from_euler(glam::EulerRot::XYZ, next() * 6.0, next() * 6.0, next());
        let t = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * 12.0;
        transforms.push(Mat4::from_scale_rotation_translation(scale, rotation, t));
    }
    let mesh = Mesh {
        positions: sphere.positions.clone(),
        indices: sphere.indices.clone(),
        ..Mesh::default()
    };
    let scene = placed(
        support::scene(vec![mesh], vec![lambert(Vec3::ONE, true)], vec![]),
        &transforms,
    );
    let flat = flattened(&scene);
    let (lo, hi) = scene.bounds().unwrap();
    let mut rays = Vec::new();
    for _ in 0..4000 {
        let o = lo + (hi - lo) * Vec3::new(next(), next(), next()) * 1.4 - (hi - lo) * 0.2;
        let target = lo + (hi - lo) * Vec3::new(next(), next(), next());
        rays.push(Ray::segment(o, target - o, 0.0, 2.0));
    }
    let reference = accel::build(
        BackendKind::available()[0],
        &flat.triangle_meshes(),
        BuildOptions::default(),
    )
    .unwrap();
    for backend in BackendKind::available() {
        let accel =
            accel::build(*backend, &scene.triangle_meshes(), BuildOptions::default()).unwrap();
        assert_eq!(accel.triangle_count(), reference.triangle_count());
        let (mut hits, mut mismatched) = (0, 0);
        for ray in &rays {
            let (got, want) = (accel.intersect(ray), reference.intersect(ray));
            assert_eq!(
                accel.occluded(ray),
                reference.occluded(ray) || got.is_some()
            );
            match (got, want) {
                (Some(g), Some(w)) => {
                    hits += 1;
                    // Baked copies are meshes in placement order, one triangle set each.
                    let same = g.instance == w.geom_id && g.prim_id == w.prim_id;
                    if !same {
                        mismatched += 1;
                        // Two triangles at (nearly) the same distance: either is right.
                        assert!((g.t - w.t).abs() <= 1e-4 * w.t.max(1.0), "{backend}");
                        continue;
                    }
                    assert!((g.t - w.t).abs() <= 1e-4 * w.t.max(1.0), "{backend}: t");
                    assert!(
                        g.ng.dot(w.ng) > 0.9999,
                        "{backend}: ng {} vs {}",
                        g.ng,
                        w.ng
                    );
                }
                (None, None) => {}
                (g, w) => {
                    // Only a ray grazing an edge may hit in one layout and miss in the other.
                    mismatched += 1;
                    let t = g.or(w).unwrap().t;
                    assert!(t.is_finite(), "{backend}");
                }
            }
        }
        eprintln!("{backend}: {hits} hits, {mismatched} differing");
        assert!(hits > 500, "{backend}: the rays must hit the copies");
        assert!(
            mismatched * 200 <= hits,
            "{backend}: {mismatched} of {hits} differ"
        );
    }
}

/// The loader stores a mesh drawn by several nodes once, with one placement per node (a
/// mirroring one included), keeps a mesh drawn once in world space, and does not share a
/// mesh whose morph weights differ.
#[test]
fn the_loader_shares_meshes_drawn_more_than_once() {
    let mut fixture = Fixture::new();
    let position = fixture.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let target = fixture.positions(&[[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0]]);
    let loaded = fixture
        .load(json!({
            "scenes": [{"nodes": [0, 1, 2, 3, 4]}],
            "nodes": [
                {"mesh": 0, "translation": [1, 0, 0]},
                {"mesh": 0, "translation": [3, 0, 0], "scale": [-1, 1, 1]},
                {"mesh": 1},
                {"mesh": 0, "translation": [5, 0, 0]},
                {"mesh": 2, "weights": [0.5]}
            ],
            "meshes": [
                {"primitives": [{"attributes": {"POSITION": position}}]},
                {"primitives": [{"attributes": {"POSITION": position}}]},
                {"primitives": [{"attributes": {"POSITION": position}, "targets": [{"POSITION": target}]}], "weights": [0.0]}
            ]
        }))
        .unwrap();
    let scene = &loaded.scene;
    assert_eq!(
        scene.meshes.len(),
        3,
        "{:?}",
        scene.meshes.iter().map(|m| &m.name).collect::<Vec<_>>()
    );
    let shared = &scene.meshes[0];
    assert_eq!(shared.instances.len(), 3);
    assert_eq!(
        shared.instances.iter().map(|p| p.node).collect::<Vec<_>>(),
        [Some(0), Some(1), Some(3)]
    );
    assert!(shared.instances[1].mirrored());
    assert_eq!(shared.positions[1], Vec3::X, "stored in object space");
    assert!((shared.instances[1].point(Vec3::X) - Vec3::new(2.0, 0.0, 0.0)).length() < 1e-6);
    assert!(scene.meshes[1].instances.is_empty(), "mesh 1 is drawn once");
    assert!(scene.meshes[2].instances.is_empty(), "mesh 2 is drawn once");
    assert_eq!(
        scene.meshes[2].positions[0],
        Vec3::new(0.0, 0.0, 0.5),
        "morphed"
    );
    assert_eq!(scene.triangle_count(), 5);
    assert_eq!(scene.unique_triangle_count(), 3);
}

/// Copies scaled to nothing are left out, and a node whose every copy is degenerate draws
/// nothing rather than a world-space mesh at the origin.
#[test]
fn degenerate_copies_are_left_out() {
    let mut fixture = Fixture::new();
    let position = fixture.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let loaded = fixture
        .load(json!({
            "scenes": [{"nodes": [0, 1, 2]}],
            "nodes": [
                {"mesh": 0, "scale": [0, 1, 1]},
                {"mesh": 0, "translation": [2, 0, 0]},
                {"mesh": 1, "scale": [0, 0, 0]},
            ],
            "meshes": [
                {"primitives": [{"attributes": {"POSITION": position}}]},
                {"primitives": [{"attributes": {"POSITION": position}}]}
            ]
        }))
        .unwrap();
    let scene = &loaded.scene;
    assert_eq!(scene.meshes[0].instances.len(), 1);
    assert_eq!(scene.meshes[0].instances[0].node, Some(1));
    assert_eq!(scene.triangle_count(), 2, "mesh 1 stays baked (drawn once)");
}

/// Placed tangents keep the bitangent on the surface: `w · n × t` of a mirrored copy equals
/// the mirrored object-space bitangent.
#[test]
fn mirrored_placements_flip_tangent_handedness() {
    let p = Placement::new(
        Affine3A::from_mat4(Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0))),
        None,
    )
    .unwrap();
    let (n, t, w) = (Vec3::Z, Vec3::X, 1.0);
    let b = w * n.cross(t);
    let (nw, tw) = (p.normal(n).normalize(), p.vector(t).normalize());
    let ww = if p.mirrored() { -w } else { w };
    assert!((ww * nw.cross(tw) - p.vector(b).normalize()).length() < 1e-6);
}

/// Placed emitters whose copies are similarities are sampled copy by copy (one light-BVH or
/// power entry per copy, a triangle within it by power). At shading points near and far,
/// the irradiance estimate `Le cos θ / pdf` agrees with the same copies baked as separate
/// triangle lights (both within 4 standard errors of each other), every sample's density
/// equals `pdf()`, and the total power is the baked total.
#[test]
fn copies_sampled_as_a_whole_are_unbiased() {
    use glam::{Vec2, Vec3 as V};
    use glint::light::area::{AreaLights, EmitterMesh, SelectionMode};
    // A fan of 6 triangles around the origin in the XZ plane, front face +Y, one dark.
    let mut positions = vec![V::ZERO];
    for k in 0..6 {
        let a = k as f32 / 6.0 * std::f32::consts::TAU;
        positions.push(V::new(a.cos(), 0.0, -a.sin()) * (0.5 + 0.1 * k as f32));
    }
    let indices: Vec<[u32; 3]> = (0..6).map(|k| [0, 1 + k, 1 + (k + 1) % 6]).collect();
    let le = |t: u32| {
        if t == 2 {
            V::ZERO
        } else {
            V::splat(1.0 + t as f32)
        }
    };
    let mut transforms = Vec::new();
    for i in 0..30 {
        let s = 0.3 + 0.05 * i as f32;
        let mirror = if i % 4 == 0 { -1.0 } else { 1.0 };
        transforms.push(Mat4::from_scale_rotation_translation(
            V::new(mirror * s, s, s),
            Quat::from_rotation_x(3.0 + 0.02 * i as f32) * Quat::from_rotation_y(i as f32),
            V::new(
                (i % 6) as f32 - 2.5,
                3.0 + (i / 6) as f32 * 0.5,
                (i % 5) as f32 - 2.0,
            ),
        ));
    }
    let placements: Vec<Placement> = transforms
        .iter()
        .map(|m| Placement::new(Affine3A::from_mat4(*m), None).unwrap())
        .collect();
    let baked: Vec<(Vec<V>, Vec<[u32; 3]>)> = transforms
        .iter()
        .map(|m| {
            let mirrored = Mat3::from_mat4(*m).determinant() < 0.0;
            let tris = indices
                .iter()
                .map(|t| if mirrored { [t[0], t[2], t[1]] } else { *t })
                .collect();
            (
                positions.iter().map(|p| m.transform_point3(*p)).collect(),
                tris,
            )
        })
        .collect();
    for mode in [SelectionMode::Power, SelectionMode::Bvh] {
        let placed = AreaLights::with_selection(
            &[EmitterMesh {
                positions: &positions,
                indices: &indices,
                two_sided: false,
                instances: &placements,
            }],
            |_, t| le(t),
            mode.clone(),
        )
        .unwrap();
        assert!(
            placed.lights().is_empty(),
            "the copies are clusters, not stored lights"
        );
        let baked_meshes: Vec<EmitterMesh<'_>> = baked
            .iter()
            .map(|(p, i)| EmitterMesh {
                positions: p,
                indices: i,
                two_sided: false,
                instances: &[],
            })
            .collect();
        let flat = AreaLights::with_selection(&baked_meshes, |_, t| le(t), mode.clone()).unwrap();
        assert!(
            (placed.total_power() - flat.total_power()).abs() <= 1e-4 * flat.total_power(),
            "{mode:?}: power {} vs {}",
            placed.total_power(),
            flat.total_power()
        );
        let mut rng = SplitMix(7);
        let mut uniform = || rng.unit();
        for p in [
            V::new(0.0, 0.0, 0.0),
            V::new(2.0, 4.0, -1.0),
            V::new(-9.0, 1.0, 6.0),
        ] {
            let n = V::Y;
            let mut estimate = |lights: &AreaLights, check: bool| {
                let count = 40_000;
                let (mut sum, mut sum2) = (0.0f64, 0.0f64);
                for _ in 0..count {
                    let (us, u) = (uniform(), Vec2::new(uniform(), uniform()));
                    let value = match lights.sample(p, n, us, u) {
                        Some(s) => {
                            // A nearly grazing sample's density is ill-conditioned (cos θ_l
                            // from a cancelling dot product); the others must agree.
                            if check && s.normal.dot(s.wi).abs() > 0.02 {
                                let q = lights.pdf(p, n, (s.mesh, s.instance, s.triangle), s.point);
                                assert!(
                                    (q - s.pdf).abs() <= 1e-3 * s.pdf,
                                    "{mode:?}: pdf() {q} vs sample {} (cos {})",
                                    s.pdf,
                                    s.normal.dot(s.wi)
                                );
                            }
                            f64::from(s.le.x * n.dot(s.wi).max(0.0) / s.pdf)
                        }
                        None => 0.0,
                    };
                    sum += value;
                    sum2 += value * value;
                }
                let mean = sum / count as f64;
                let var = (sum2 / count as f64 - mean * mean).max(0.0);
                (mean, (var / count as f64).sqrt())
            };
            let (a, ea) = estimate(&placed, true);
            let (b, eb) = estimate(&flat, false);
            eprintln!("{mode:?} at {p}: clustered {a:.5} ± {ea:.5}, baked {b:.5} ± {eb:.5}");
            assert!(b > 0.0);
            assert!(
                (a - b).abs() <= 4.0 * (ea * ea + eb * eb).sqrt(),
                "{mode:?} at {p}: {a} ± {ea} vs {b} ± {eb}"
            );
        }
    }
}
