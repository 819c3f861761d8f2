//! The C shim's contract, checked through the Embree backend on whichever Embree (3 or 4) the
//! build links: meshes without triangles keep geometry ids equal to mesh indices, and the
//! 8-wide packet paths (with a masked last packet) answer exactly as the single-ray paths do.
//! `ffi/shim_test.c` checks what Rust cannot reach (errors, lifetimes, struct overruns).

#![cfg(feature = "embree")]

use glam::Vec3;
use glint::accel::embree::EmbreeAccel;
use glint::accel::{self, BackendKind, BuildOptions, Coherence, Hit, Ray, TriangleMesh};
use glint::procedural;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;

/// Both backends: a mesh with vertices but no triangles and a mesh with nothing at all still
/// take their geometry ids, so the mesh after them is found under its own index.
#[test]
fn meshes_without_triangles_keep_ids_dense() {
    let triangle = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let shifted = triangle.map(|p| p + Vec3::new(5.0, 0.0, 0.0));
    let indices = [[0u32, 1, 2]];
    let meshes = [
        TriangleMesh {
            positions: &triangle,
            indices: &indices,
            instances: &[],
        },
        TriangleMesh {
            positions: &triangle,
            indices: &[],
            instances: &[],
        },
        TriangleMesh {
            positions: &[],
            indices: &[],
            instances: &[],
        },
        TriangleMesh {
            positions: &shifted,
            indices: &indices,
            instances: &[],
        },
    ];
    // +0.0 components on purpose: the bvh backend misses rays whose direction has -0.0 ones
    // (`-Vec3::Z`), a separate bug; this test is about geometry ids.
    let down = Vec3::new(0.0, 0.0, -1.0);
    for &kind in BackendKind::available() {
        let accel = accel::build(kind, &meshes, BuildOptions::default())
            .unwrap_or_else(|e| panic!("{kind}: empty meshes must build: {e}"));
        let hit = accel
            .intersect(&Ray::new(Vec3::new(5.25, 0.25, 1.0), down))
            .unwrap_or_else(|| panic!("{kind}: the last mesh is hit"));
        assert_eq!((hit.geom_id, hit.prim_id), (3, 0), "{kind}");
        let hit = accel
            .intersect(&Ray::new(Vec3::new(0.25, 0.25, 1.0), down))
            .unwrap_or_else(|| panic!("{kind}: the first mesh is hit"));
        assert_eq!((hit.geom_id, hit.prim_id), (0, 0), "{kind}");
        assert_eq!(accel.triangle_count(), 2, "{kind}");
    }
}

/// Rays from a shell around the unit sphere towards points inside it: most hit, some miss,
/// some are cut short by tfar.
fn rays_around_sphere(n: usize, seed: u64) -> Vec<Ray> {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let mut point = |scale: f32| {
        Vec3::new(
            rng.random_range(-1.0..=1.0),
            rng.random_range(-1.0..=1.0),
            rng.random_range(-1.0..=1.0),
        ) * scale
    };
    (0..n)
        .map(|i| {
            let origin = point(3.0);
            let target = point(1.2);
            let dir = (target - origin).normalize_or(Vec3::Z);
            // Every fifth ray ends early, so occlusion and tfar clipping are both exercised.
            let tfar = if i % 5 == 0 { 1.5 } else { f32::INFINITY };
            Ray::segment(origin, dir, 0.0, tfar)
        })
        .collect()
}

/// Packets and single rays run different Embree kernels over the same triangles; the answers
/// must be identical (same triangle, same t to within rounding) including in the masked lanes
/// of a last packet of fewer than 8 rays. 1003 rays leave a last packet of 3. On every
/// instruction set the CPU has: each has its own single-ray and packet kernels.
#[test]
fn packets_answer_like_single_rays() {
    let mesh = procedural::displaced_sphere(4, 0.05, 21);
    let rays = rays_around_sphere(1003, 22);
    let isas = std::iter::once(glint::accel::EmbreeIsa::Native)
        .chain(glint::accel::EmbreeIsa::supported());
    for isa in isas {
        let options = BuildOptions {
            embree_isa: Some(isa),
            ..BuildOptions::default()
        };
        let accel = EmbreeAccel::build(&[mesh.as_triangle_mesh()], options).expect("builds");
        packets_answer_like_single_rays_on(&accel, &rays);
    }
}

fn packets_answer_like_single_rays_on(accel: &EmbreeAccel, rays: &[Ray]) {
    for coherence in [Coherence::Coherent, Coherence::Incoherent] {
        let mut single: Vec<Option<Hit>> = vec![None; rays.len()];
        let mut packets: Vec<Option<Hit>> = vec![None; rays.len()];
        accel.intersect_single(rays, &mut single, coherence);
        accel.intersect_packets(rays, &mut packets, coherence);
        let hits = single.iter().flatten().count();
        assert!(
            hits > rays.len() / 4 && hits < rays.len(),
            "{coherence:?}: {hits} hits of {} is not a mix of hits and misses",
            rays.len()
        );
        for (i, (s, p)) in single.iter().zip(&packets).enumerate() {
            match (s, p) {
                (Some(s), Some(p)) => {
                    let isa = accel.isa();
                    assert_eq!(
                        (s.geom_id, s.prim_id),
                        (p.geom_id, p.prim_id),
                        "{isa}: ray {i}"
                    );
                    assert!((s.t - p.t).abs() <= 1e-5 * s.t, "ray {i}: {s:?} vs {p:?}");
                    assert!(
                        (s.u - p.u).abs() <= 1e-4 && (s.v - p.v).abs() <= 1e-4,
                        "ray {i}"
                    );
                    assert!((s.ng - p.ng).length() <= 1e-5, "ray {i}");
                }
                (None, None) => {}
                _ => panic!("ray {i}: single {s:?}, packet {p:?}"),
            }
        }
        let mut single_blocked = vec![false; rays.len()];
        let mut packet_blocked = vec![true; rays.len()];
        accel.occluded_single(rays, &mut single_blocked, coherence);
        accel.occluded_packets(rays, &mut packet_blocked, coherence);
        assert_eq!(single_blocked, packet_blocked, "{coherence:?}");
        // Occlusion is the closest hit's existence: the same interval, the same triangles.
        let from_hits: Vec<bool> = single.iter().map(Option::is_some).collect();
        assert_eq!(single_blocked, from_hits, "{coherence:?}");
    }
}
