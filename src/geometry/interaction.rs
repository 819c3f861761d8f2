//! The surface interaction: everything about a ray hit that shading reads, computed once.

use super::error::triangle_point;
use super::float::gamma;
use crate::accel::{Hit, Placement};
use crate::scene::Mesh;
use glam::{Mat3A, Vec3, Vec3A, Vec4};

/// A ray hit on a triangle, in world space.
///
/// Both normals are oriented toward the side the ray came from (`dot(ng, wo) > 0`), so shading
/// is the same for either face; [`SurfaceInteraction::front_face`] keeps which face it was.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceInteraction {
    /// The hit point, reconstructed from barycentrics.
    pub p: Vec3,
    /// Per-axis bound on the absolute floating-point error of `p`.
    pub p_error: Vec3,
    /// Unit geometric normal, on the incoming ray's side.
    pub ng: Vec3,
    /// Unit shading normal (interpolated vertex normals, or `ng`), flipped with `ng`.
    pub ns: Vec3,
    /// Unit direction from `p` back along the incoming ray.
    pub wo: Vec3,
    /// Whether the ray hit the front face (glTF winding: counter-clockwise seen from the front).
    pub front_face: bool,
    /// Barycentric weights of the triangle's three vertices.
    pub barycentrics: [f32; 3],
    /// The triangle's vertex indices.
    pub vertices: [u32; 3],
    /// The placement of the copy hit, for a mesh stored in object space: its per-vertex
    /// normals and tangents go to world space through it.
    pub placement: Option<Placement>,
}

impl SurfaceInteraction {
    /// Builds the record for `hit` on `mesh` of a ray with direction `ray_dir`, with
    /// `ns = ng` (see [`shading_normal`] to interpolate vertex normals).
    ///
    /// `None` when the hit cannot be shaded: the triangle is not in the mesh, or it is so
    /// degenerate that it has no normal. The caller treats it as black, never as NaN.
    #[inline]
    pub fn from_hit(mesh: &Mesh, hit: &Hit, ray_dir: Vec3) -> Option<Self> {
        let vertices = *mesh.indices.get(hit.prim_id as usize)?;
        let [p0, p1, p2] = mesh.corners(vertices, None)?;
        let (p, p_error) = triangle_point(p0, p1, p2, hit.u, hit.v);
        let placement = match mesh.instances.len() {
            0 => None,
            _ => Some(*mesh.placement(hit.instance)?),
        };
        let (p, p_error) = match &placement {
            Some(placement) => transformed_point(placement, p, p_error),
            None => (p, p_error),
        };
        let wo = (-ray_dir).normalize_or_zero();
        if !hit.ng.is_finite() || hit.ng == Vec3::ZERO || wo == Vec3::ZERO || !p.is_finite() {
            return None;
        }
        let front_face = hit.ng.dot(wo) > 0.0;
        let ng = if front_face { hit.ng } else { -hit.ng };
        Some(Self {
            p,
            p_error,
            ng,
            ns: ng,
            wo,
            front_face,
            barycentrics: [1.0 - hit.u - hit.v, hit.u, hit.v],
            vertices,
            placement,
        })
    }

    /// The hit triangle's corners in world space (`None` if an index is out of range).
    #[inline]
    pub fn world_triangle(&self, mesh: &Mesh) -> Option<[Vec3; 3]> {
        mesh.corners(self.vertices, self.placement.as_ref())
    }

    /// An interpolated per-vertex normal (or its derivative) in world space; not normalised.
    #[inline]
    pub fn normal_to_world(&self, n: Vec3) -> Vec3 {
        match &self.placement {
            Some(placement) => placement.normal(n),
            None => n,
        }
    }

    /// A per-vertex tangent (xyz, handedness w) in world space: xyz through the placement
    /// (not normalised), w flipped by a mirroring one so that the bitangent `w · n × t`
    /// follows the surface.
    #[inline]
    pub fn tangent_to_world(&self, t: Vec4) -> Vec4 {
        match &self.placement {
            Some(placement) => {
                let w = if placement.mirrored() { -t.w } else { t.w };
                placement.vector(t.truncate()).extend(w)
            }
            None => t,
        }
    }

    /// Interpolates a per-vertex attribute with the hit's barycentrics. `None` if an index is
    /// out of range for `values`.
    #[inline]
    pub fn interpolate<T>(&self, values: &[T]) -> Option<T>
    where
        T: Copy + std::ops::Mul<f32, Output = T> + std::ops::Add<Output = T>,
    {
        let [b0, b1, b2] = self.barycentrics;
        let [i0, i1, i2] = self.vertices.map(|i| i as usize);
        Some(*values.get(i0)? * b0 + *values.get(i1)? * b1 + *values.get(i2)? * b2)
    }
}

/// The shading normal from per-vertex normals: their barycentric interpolation, normalised and
/// flipped with the geometric normal when the back face was hit. Falls back to `si.ng` when
/// the interpolation is zero or not finite (opposite normals, bad data), so it is always unit.
#[inline]
pub fn shading_normal(si: &SurfaceInteraction, normals: &[Vec3]) -> Vec3 {
    match si.interpolate(normals) {
        Some(n) => {
            let n = si.normal_to_world(n).normalize_or_zero();
            if n == Vec3::ZERO {
                si.ng
            } else if si.front_face {
                n
            } else {
                -n
            }
        }
        None => si.ng,
    }
}

/// A point and its error bound carried through an affine placement: the bound grows by the
/// rounding of the 3×3 product and the translation (pbrt-v4's transformed interval point):
/// `(1 + γ₃)|L|·e + γ₃(|L|·|p| + |t|)`.
#[inline]
fn transformed_point(placement: &Placement, p: Vec3, error: Vec3) -> (Vec3, Vec3) {
    let m = placement.world_from_object();
    let abs = Mat3A::from_cols(
        m.matrix3.x_axis.abs(),
        m.matrix3.y_axis.abs(),
        m.matrix3.z_axis.abs(),
    );
    let g3 = gamma(3);
    let e = Vec3A::from(error);
    let a = Vec3A::from(p).abs();
    let bound = (1.0 + g3) * (abs * e) + g3 * (abs * a + m.translation.abs());
    (placement.point(p), Vec3::from(bound))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad_mesh() -> Mesh {
        Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Z],
            indices: vec![[0, 2, 1]],
            normals: Some(vec![Vec3::Y, Vec3::Y, Vec3::new(1.0, 1.0, 0.0).normalize()]),
            ..Default::default()
        }
    }

    #[test]
    fn back_face_hits_flip_both_normals() {
        let mesh = quad_mesh();
        // (v1 − v0) × (v2 − v0) = Z × X = +Y.
        let hit = Hit {
            t: 1.0,
            geom_id: 0,
            prim_id: 0,
            u: 0.25,
            v: 0.25,
            ng: Vec3::Y,
            instance: 0,
        };
        let front = SurfaceInteraction::from_hit(&mesh, &hit, -Vec3::Y).unwrap();
        assert!(front.front_face && front.ng == Vec3::Y);
        let back = SurfaceInteraction::from_hit(&mesh, &hit, Vec3::Y).unwrap();
        assert!(!back.front_face && back.ng == -Vec3::Y);
        let ns = shading_normal(&back, mesh.normals.as_deref().unwrap());
        assert!(ns.dot(back.ng) > 0.0 && (ns.length() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn degenerate_hits_are_rejected_not_nan() {
        let mesh = quad_mesh();
        let hit = Hit {
            t: 1.0,
            geom_id: 0,
            prim_id: 0,
            u: 0.25,
            v: 0.25,
            ng: Vec3::ZERO,
            instance: 0,
        };
        assert!(SurfaceInteraction::from_hit(&mesh, &hit, -Vec3::Y).is_none());
        let bad_prim = Hit {
            prim_id: 7,
            ng: Vec3::Y,
            ..hit
        };
        assert!(SurfaceInteraction::from_hit(&mesh, &bad_prim, -Vec3::Y).is_none());
    }
}
