//! The Embree and obvhs backends must answer the same queries the same way: hit versus miss
//! identical, t within a tight relative tolerance, the same primitive on at least 99.99% of
//! rays (coplanar ties aside), for coherent camera rays and incoherent random rays, on
//! procedural meshes and on the shared real assets.
//!
//! Embree runs once per kernel this machine has ([`accel::every_configuration`]: native, and
//! pinned to SSE2, SSE4.2, AVX, AVX2, AVX-512 where the CPU supports them), since its kernels
//! round differently and an assumption that holds for one may fail for another. Exact float
//! equalities are asserted only where glint's own arithmetic computes the value (hit
//! attributes are re-solved by glint on the triangle Embree reports: `accel::triangle`);
//! anything Embree computes is compared within a stated number of ulps.

use crate::support::{bounds, camera_rays, random_rays};
use glam::Vec3;
use glint::accel::{self, Accel, BackendKind, BuildOptions, Coherence, Hit, Ray, TriangleMesh};
use glint::procedural;

/// Relative tolerance on t: both backends evaluate the same Möller–Trumbore expression, but
/// Embree's SIMD kernels may fuse operations differently.
const T_REL_TOL: f32 = 1e-4;
/// Absolute tolerance on t as a share of the scene's diagonal (rays have unit directions): t is
/// computed from vertex − origin differences whose rounding scales with the scene, not with t,
/// so random origins a micron from a surface need this floor.
const T_ABS_TOL: f32 = 1e-6;
/// Share of hits that must report the same primitive, ties (both candidates at the same t:
/// coincident faces, shared edges) aside.
const SAME_PRIM_MIN: f64 = 0.9999;

struct Comparison {
    rays: usize,
    hits: usize,
    hit_miss_mismatch: usize,
    t_mismatch: usize,
    prim_mismatch: usize,
    ties: usize,
}

fn compare(a: &[Option<Hit>], b: &[Option<Hit>], rays: &[Ray], diagonal: f32) -> Comparison {
    let mut c = Comparison {
        rays: rays.len(),
        hits: 0,
        hit_miss_mismatch: 0,
        t_mismatch: 0,
        prim_mismatch: 0,
        ties: 0,
    };
    for (ha, hb) in a.iter().zip(b) {
        match (ha, hb) {
            (Some(x), Some(y)) => {
                c.hits += 1;
                let same_t = (x.t - y.t).abs()
                    <= T_REL_TOL * x.t.abs().max(y.t.abs()) + T_ABS_TOL * diagonal;
                if (x.geom_id, x.prim_id) == (y.geom_id, y.prim_id) {
                    if !same_t {
                        eprintln!("t mismatch: {x:?} vs {y:?}");
                        c.t_mismatch += 1;
                    }
                } else if same_t {
                    // Two surfaces at the same distance (coincident faces, a shared edge):
                    // either answer is right.
                    c.ties += 1;
                } else {
                    eprintln!("primitive mismatch: {x:?} vs {y:?}");
                    c.prim_mismatch += 1;
                }
            }
            (None, None) => {}
            _ => c.hit_miss_mismatch += 1,
        }
    }
    c
}

fn trace(accel: &dyn Accel, rays: &[Ray], coherence: Coherence) -> Vec<Option<Hit>> {
    let mut hits = vec![None; rays.len()];
    accel.intersect_many(rays, &mut hits, coherence);
    hits
}

/// Builds every backend and Embree kernel over `meshes` and checks agreement with the first
/// (Embree's native kernels when compiled in) on the given ray sets.
fn check_agreement(label: &str, meshes: &[TriangleMesh<'_>], ray_sets: &[(&str, Vec<Ray>)]) {
    let backends: Vec<(String, Box<dyn Accel>)> = accel::every_configuration()
        .into_iter()
        .map(|(k, options)| {
            let name = accel::configuration_label(k, &options);
            (name, accel::build(k, meshes, options).expect("build"))
        })
        .collect();
    let (lo, hi) = bounds(meshes.iter().flat_map(|m| m.positions.iter().copied()));
    let diagonal = (hi - lo).length();
    assert!(
        backends.len() >= 2 || !cfg!(feature = "embree"),
        "both backends must be compiled in"
    );
    for (set_name, rays) in ray_sets {
        let coherence = if set_name.starts_with("camera") {
            Coherence::Coherent
        } else {
            Coherence::Incoherent
        };
        let reference = trace(backends[0].1.as_ref(), rays, coherence);
        for (name, other) in &backends[1..] {
            let answers = trace(other.as_ref(), rays, coherence);
            let c = compare(&reference, &answers, rays, diagonal);
            let same = 1.0 - c.prim_mismatch as f64 / c.hits.max(1) as f64;
            let label = format!("{label} ({} vs {name})", backends[0].0);
            eprintln!(
                "{label} / {set_name}: {} rays, {} hits, hit/miss mismatches {}, t mismatches {}, \
                 ties {}, same primitive {:.6}",
                c.rays, c.hits, c.hit_miss_mismatch, c.t_mismatch, c.ties, same
            );
            assert!(
                c.hits > c.rays / 20,
                "{label}/{set_name}: too few hits to be a test"
            );
            assert_eq!(
                c.hit_miss_mismatch, 0,
                "{label}/{set_name}: hit vs miss differs"
            );
            assert_eq!(c.t_mismatch, 0, "{label}/{set_name}: t differs");
            assert!(
                same >= SAME_PRIM_MIN,
                "{label}/{set_name}: same primitive on only {same}"
            );
        }
    }
}

fn procedural_case(label: &str, mesh: &procedural::OwnedMesh) {
    let (lo, hi) = bounds(mesh.positions.iter().copied());
    let ray_sets = [
        (
            "camera +z",
            camera_rays(lo, hi, Vec3::new(0.3, -0.4, -1.0), 320, 240),
        ),
        (
            "camera -x",
            camera_rays(lo, hi, Vec3::new(-1.0, -0.2, 0.1), 320, 240),
        ),
        ("random", random_rays(lo, hi, 100_000, 7)),
    ];
    check_agreement(label, &[mesh.as_triangle_mesh()], &ray_sets);
}

#[test]
fn displaced_sphere_agrees() {
    procedural_case("sphere", &procedural::displaced_sphere(6, 0.05, 1));
}

#[test]
fn terrain_agrees() {
    procedural_case("terrain", &procedural::terrain(256, 0.1, 2));
}

#[test]
fn triangle_soup_agrees() {
    procedural_case("soup", &procedural::triangle_soup(100_000, 0.02, 3));
}

/// Several meshes: geometry ids must map back to the right mesh in both backends.
#[test]
fn multiple_meshes_keep_their_ids() {
    let a = procedural::displaced_sphere(4, 0.0, 4);
    let mut b = procedural::terrain(64, 0.05, 5);
    for p in &mut b.positions {
        *p = *p * 3.0 - Vec3::Y * 1.5;
    }
    let c = procedural::triangle_soup(2_000, 0.05, 6);
    let meshes = [
        a.as_triangle_mesh(),
        b.as_triangle_mesh(),
        c.as_triangle_mesh(),
    ];
    let (lo, hi) = bounds(
        [&a, &b, &c]
            .iter()
            .flat_map(|m| m.positions.iter().copied()),
    );
    let ray_sets = [
        (
            "camera",
            camera_rays(lo, hi, Vec3::new(0.2, -0.5, -1.0), 200, 200),
        ),
        ("random", random_rays(lo, hi, 50_000, 8)),
    ];
    check_agreement("three meshes", &meshes, &ray_sets);
}

/// `occluded` agrees with the closest hit: nothing lies before the closest hit, something lies
/// at it. Checked on every backend, single-ray and batched.
#[test]
fn occluded_agrees_with_closest_hit() {
    let mesh = procedural::displaced_sphere(5, 0.05, 9);
    let (lo, hi) = bounds(mesh.positions.iter().copied());
    let rays = random_rays(lo * 1.5, hi * 1.5, 20_000, 10);
    for (k, options) in accel::every_configuration() {
        let kind = accel::configuration_label(k, &options);
        let accel = accel::build(k, &[mesh.as_triangle_mesh()], options).expect("build");
        let hits = trace(accel.as_ref(), &rays, Coherence::Incoherent);
        let mut before = Vec::new();
        let mut beyond = Vec::new();
        for (ray, hit) in rays.iter().zip(&hits) {
            let Some(hit) = hit else { continue };
            before.push(Ray {
                tfar: hit.t * (1.0 - 1e-4),
                ..*ray
            });
            beyond.push(Ray {
                tfar: hit.t * (1.0 + 1e-4),
                ..*ray
            });
        }
        assert!(before.len() > 5_000, "{kind}: too few hits");
        let mut blocked = vec![false; before.len()];
        accel.occluded_many(&before, &mut blocked, Coherence::Incoherent);
        assert!(
            blocked.iter().all(|b| !b),
            "{kind}: occluded before the closest hit"
        );
        accel.occluded_many(&beyond, &mut blocked, Coherence::Incoherent);
        assert!(
            blocked.iter().all(|b| *b),
            "{kind}: not occluded past the closest hit"
        );
        // The single-ray path gives the same answers as the batched one.
        for (ray, b) in beyond.iter().zip(&blocked).take(2_000) {
            assert_eq!(accel.occluded(ray), *b);
        }
        // A miss stays a miss for occlusion with an infinite interval.
        let misses: Vec<Ray> = rays
            .iter()
            .zip(&hits)
            .filter(|(_, h)| h.is_none())
            .map(|(r, _)| *r)
            .collect();
        let mut out = vec![true; misses.len()];
        accel.occluded_many(&misses, &mut out, Coherence::Incoherent);
        assert!(
            out.iter().all(|b| !b),
            "{kind}: occluded on a ray that misses"
        );
    }
}

/// Units in the last place between two finite floats of the same sign.
fn ulps(a: f32, b: f32) -> u32 {
    (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs() as u32
}

/// Interval ends: a hit at exactly tnear is rejected, one at exactly tfar accepted (Embree's
/// rule), and the barycentrics and normal agree. `t`, `u`, `v` and the normal are glint's own
/// arithmetic on the reported triangle (exact here: 2, 1/4, 1/2 and +z are representable and
/// every step of the solve is exact for these inputs), so they are asserted exactly; the
/// interval decisions are Embree's kernels' and hold on every one of them because the scaled
/// test `|det|·tnear < T <= |det|·tfar` is exact for these inputs too.
#[test]
fn interval_ends_and_hit_attributes_agree() {
    let positions = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let indices = [[0u32, 1, 2]];
    let mesh = [TriangleMesh {
        positions: &positions,
        indices: &indices,
        instances: &[],
    }];
    let origin = Vec3::new(0.25, 0.5, 2.0);
    let dir = Vec3::new(0.0, 0.0, -1.0);
    for (k, options) in accel::every_configuration() {
        let kind = accel::configuration_label(k, &options);
        let accel = accel::build(k, &mesh, options).expect("build");
        let hit = accel.intersect(&Ray::new(origin, dir)).expect("hit");
        assert_eq!((hit.t, hit.u, hit.v), (2.0, 0.25, 0.5), "{kind}: {hit:?}");
        assert_eq!(hit.ng, Vec3::Z, "{kind}");
        // The packet path reports the same bits.
        let mut packet = [None; 3];
        accel.intersect_many(
            &[Ray::new(origin, dir); 3],
            &mut packet,
            Coherence::Coherent,
        );
        assert!(packet.iter().all(|h| *h == Some(hit)), "{kind}: {packet:?}");
        assert!(
            accel
                .intersect(&Ray::segment(origin, dir, 2.0, 3.0))
                .is_none(),
            "{kind}"
        );
        assert!(
            accel
                .intersect(&Ray::segment(origin, dir, 0.0, 2.0))
                .is_some(),
            "{kind}"
        );
        assert!(
            !accel.occluded(&Ray::segment(origin, dir, 0.0, 1.999)),
            "{kind}"
        );
        assert!(
            accel.occluded(&Ray::segment(origin, dir, 0.0, 2.0)),
            "{kind}"
        );
        // From behind: same triangle, normal still the geometric one.
        let back = accel
            .intersect(&Ray::new(Vec3::new(0.25, 0.5, -1.0), Vec3::Z))
            .expect("back hit");
        assert_eq!(back.ng, Vec3::Z, "{kind}");
        // An oblique ray whose t is not exact in f32: every kernel reports the same bits
        // (glint's arithmetic), within 4 ulps of the f64 answer.
        let oblique = Ray::new(Vec3::new(0.1, 0.2, 0.7), Vec3::new(0.31, 0.17, -0.93));
        let h = accel.intersect(&oblique).expect("oblique hit");
        let exact = f64::from(0.7f32) / f64::from(0.93f32);
        assert!(ulps(h.t, exact as f32) <= 4, "{kind}: t {} vs {exact}", h.t);
    }
}

/// Hit attributes are the same bits on every Embree kernel and on obvhs for the same triangle:
/// glint re-solves Embree's hits with obvhs's arithmetic, so no image depends on which kernel
/// Embree picked for this CPU except through which triangle a tie goes to.
#[test]
fn every_kernel_reports_the_same_hit_bits() {
    let mesh = procedural::displaced_sphere(5, 0.05, 21);
    let meshes = [mesh.as_triangle_mesh()];
    let (lo, hi) = bounds(mesh.positions.iter().copied());
    let rays = random_rays(lo * 1.2, hi * 1.2, 20_000, 22);
    let answers: Vec<(String, Vec<Option<Hit>>)> = accel::every_configuration()
        .into_iter()
        .map(|(k, options)| {
            let accel = accel::build(k, &meshes, options).expect("build");
            let name = accel::configuration_label(k, &options);
            (name, trace(accel.as_ref(), &rays, Coherence::Incoherent))
        })
        .collect();
    let (first_name, first) = &answers[0];
    for (name, other) in &answers[1..] {
        let mut same_prim = 0usize;
        for (a, b) in first.iter().zip(other) {
            if let (Some(a), Some(b)) = (a, b)
                && (a.geom_id, a.prim_id) == (b.geom_id, b.prim_id)
            {
                same_prim += 1;
                assert_eq!(
                    (a.t.to_bits(), a.u.to_bits(), a.v.to_bits(), a.ng),
                    (b.t.to_bits(), b.u.to_bits(), b.v.to_bits(), b.ng),
                    "{first_name} vs {name}"
                );
            }
        }
        assert!(
            same_prim > 5_000,
            "{first_name} vs {name}: {same_prim} common hits"
        );
    }
}

/// The shared real assets: flattened to world-space triangles by glint's loader.
#[test]
fn shared_assets_agree() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes");
    let files = [
        "2CylinderEngine/2CylinderEngine.glb",
        "DamagedHelmet/glTF/DamagedHelmet.gltf",
        "Suzanne/glTF/Suzanne.gltf",
        "BoxTextured/BoxTextured.gltf",
    ];
    for file in files {
        let path = root.join(file);
        let scene =
            glint::scene::gltf::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let meshes = scene.triangle_meshes();
        let (lo, hi) = scene.bounds().expect("non-empty");
        let ray_sets = [
            (
                "camera front",
                camera_rays(lo, hi, Vec3::new(0.2, -0.3, -1.0), 256, 192),
            ),
            (
                "camera side",
                camera_rays(lo, hi, Vec3::new(1.0, -0.3, 0.2), 256, 192),
            ),
            ("random", random_rays(lo, hi, 50_000, 11)),
        ];
        check_agreement(file, &meshes, &ray_sets);
    }
}

/// Embree really runs in the test command: the Embree backend is compiled in and linked.
#[cfg(feature = "embree")]
#[test]
fn embree_is_linked_and_runs() {
    let major = glint::accel::embree::embree_major();
    assert!(major == 3 || major == 4, "Embree major {major}");
    assert_eq!(major.to_string(), env!("GLINT_EMBREE_MAJOR"));
    let mesh = procedural::displaced_sphere(2, 0.0, 1);
    let accel = accel::build(
        BackendKind::Embree,
        &[mesh.as_triangle_mesh()],
        BuildOptions::default(),
    )
    .expect("Embree builds");
    assert_eq!(accel.kind(), BackendKind::Embree);
    assert!(
        accel
            .intersect(&Ray::new(Vec3::Z * 5.0, -Vec3::Z))
            .is_some()
    );
}

/// Every build setting answers the same queries: Embree LOW/MEDIUM/HIGH with and without the
/// robust flag, obvhs's three presets, all against obvhs MEDIUM.
#[test]
fn every_build_setting_agrees() {
    use glint::accel::BuildQuality;
    let mesh = procedural::displaced_sphere(5, 0.05, 12);
    let meshes = [mesh.as_triangle_mesh()];
    let (lo, hi) = bounds(mesh.positions.iter().copied());
    let diagonal = (hi - lo).length();
    let camera = camera_rays(lo, hi, Vec3::new(0.1, 0.2, -1.0), 160, 120);
    let random = random_rays(lo, hi, 20_000, 13);
    let reference =
        accel::build(BackendKind::Bvh, &meshes, BuildOptions::default()).expect("build");
    for (kind, base) in accel::every_configuration() {
        for quality in BuildQuality::ALL {
            for robust in [false, true] {
                let options = BuildOptions {
                    quality,
                    robust,
                    ..base
                };
                let accel = accel::build(kind, &meshes, options).expect("build");
                for rays in [&camera, &random] {
                    let c = compare(
                        &trace(reference.as_ref(), rays, Coherence::Incoherent),
                        &trace(accel.as_ref(), rays, Coherence::Incoherent),
                        rays,
                        diagonal,
                    );
                    let same = 1.0 - c.prim_mismatch as f64 / c.hits.max(1) as f64;
                    assert_eq!(c.hit_miss_mismatch, 0, "{kind} {options:?}");
                    assert_eq!(c.t_mismatch, 0, "{kind} {options:?}");
                    assert!(same >= SAME_PRIM_MIN, "{kind} {options:?}: {same}");
                }
            }
        }
    }
}

/// Hits closer than 1e-4 (obvhs culls nodes nearer than that unless glint corrects for it),
/// at tiny scene scales, and directions with −0.0 components (obvhs's octant test treats −0.0
/// as positive): both backends must still find every hit.
#[test]
fn near_hits_tiny_scales_and_signed_zero_directions() {
    let positions = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let indices = [[0u32, 1, 2]];
    for scale in [1e-6f32, 1e-3, 1.0, 1e4] {
        let scaled: Vec<Vec3> = positions.iter().map(|p| *p * scale).collect();
        let mesh = [TriangleMesh {
            positions: &scaled,
            indices: &indices,
            instances: &[],
        }];
        for (k, options) in accel::every_configuration() {
            let kind = accel::configuration_label(k, &options);
            let accel = accel::build(k, &mesh, options).expect("build");
            for height in [1e-9f32, 1e-6, 1e-3, 1.0] {
                let origin = Vec3::new(0.25, 0.25, height) * scale;
                // -Vec3::Z is (-0.0, -0.0, -1.0).
                for dir in [
                    -Vec3::Z,
                    Vec3::new(0.0, 0.0, -1.0),
                    Vec3::new(-0.0, 0.0, -2.0),
                ] {
                    let ray = Ray::new(origin, dir);
                    let hit = accel.intersect(&ray);
                    let what = format!("{kind}, scale {scale}, height {height}, dir {dir:?}");
                    let hit = hit.unwrap_or_else(|| panic!("{what}: missed"));
                    let expected = height * scale / dir.length();
                    assert!(
                        (hit.t - expected).abs() <= expected * 1e-5,
                        "{what}: t {}",
                        hit.t
                    );
                    assert!(accel.occluded(&ray), "{what}: not occluded");
                    let short = Ray::segment(origin, dir, 0.0, expected * 0.999);
                    assert!(!accel.occluded(&short), "{what}: occluded short of the hit");
                }
            }
        }
    }
}
