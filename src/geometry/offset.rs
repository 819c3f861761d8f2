//! Spawning rays from a surface without re-hitting it (pbrt-v4's `OffsetRayOrigin`,
//! `SpawnRay` and `SpawnRayTo`).

use crate::accel::Ray;
use glam::Vec3;

/// How much of a shadow segment toward a point light is tested, as a fraction short of the
/// light: the segment ends at `1 − SHADOW_EPSILON` so that geometry at the light's own position
/// (a bulb's housing modelled around it) does not shadow it. Relative, so scale-free.
pub const SHADOW_EPSILON: f32 = 1.0e-4;

/// Moves `p` (with per-axis error bound `p_error`) along the geometric normal `n` to the side
/// that `w` points to, far enough that the error box lies behind the new origin: by
/// `d = dot(|n|, p_error)`, then rounds each moved coordinate one more ulp away from the surface.
///
/// `n` need not face `w`; only the sign of `dot(w, n)` chooses the side.
#[inline]
pub fn offset_ray_origin(p: Vec3, p_error: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    let d = n.abs().dot(p_error);
    let mut offset = d * n;
    if w.dot(n) < 0.0 {
        offset = -offset;
    }
    let mut po = p + offset;
    // Rounding in the addition above may land back inside the error box: step one more
    // representable value outward on every axis that moved.
    for axis in 0..3 {
        if offset[axis] > 0.0 {
            po[axis] = po[axis].next_up();
        } else if offset[axis] < 0.0 {
            po[axis] = po[axis].next_down();
        }
    }
    po
}

/// A ray leaving the surface point `p` in direction `dir`, over `(0, ∞)`.
#[inline]
pub fn spawn_ray(p: Vec3, p_error: Vec3, n: Vec3, dir: Vec3) -> Ray {
    Ray::new(offset_ray_origin(p, p_error, n, dir), dir)
}

/// A shadow segment from the surface point `p` toward `target`: the origin is offset as in
/// [`offset_ray_origin`], the direction is `target − origin` (so `t = 1` is the target) and the
/// interval is `(0, 1 − SHADOW_EPSILON]`.
#[inline]
pub fn spawn_ray_to(p: Vec3, p_error: Vec3, n: Vec3, target: Vec3) -> Ray {
    let origin = offset_ray_origin(p, p_error, n, target - p);
    Ray::segment(origin, target - origin, 0.0, 1.0 - SHADOW_EPSILON)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The offset origin lies strictly on `w`'s side of the plane through `p` for every
    /// point of the error box, however large the coordinates.
    #[test]
    fn offset_clears_the_error_box() {
        let n = Vec3::new(0.3, 0.9, -0.2).normalize();
        for scale in [1e-4f32, 1.0, 1e6] {
            let p = Vec3::new(1.5, -2.25, 0.125) * scale;
            let err = p.abs() * 1e-6;
            for w in [n, -n] {
                let o = offset_ray_origin(p, err, n, w);
                // The farthest corner of the box toward w's side.
                let corner = p + err * n.signum() * w.dot(n).signum();
                let side = ((o - corner).as_dvec3()).dot(n.as_dvec3()) * w.dot(n) as f64;
                assert!(side > 0.0, "scale {scale}: origin not past the error box");
            }
        }
    }

    #[test]
    fn spawn_ray_to_ends_just_short_of_the_target() {
        let p = Vec3::new(0.0, 0.0, 0.0);
        let target = Vec3::new(0.0, 2.0, 0.0);
        let ray = spawn_ray_to(p, Vec3::splat(1e-7), Vec3::Y, target);
        assert!(ray.origin.y > 0.0);
        let end = ray.at(ray.tfar);
        assert!(end.y < target.y && end.y > target.y * (1.0 - 2.0 * SHADOW_EPSILON));
        assert_eq!(ray.at(1.0), target);
    }
}
