//! The pure-Rust backend: a compressed wide BVH (CWBVH) built with PLOC by the `obvhs` crate.
//!
//! obvhs owns the tree and its traversal; this module owns the triangles. They are stored in
//! the BVH's leaf order (so a leaf's triangles are contiguous in memory) and intersected with
//! the same Möller–Trumbore formulation and the same interval rule (`tnear < t <= tfar`) that
//! Embree's default triangle intersector uses, so that both backends agree on edges and at the
//! ends of the interval.

use super::{Accel, BackendKind, BuildOptions, BuildQuality, Hit, Ray, TriangleMesh};
use glam::{Vec3, Vec3A};
use obvhs::{BvhBuildParams, cwbvh::CwBvh, ray::RayHit, triangle::Triangle};
use std::time::Duration;

/// The obvhs CWBVH over a scene's triangles.
pub struct BvhAccel {
    bvh: CwBvh,
    /// Triangles in leaf order (spatial splits may list one triangle in several leaves).
    triangles: Vec<Triangle>,
    /// (geometry id, primitive id) of each entry of `triangles`.
    ids: Vec<[u32; 2]>,
    triangle_count: usize,
}

/// obvhs's build preset for a quality level.
pub fn build_params(quality: BuildQuality) -> BvhBuildParams {
    match quality {
        BuildQuality::Low => BvhBuildParams::fast_build(),
        BuildQuality::Medium => BvhBuildParams::medium_build(),
        BuildQuality::High => BvhBuildParams::very_slow_build(),
    }
}

impl BvhAccel {
    /// Builds the BVH over all meshes. `options.robust` has no counterpart in obvhs.
    pub fn build(meshes: &[TriangleMesh<'_>], options: BuildOptions) -> Self {
        let mut flat = Vec::with_capacity(meshes.iter().map(|m| m.indices.len()).sum());
        let mut flat_ids = Vec::with_capacity(flat.capacity());
        for (geom, mesh) in meshes.iter().enumerate() {
            for (prim, tri) in mesh.indices.iter().enumerate() {
                let [a, b, c] = tri.map(|i| Vec3A::from(mesh.positions[i as usize]));
                flat.push(Triangle {
                    v0: a,
                    v1: b,
                    v2: c,
                });
                flat_ids.push([geom as u32, prim as u32]);
            }
        }
        let triangle_count = flat.len();
        if flat.is_empty() {
            return Self {
                bvh: CwBvh::default(),
                triangles: Vec::new(),
                ids: Vec::new(),
                triangle_count,
            };
        }
        let bvh = obvhs::cwbvh::builder::build_cwbvh_from_tris(
            &flat,
            build_params(options.quality),
            &mut Duration::default(),
        );
        let triangles = bvh
            .primitive_indices
            .iter()
            .map(|&i| flat[i as usize])
            .collect();
        let ids = bvh
            .primitive_indices
            .iter()
            .map(|&i| flat_ids[i as usize])
            .collect();
        Self {
            bvh,
            triangles,
            ids,
            triangle_count,
        }
    }

    /// obvhs accepts a candidate only if `t < tmax`, where Embree's rule is `t <= tfar`; the
    /// traversal ray's tmax is therefore one ulp past tfar, and the exact interval test happens
    /// in [`intersect_triangle`] against the caller's `tfar`.
    fn obvhs_ray(ray: &Ray) -> obvhs::ray::Ray {
        obvhs::ray::Ray::new(
            Vec3A::from(ray.origin),
            Vec3A::from(ray.dir),
            ray.tnear,
            ray.tfar.next_up(),
        )
    }
}

/// Möller–Trumbore as Embree computes it, scaled by the determinant to defer the division.
/// Returns `(t, u, v)` with `tnear < t <= tfar`, or `None`.
#[inline(always)]
fn intersect_triangle(
    tri: &Triangle,
    ray: &obvhs::ray::Ray,
    tnear: f32,
    tfar: f32,
) -> Option<(f32, f32, f32)> {
    let e1 = tri.v0 - tri.v1;
    let e2 = tri.v2 - tri.v0;
    let ng = e2.cross(e1);
    let c = tri.v0 - ray.origin;
    let r = c.cross(ray.direction);
    let den = ng.dot(ray.direction);
    let abs_den = den.abs();
    let sign = den.signum();
    let u = r.dot(e2) * sign;
    let v = r.dot(e1) * sign;
    if den == 0.0 || u < 0.0 || v < 0.0 || u + v > abs_den {
        return None;
    }
    let t_scaled = ng.dot(c) * sign;
    if !(abs_den * tnear < t_scaled && t_scaled <= abs_den * tfar) {
        return None;
    }
    let inv = 1.0 / abs_den;
    Some((t_scaled * inv, u * inv, v * inv))
}

impl Accel for BvhAccel {
    fn kind(&self) -> BackendKind {
        BackendKind::Bvh
    }

    fn intersect(&self, ray: &Ray) -> Option<Hit> {
        if self.triangles.is_empty() {
            return None;
        }
        let oray = Self::obvhs_ray(ray);
        let mut hit = RayHit::none();
        let found = self.bvh.ray_traverse(oray, &mut hit, |r, id| {
            intersect_triangle(&self.triangles[id], r, ray.tnear, ray.tfar)
                .map_or(f32::INFINITY, |(t, _, _)| t)
        });
        if !found {
            return None;
        }
        let index = hit.primitive_id as usize;
        let tri = &self.triangles[index];
        // Recompute u, v for the winner only; the traversal needs t alone.
        let (t, u, v) = intersect_triangle(tri, &oray, ray.tnear, ray.tfar)?;
        let [geom_id, prim_id] = self.ids[index];
        Some(Hit {
            t,
            geom_id,
            prim_id,
            u,
            v,
            ng: Vec3::from((tri.v1 - tri.v0).cross(tri.v2 - tri.v0).normalize_or_zero()),
        })
    }

    fn occluded(&self, ray: &Ray) -> bool {
        if self.triangles.is_empty() {
            return false;
        }
        let oray = Self::obvhs_ray(ray);
        // Any hit in the interval ends the traversal: report it as -∞ so that obvhs's
        // `t < tmax` test cannot reject a hit at exactly tfar.
        !self.bvh.ray_traverse_miss(oray, |r, id| {
            match intersect_triangle(&self.triangles[id], r, ray.tnear, ray.tfar) {
                Some(_) => f32::NEG_INFINITY,
                None => f32::INFINITY,
            }
        })
    }

    fn triangle_count(&self) -> usize {
        self.triangle_count
    }
}
