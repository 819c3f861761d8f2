//! Placements: where one object-space mesh is drawn, for two-level ray queries.
//!
//! A mesh with placements is stored once, in object space, and drawn once per placement
//! (glTF's EXT_mesh_gpu_instancing, or a mesh several nodes share). Both backends keep one
//! structure for the mesh and a top level over its placements, so memory grows with the
//! unique geometry rather than with the number of copies.

use glam::{Affine3A, Mat3A, Vec3, Vec3A};

/// The matrix that maps object-space normals to world space for the linear map `linear`: the
/// inverse transpose, computed as the cofactor matrix (det · inverse transpose) with the
/// determinant's sign restored. Unlike an inverse, the cofactor exists for a singular
/// (flattening) map too; callers normalise, so the magnitude of det does not matter.
pub fn normal_matrix(linear: Mat3A) -> Mat3A {
    let (a, b, c) = (linear.x_axis, linear.y_axis, linear.z_axis);
    let cofactor = Mat3A::from_cols(b.cross(c), c.cross(a), a.cross(b));
    if linear.determinant() < 0.0 {
        -cofactor
    } else {
        cofactor
    }
}

/// One copy of an object-space mesh in the world: its affine world-from-object transform, with
/// the inverse and the normal matrix computed once.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    world_from_object: Affine3A,
    object_from_world: Affine3A,
    /// Maps object-space normals to world space: the inverse transpose of the linear part
    /// (its cofactor matrix with the determinant's sign, so only the direction is exact).
    normal_from_object: Mat3A,
    /// Whether the transform mirrors (negative determinant).
    mirrored: bool,
    /// The glTF node that places this copy, reported by the `instance_id` AOV; the ray
    /// backends ignore it.
    pub node: Option<u32>,
}

impl Placement {
    /// The placement for `world_from_object`, or `None` when the transform is not finite or
    /// not invertible (a copy scaled to nothing covers no area and is never hit).
    pub fn new(world_from_object: Affine3A, node: Option<u32>) -> Option<Self> {
        let linear = world_from_object.matrix3;
        let det = linear.determinant();
        if !world_from_object.is_finite() || !det.is_finite() || det == 0.0 {
            return None;
        }
        let object_from_world = world_from_object.inverse();
        if !object_from_world.is_finite() {
            return None;
        }
        Some(Self {
            world_from_object,
            object_from_world,
            normal_from_object: normal_matrix(linear),
            mirrored: det < 0.0,
            node,
        })
    }

    /// World from object.
    #[inline]
    pub fn world_from_object(&self) -> &Affine3A {
        &self.world_from_object
    }

    /// Object from world (the inverse).
    #[inline]
    pub fn object_from_world(&self) -> &Affine3A {
        &self.object_from_world
    }

    /// Whether the transform mirrors: then glTF's front faces, counter-clockwise in object
    /// space, are clockwise in world space, and tangent handedness flips.
    #[inline]
    pub fn mirrored(&self) -> bool {
        self.mirrored
    }

    /// A point to world space.
    #[inline]
    pub fn point(&self, p: Vec3) -> Vec3 {
        self.world_from_object.transform_point3(p)
    }

    /// A direction (tangent, displacement) to world space; not normalised.
    #[inline]
    pub fn vector(&self, v: Vec3) -> Vec3 {
        self.world_from_object.transform_vector3(v)
    }

    /// A surface normal to world space, on the same side of the surface; not normalised.
    #[inline]
    pub fn normal(&self, n: Vec3) -> Vec3 {
        Vec3::from(self.normal_from_object * Vec3A::from(n))
    }

    /// The linear part (world from object), for error bounds.
    #[inline]
    pub fn linear(&self) -> Mat3A {
        self.world_from_object.matrix3
    }

    /// The world-space bounds of object-space bounds `[lo, hi]` (the eight corners).
    pub fn bounds(&self, lo: Vec3, hi: Vec3) -> (Vec3, Vec3) {
        let mut out = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for corner in 0..8 {
            let p = Vec3::new(
                if corner & 1 == 0 { lo.x } else { hi.x },
                if corner & 2 == 0 { lo.y } else { hi.y },
                if corner & 4 == 0 { lo.z } else { hi.z },
            );
            let w = self.point(p);
            out = (out.0.min(w), out.1.max(w));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Mat3, Quat};

    #[test]
    fn normals_stay_perpendicular_and_on_their_side_under_any_transform() {
        let transforms = [
            Affine3A::from_scale_rotation_translation(
                Vec3::new(2.0, 0.5, 3.0),
                Quat::from_rotation_y(0.7),
                Vec3::new(1.0, -2.0, 5.0),
            ),
            // A mirror with shear.
            Affine3A::from_mat3(Mat3::from_cols(
                Vec3::new(-1.0, 0.2, 0.0),
                Vec3::new(0.0, 1.0, 0.3),
                Vec3::new(0.1, 0.0, 2.0),
            )),
        ];
        for m in transforms {
            let p = Placement::new(m, None).unwrap();
            let (t0, t1) = (Vec3::new(1.0, 2.0, -0.5), Vec3::new(-0.3, 0.4, 1.0));
            let n = t0.cross(t1);
            let (w0, w1, wn) = (p.vector(t0), p.vector(t1), p.normal(n));
            assert!(wn.dot(w0).abs() < 1e-4 * wn.length() * w0.length());
            assert!(wn.dot(w1).abs() < 1e-4 * wn.length() * w1.length());
            // The transformed normal keeps the side the object-space normal named: the
            // world cross product of the transformed edges flips exactly for mirrors.
            let side = w0.cross(w1).dot(wn);
            assert_eq!(side < 0.0, p.mirrored(), "{m:?}");
            let x = Vec3::new(0.3, -7.0, 2.0);
            assert!(
                p.object_from_world()
                    .transform_point3(p.point(x))
                    .distance(x)
                    < 1e-4
            );
        }
    }

    #[test]
    fn singular_and_non_finite_transforms_are_not_placements() {
        assert!(Placement::new(Affine3A::from_scale(Vec3::new(1.0, 0.0, 1.0)), None).is_none());
        assert!(Placement::new(Affine3A::from_translation(Vec3::NAN), None).is_none());
        assert!(Placement::new(Affine3A::IDENTITY, Some(3)).is_some());
    }
}
