//! The ray-triangle arithmetic whose results both backends report.
//!
//! Embree compiles its kernels for several instruction sets (SSE2 to AVX-512) and picks one
//! by the CPU it runs on. They do not round alike: the hit distance is `T / |det|` computed
//! with an approximate reciprocal (`rcpps` or `vrcp14ps` and one Newton step, with or without
//! FMA), whose last bits differ between kernels and between Intel's and AMD's `rcpps`. So the
//! same ray and triangle give `t`, `u` and `v` that differ in the last few ulps from machine to
//! machine, and so would every image.
//!
//! glint therefore lets a backend decide only *which* triangle a ray hits, and computes what it
//! reports about the hit here, in Rust, with exact IEEE division ([`solve`] and [`refine`]):
//! the obvhs backend intersects with these very functions, and the Embree backend re-solves
//! the triangle Embree reported. For a given ray and triangle, `t`, `u`, `v` and the normal are
//! then the same bits on every x86-64 CPU, whatever kernel Embree chose.

use super::{Placement, Ray};
use glam::{Vec3, Vec3A};

/// Möller–Trumbore as Embree's default triangle intersector computes it, scaled by the
/// determinant so that the division can be deferred: `u`, `v` and `t` are the barycentrics
/// and distance times `abs_den`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Scaled {
    /// The determinant (0 for a ray parallel to the triangle's plane).
    pub den: f32,
    /// `|den|`.
    pub abs_den: f32,
    /// Weight of `v1`, times `abs_den`.
    pub u: f32,
    /// Weight of `v2`, times `abs_den`.
    pub v: f32,
    /// Distance along the ray, times `abs_den`.
    pub t: f32,
}

/// Solves for the ray `origin + t·dir` against the triangle `(v0, v1, v2)`.
#[inline(always)]
pub(crate) fn solve(v0: Vec3A, v1: Vec3A, v2: Vec3A, origin: Vec3A, dir: Vec3A) -> Scaled {
    let e1 = v0 - v1;
    let e2 = v2 - v0;
    let ng = e2.cross(e1);
    let c = v0 - origin;
    let r = c.cross(dir);
    let den = ng.dot(dir);
    let abs_den = den.abs();
    let sign = den.signum();
    Scaled {
        den,
        abs_den,
        u: r.dot(e2) * sign,
        v: r.dot(e1) * sign,
        t: ng.dot(c) * sign,
    }
}

/// The hit `(t, u, v)` of the ray against the triangle when it lies inside the triangle and
/// `tnear < t <= tfar` (Embree's interval rule, tested before the division as Embree does).
#[inline(always)]
pub(crate) fn intersect(
    v0: Vec3A,
    v1: Vec3A,
    v2: Vec3A,
    origin: Vec3A,
    dir: Vec3A,
    tnear: f32,
    tfar: f32,
) -> Option<(f32, f32, f32)> {
    let s = solve(v0, v1, v2, origin, dir);
    s.accepts(tnear, tfar).then(|| s.divided())
}

impl Scaled {
    /// Whether the solution lies inside the triangle and `tnear < t <= tfar`.
    #[inline(always)]
    fn accepts(&self, tnear: f32, tfar: f32) -> bool {
        self.den != 0.0
            && self.u >= 0.0
            && self.v >= 0.0
            && self.u + self.v <= self.abs_den
            && self.abs_den * tnear < self.t
            && self.t <= self.abs_den * tfar
    }

    /// `(t, u, v)`, divided by `abs_den`.
    #[inline(always)]
    fn divided(&self) -> (f32, f32, f32) {
        let inv = 1.0 / self.abs_den;
        (self.t * inv, self.u * inv, self.v * inv)
    }
}

/// The unnormalised winding normal `(v1 − v0) × (v2 − v0)`.
#[inline(always)]
pub(crate) fn winding_normal(v0: Vec3A, v1: Vec3A, v2: Vec3A) -> Vec3 {
    Vec3::from((v1 - v0).cross(v2 - v0))
}

/// `(t, u, v)` for a ray another kernel found to hit the triangle, computed with
/// [`intersect`]'s arithmetic: exactly its answer when it accepts the hit too. Where the two
/// disagree by rounding (a ray through an edge or at an end of the interval), the barycentrics
/// are clamped into the triangle and `t` into `[tnear, tfar]`, so the answer stays a point of
/// the triangle within the ray's interval. `None` for a ray parallel to the triangle's plane
/// (the caller keeps the other kernel's answer).
#[inline]
pub(crate) fn refine(v0: Vec3A, v1: Vec3A, v2: Vec3A, ray: &Ray) -> Option<(f32, f32, f32)> {
    let s = solve(v0, v1, v2, Vec3A::from(ray.origin), Vec3A::from(ray.dir));
    if s.accepts(ray.tnear, ray.tfar) {
        return Some(s.divided());
    }
    if s.den == 0.0 || !s.abs_den.is_finite() {
        return None;
    }
    let (t, u, v) = s.divided();
    let (mut u, mut v) = (u.max(0.0), v.max(0.0));
    let sum = u + v;
    if sum > 1.0 {
        u /= sum;
        v /= sum;
    }
    let t = t.max(ray.tnear).min(ray.tfar);
    (t.is_finite() && u.is_finite() && v.is_finite()).then_some((t, u, v))
}

/// A ray carried into a placement's object space: the same parameter `t` names the same
/// point, since the map is affine.
#[inline]
pub(crate) fn to_object(ray: &Ray, placement: &Placement) -> Ray {
    let m = placement.object_from_world();
    Ray {
        origin: m.transform_point3(ray.origin),
        dir: m.transform_vector3(ray.dir),
        tnear: ray.tnear,
        tfar: ray.tfar,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit() -> [Vec3A; 3] {
        [Vec3A::ZERO, Vec3A::X, Vec3A::Y]
    }

    #[test]
    fn refine_equals_intersect_where_it_accepts() {
        let [a, b, c] = unit();
        let ray = Ray::new(Vec3::new(0.25, 0.5, 2.0), Vec3::NEG_Z);
        let exact = intersect(
            a,
            b,
            c,
            Vec3A::from(ray.origin),
            Vec3A::from(ray.dir),
            0.0,
            f32::INFINITY,
        );
        assert_eq!(exact, Some((2.0, 0.25, 0.5)));
        assert_eq!(refine(a, b, c, &ray), exact);
    }

    #[test]
    fn refine_clamps_an_edge_hit_into_the_triangle_and_interval() {
        let [a, b, c] = unit();
        // Just outside the hypotenuse and just before tnear: another kernel's rounding.
        let ray = Ray::segment(Vec3::new(0.5, 0.5000001, 2.0), Vec3::NEG_Z, 2.0, 5.0);
        let (t, u, v) = refine(a, b, c, &ray).expect("not parallel");
        assert!(u >= 0.0 && v >= 0.0 && u + v <= 1.0 + 1e-6, "{u} {v}");
        assert!((2.0..=5.0).contains(&t), "{t}");
        // Parallel: no answer of its own.
        let parallel = Ray::new(Vec3::new(0.2, 0.2, 1.0), Vec3::X);
        assert_eq!(refine(a, b, c, &parallel), None);
    }
}
