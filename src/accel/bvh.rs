//! The pure-Rust backend: compressed wide BVHs (CWBVH) built with PLOC by the `obvhs` crate.
//!
//! Meshes drawn as given share one BVH in world space. A mesh with placements gets its own
//! BVH in object space, and a top-level BVH over all placements' world bounds finds the copies
//! a ray may meet; the ray is carried into each copy's object space (same `t`) and the hit's
//! normal back to world space. This is the two-level layout Embree's instances have.
//!
//! obvhs owns the tree and its traversal; this module owns the triangles. They are stored in
//! the BVH's leaf order (so a leaf's triangles are contiguous in memory) and intersected with
//! the same Möller–Trumbore formulation and the same interval rule (`tnear < t <= tfar`) that
//! Embree's default triangle intersector uses, so that both backends agree on edges and at the
//! ends of the interval.

use super::triangle::{self, to_object};
use super::{Accel, BackendKind, BuildOptions, BuildQuality, Hit, Placement, Ray, TriangleMesh};
use glam::{Vec3, Vec3A};
use obvhs::{BvhBuildParams, cwbvh::CwBvh, ray::RayHit, triangle::Triangle};
use std::time::Duration;

/// The obvhs CWBVHs over a scene's triangles: one over every mesh drawn as given, and, for
/// meshes with placements, one per mesh in object space under a top-level BVH over the
/// placements' world bounds.
pub struct BvhAccel {
    /// Meshes without placements, in world space.
    direct: Blas,
    /// One structure per placed mesh, in object space.
    placed: Vec<Blas>,
    /// The top level over every placement of every placed mesh.
    top: CwBvh,
    /// The placements in the top level's leaf order.
    top_items: Vec<TopItem>,
    triangle_count: usize,
}

/// One placement in the top level.
struct TopItem {
    /// Index into `BvhAccel::placed`.
    blas: u32,
    /// Which of its placements.
    instance: u32,
    placement: Placement,
}

impl TopItem {
    /// The world-space hit of entry `index` of `blas` (this item's structure) at `t`, (`u`, `v`).
    fn hit(&self, blas: &Blas, index: usize, t: f32, u: f32, v: f32) -> Hit {
        let [geom_id, prim_id] = blas.ids[index];
        Hit {
            t,
            geom_id,
            prim_id,
            instance: self.instance,
            u,
            v,
            ng: self
                .placement
                .normal(blas.normal(index))
                .normalize_or_zero(),
        }
    }
}

/// A bottom-level structure: a CWBVH and its triangles in leaf order.
#[derive(Default)]
struct Blas {
    bvh: CwBvh,
    /// Triangles in leaf order (spatial splits may list one triangle in several leaves).
    triangles: Vec<Triangle>,
    /// (geometry id, primitive id) of each entry of `triangles`.
    ids: Vec<[u32; 2]>,
}

/// A hit inside one bottom-level structure: the entry of `triangles` and `(t, u, v)`.
type BlasHit = (usize, f32, f32, f32);

impl Blas {
    /// Builds over the meshes given as `(geometry id, mesh)`, in the meshes' own space.
    fn build<'a>(
        meshes: impl Iterator<Item = (u32, &'a TriangleMesh<'a>)>,
        options: BuildOptions,
    ) -> Self {
        let mut flat = Vec::new();
        let mut flat_ids = Vec::new();
        for (geom, mesh) in meshes {
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
                flat_ids.push([geom, prim as u32]);
            }
        }
        if flat.is_empty() {
            return Self::default();
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
        }
    }

    /// The closest hit of `ray` in `[tnear, tfar]`.
    fn closest(&self, ray: &Ray) -> Option<BlasHit> {
        if self.triangles.is_empty() {
            return None;
        }
        let exact = exact_ray(ray);
        // The closest hit is tracked here, exactly; obvhs gets the shifted distance only to
        // prune nodes beyond it (rounding t + shift is monotonic, so no closer node is pruned).
        let mut best: Option<BlasHit> = None;
        let mut best_t = ray.tfar;
        let mut ignored = RayHit::none();
        self.bvh.ray_traverse(
            traversal_ray(ray),
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
        best
    }

    /// Whether anything lies in `[tnear, tfar]`.
    fn any(&self, ray: &Ray) -> bool {
        if self.triangles.is_empty() {
            return false;
        }
        let exact = exact_ray(ray);
        // Any hit ends the traversal: report it as -∞ so that obvhs's `t < tmax` accepts it.
        !self.bvh.ray_traverse_miss(traversal_ray(ray), |_, id| {
            match intersect_triangle(&self.triangles[id], &exact) {
                Some(_) => f32::NEG_INFINITY,
                None => f32::INFINITY,
            }
        })
    }

    /// Calls `found` with every hit of `ray` in `[tnear, tfar]` (entry, `t`, `u`, `v`).
    fn each(&self, ray: &Ray, mut found: impl FnMut(BlasHit)) {
        if self.triangles.is_empty() {
            return;
        }
        let exact = exact_ray(ray);
        // Reporting every hit as a miss (+∞) keeps obvhs traversing the whole interval.
        self.bvh.ray_traverse_miss(traversal_ray(ray), |_, id| {
            if let Some((t, u, v)) = intersect_triangle(&self.triangles[id], &exact) {
                found((id, t, u, v));
            }
            f32::INFINITY
        });
    }

    /// The unnormalised winding normal of entry `index`.
    fn normal(&self, index: usize) -> Vec3 {
        let tri = &self.triangles[index];
        triangle::winding_normal(tri.v0, tri.v1, tri.v2)
    }

    fn memory_bytes(&self) -> usize {
        self.bvh.nodes.len() * std::mem::size_of::<obvhs::cwbvh::node::CwBvhNode>()
            + self.bvh.primitive_indices.len() * 4
            + self.triangles.len() * std::mem::size_of::<Triangle>()
            + self.ids.len() * 8
    }
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
    /// Builds the BVHs over all meshes. `options.robust` has no counterpart in obvhs.
    pub fn build(meshes: &[TriangleMesh<'_>], options: BuildOptions) -> Self {
        let triangle_count = meshes.iter().map(TriangleMesh::drawn_triangles).sum();
        let direct = Blas::build(
            meshes
                .iter()
                .enumerate()
                .filter(|(_, m)| m.instances.is_empty())
                .map(|(g, m)| (g as u32, m)),
            options,
        );
        let mut placed = Vec::new();
        let mut items = Vec::new();
        let mut bounds = Vec::new();
        for (geom, mesh) in meshes.iter().enumerate() {
            if mesh.instances.is_empty() {
                continue;
            }
            let blas = Blas::build(std::iter::once((geom as u32, mesh)), options);
            if blas.triangles.is_empty() {
                continue;
            }
            let (lo, hi) = (blas.bvh.total_aabb.min, blas.bvh.total_aabb.max);
            for (instance, placement) in mesh.instances.iter().enumerate() {
                let (wlo, whi) = placement.bounds(Vec3::from(lo), Vec3::from(hi));
                bounds.push(obvhs::aabb::Aabb::new(Vec3A::from(wlo), Vec3A::from(whi)));
                items.push(TopItem {
                    blas: placed.len() as u32,
                    instance: instance as u32,
                    placement: *placement,
                });
            }
            placed.push(blas);
        }
        let (top, top_items) = if items.is_empty() {
            (CwBvh::default(), Vec::new())
        } else {
            let top = obvhs::cwbvh::builder::build_cwbvh(
                &bounds,
                build_params(options.quality),
                &mut Duration::default(),
            );
            let mut slots: Vec<Option<TopItem>> = items.into_iter().map(Some).collect();
            // Each placement appears in exactly one leaf (no splits over boxes).
            let ordered = top
                .primitive_indices
                .iter()
                .filter_map(|&i| slots.get_mut(i as usize).and_then(Option::take))
                .collect();
            (top, ordered)
        };
        Self {
            direct,
            placed,
            top,
            top_items,
            triangle_count,
        }
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
#[inline]
fn traversal_ray(ray: &Ray) -> obvhs::ray::Ray {
    let dir = Vec3A::from(ray.dir) + Vec3A::ZERO;
    obvhs::ray::Ray::new(
        Vec3A::from(ray.origin) - dir * TRAVERSAL_SHIFT,
        dir,
        ray.tnear + TRAVERSAL_SHIFT,
        (ray.tfar + TRAVERSAL_SHIFT).next_up(),
    )
}

/// The caller's ray, unshifted, for the exact triangle tests.
#[inline]
fn exact_ray(ray: &Ray) -> obvhs::ray::Ray {
    obvhs::ray::Ray::new(
        Vec3A::from(ray.origin),
        Vec3A::from(ray.dir),
        ray.tnear,
        ray.tfar,
    )
}

/// obvhs's internal lower bound on a node's entry distance (`cwbvh::node::EPSILON`).
const OBVHS_NODE_T_FLOOR: f32 = 1e-4;
/// How far (in ray-parameter units) the traversal ray starts behind the caller's origin: twice
/// the floor, so that no hit at t ≥ 0 falls under it.
const TRAVERSAL_SHIFT: f32 = 2.0 * OBVHS_NODE_T_FLOOR;

/// The hit of `ray` on `tri`, with the arithmetic both backends report ([`triangle`]).
#[inline(always)]
fn intersect_triangle(tri: &Triangle, ray: &obvhs::ray::Ray) -> Option<(f32, f32, f32)> {
    triangle::intersect(
        tri.v0,
        tri.v1,
        tri.v2,
        ray.origin,
        ray.direction,
        ray.tmin,
        ray.tmax,
    )
}

impl Accel for BvhAccel {
    fn kind(&self) -> BackendKind {
        BackendKind::Bvh
    }

    fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let mut best = self.direct.closest(ray).map(|(index, t, u, v)| {
            let [geom_id, prim_id] = self.direct.ids[index];
            Hit {
                t,
                geom_id,
                prim_id,
                instance: 0,
                u,
                v,
                ng: self.direct.normal(index).normalize_or_zero(),
            }
        });
        if self.top_items.is_empty() {
            return best;
        }
        let mut bounded = *ray;
        if let Some(hit) = &best {
            bounded.tfar = hit.t;
        }
        let mut ignored = RayHit::none();
        self.top
            .ray_traverse(traversal_ray(&bounded), &mut ignored, |_, id| {
                let item = &self.top_items[id];
                let blas = &self.placed[item.blas as usize];
                match blas.closest(&to_object(&bounded, &item.placement)) {
                    // Ties go to the earlier hit, as in one structure's traversal order.
                    Some((index, t, u, v)) if best.is_none() || t < bounded.tfar => {
                        bounded.tfar = t;
                        best = Some(item.hit(blas, index, t, u, v));
                        t + TRAVERSAL_SHIFT
                    }
                    _ => f32::INFINITY,
                }
            });
        best
    }

    fn occluded(&self, ray: &Ray) -> bool {
        if self.direct.any(ray) {
            return true;
        }
        if self.top_items.is_empty() {
            return false;
        }
        !self.top.ray_traverse_miss(traversal_ray(ray), |_, id| {
            let item = &self.top_items[id];
            if self.placed[item.blas as usize].any(&to_object(ray, &item.placement)) {
                f32::NEG_INFINITY
            } else {
                f32::INFINITY
            }
        })
    }

    fn all_hits(&self, ray: &Ray, out: &mut Vec<Hit>) {
        out.clear();
        self.direct.each(ray, |(index, t, u, v)| {
            let [geom_id, prim_id] = self.direct.ids[index];
            out.push(Hit {
                t,
                geom_id,
                prim_id,
                instance: 0,
                u,
                v,
                ng: self.direct.normal(index).normalize_or_zero(),
            });
        });
        if !self.top_items.is_empty() {
            self.top.ray_traverse_miss(traversal_ray(ray), |_, id| {
                let item = &self.top_items[id];
                let blas = &self.placed[item.blas as usize];
                blas.each(&to_object(ray, &item.placement), |(index, t, u, v)| {
                    out.push(item.hit(blas, index, t, u, v));
                });
                f32::INFINITY
            });
        }
        super::order_all_hits(out);
    }

    fn triangle_count(&self) -> usize {
        self.triangle_count
    }

    fn memory_bytes(&self) -> Option<usize> {
        let top = self.top.nodes.len() * std::mem::size_of::<obvhs::cwbvh::node::CwBvhNode>()
            + self.top.primitive_indices.len() * 4
            + self.top_items.len() * std::mem::size_of::<TopItem>();
        Some(
            self.direct.memory_bytes()
                + self.placed.iter().map(Blas::memory_bytes).sum::<usize>()
                + top,
        )
    }
}
