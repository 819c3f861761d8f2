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
                // A triangle whose normal (computed as `intersect_triangle` does) is zero is
                // never hit (the determinant is 0 for every ray), and thousands of coincident
                // ones make obvhs's PLOC build take seconds: leave them out of the tree.
                if (c - a).cross(a - b) == Vec3A::ZERO {
                    continue;
                }
                flat.push(Triangle {
                    v0: a,
                    v1: b,
                    v2: c,
                });
                flat_ids.push([geom as u32, prim as u32]);
            }
        }
        let triangle_count = meshes.iter().map(|m| m.indices.len()).sum();
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

    /// The ray obvhs traverses with. Two quirks of obvhs's traversal are corrected here:
    /// - Its node test clamps each child's entry distance to at least [`OBVHS_NODE_T_FLOOR`]
    ///   and ignores the ray's tmin, culling every node nearer than that (in parameter units,
    ///   whatever the scene's scale). The traversal ray therefore starts [`TRAVERSAL_SHIFT`]
    ///   behind the caller's origin, so that every hit lies beyond the floor; triangles are
    ///   still tested exactly against the caller's ray.
    /// - Its ray octant treats −0.0 as positive while the inverse direction is negative, which
    ///   misses everything; −0.0 components become +0.0 (adding +0.0 does exactly that).
    fn traversal_ray(ray: &Ray) -> obvhs::ray::Ray {
        let dir = Vec3A::from(ray.dir) + Vec3A::ZERO;
        obvhs::ray::Ray::new(
            Vec3A::from(ray.origin) - dir * TRAVERSAL_SHIFT,
            dir,
            ray.tnear + TRAVERSAL_SHIFT,
            (ray.tfar + TRAVERSAL_SHIFT).next_up(),
        )
    }

    fn exact_ray(ray: &Ray) -> obvhs::ray::Ray {
        obvhs::ray::Ray::new(
            Vec3A::from(ray.origin),
            Vec3A::from(ray.dir),
            ray.tnear,
            ray.tfar,
        )
    }
}

/// obvhs's internal lower bound on a node's entry distance (`cwbvh::node::EPSILON`).
const OBVHS_NODE_T_FLOOR: f32 = 1e-4;
/// How far (in ray-parameter units) the traversal ray starts behind the caller's origin: twice
/// the floor, so that no hit at t ≥ 0 falls under it.
const TRAVERSAL_SHIFT: f32 = 2.0 * OBVHS_NODE_T_FLOOR;

/// Möller–Trumbore as Embree computes it, scaled by the determinant to defer the division.
/// Returns `(t, u, v)` with `tnear < t <= tfar` (Embree's interval rule), or `None`.
#[inline(always)]
fn intersect_triangle(tri: &Triangle, ray: &obvhs::ray::Ray) -> Option<(f32, f32, f32)> {
    let (tnear, tfar) = (ray.tmin, ray.tmax);
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
        let exact = Self::exact_ray(ray);
        // The closest hit is tracked here, exactly; obvhs gets the shifted distance only to
        // prune nodes beyond it (rounding t + shift is monotonic, so no closer node is pruned).
        let mut best: Option<(usize, f32, f32, f32)> = None;
        let mut best_t = ray.tfar;
        let mut ignored = RayHit::none();
        self.bvh
            .ray_traverse(
                Self::traversal_ray(ray),
                &mut ignored,
                |_, id| match intersect_triangle(&self.triangles[id], &exact) {
                    Some((t, u, v)) if best.is_none() || t < best_t => {
                        best = Some((id, t, u, v));
                        best_t = t;
                        t + TRAVERSAL_SHIFT
                    }
                    _ => f32::INFINITY,
                },
            );
        let (index, t, u, v) = best?;
        let tri = &self.triangles[index];
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
        let exact = Self::exact_ray(ray);
        // Any hit ends the traversal: report it as -∞ so that obvhs's `t < tmax` accepts it.
        !self
            .bvh
            .ray_traverse_miss(Self::traversal_ray(ray), |_, id| {
                match intersect_triangle(&self.triangles[id], &exact) {
                    Some(_) => f32::NEG_INFINITY,
                    None => f32::INFINITY,
                }
            })
    }

    fn triangle_count(&self) -> usize {
        self.triangle_count
    }
}
