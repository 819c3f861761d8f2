//! Ray differentials (Igehy 1999, as in pbrt): each camera ray carries its two neighbours, the
//! rays through the film positions one pixel spacing to the right (x) and below (y). Where the
//! main ray hits a surface the neighbours are intersected with the hit's tangent plane, which
//! gives the surface point's derivatives ∂p/∂x and ∂p/∂y; from those, the barycentric
//! derivatives, and from those the derivative of any vertex attribute (texture coordinates,
//! normals, colours). Mirror reflections carry the neighbours on with the reflection law's
//! first-order terms, including the curvature of interpolated shading normals.
//!
//! The spacing is one pixel divided by √spp (a pixel's samples share it, so each covers
//! 1/spp of its area). At grazing angles a neighbour can run parallel to the tangent plane or
//! away from it; the footprint is then unbounded, and it is clamped to
//! [`MAX_FOOTPRINT`] scene units, which every filter reads as "the whole texture". Nothing here
//! returns NaN or infinity.

use glam::{Vec2, Vec3};

/// Longest ∂p/∂x or ∂p/∂y, in scene units: a grazing or escaping neighbour ray's footprint.
pub const MAX_FOOTPRINT: f32 = 1e8;

/// A ray's two neighbours.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayDifferential {
    /// Origin of the ray one spacing to the right on the film.
    pub rx_origin: Vec3,
    /// Its direction.
    pub rx_dir: Vec3,
    /// Origin of the ray one spacing down on the film.
    pub ry_origin: Vec3,
    /// Its direction.
    pub ry_dir: Vec3,
}

impl RayDifferential {
    /// Whether every component is finite.
    pub fn is_finite(&self) -> bool {
        self.rx_origin.is_finite()
            && self.rx_dir.is_finite()
            && self.ry_origin.is_finite()
            && self.ry_dir.is_finite()
    }
}

/// ∂p/∂x and ∂p/∂y at a surface point, in scene units per film spacing.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceDifferentials {
    /// ∂p/∂x.
    pub dp_dx: Vec3,
    /// ∂p/∂y.
    pub dp_dy: Vec3,
}

/// Intersects the neighbours of `rd` with the plane through `p` with normal `n`: the
/// surface's ∂p/∂x and ∂p/∂y, each finite and at most [`MAX_FOOTPRINT`] long.
pub fn at_surface(rd: &RayDifferential, p: Vec3, n: Vec3) -> SurfaceDifferentials {
    SurfaceDifferentials {
        dp_dx: plane_offset(rd.rx_origin, rd.rx_dir, p, n),
        dp_dy: plane_offset(rd.ry_origin, rd.ry_dir, p, n),
    }
}

/// Where the ray `(o, d)` meets the plane `(p, n)`, relative to `p`, clamped.
fn plane_offset(o: Vec3, d: Vec3, p: Vec3, n: Vec3) -> Vec3 {
    let t = n.dot(p - o) / n.dot(d);
    let offset = o + d * t - p;
    let length = offset.length();
    if t >= 0.0 && length.is_finite() && length <= MAX_FOOTPRINT {
        return offset;
    }
    // Parallel to the plane, or meeting it behind its origin: the footprint is unbounded
    // along the neighbour's direction projected onto the plane.
    let along = (d - n * n.dot(d)).normalize_or_zero();
    let along = if along == Vec3::ZERO || !along.is_finite() {
        n.normalize_or_zero().any_orthonormal_vector()
    } else {
        along
    };
    if along.is_finite() {
        along * MAX_FOOTPRINT
    } else {
        Vec3::X * MAX_FOOTPRINT
    }
}

/// The derivatives `(∂b₁, ∂b₂)` of the barycentric weights of vertices 1 and 2 for a
/// displacement `dp` in the plane of the triangle `positions` (least squares, so a `dp` off
/// the plane uses its projection). Zero for a degenerate triangle.
pub fn barycentric_derivatives(positions: [Vec3; 3], dp: Vec3) -> Vec2 {
    let e1 = positions[1] - positions[0];
    let e2 = positions[2] - positions[0];
    let (a11, a12, a22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = a11 * a22 - a12 * a12;
    let (r1, r2) = (e1.dot(dp), e2.dot(dp));
    let db = Vec2::new(a22 * r1 - a12 * r2, a11 * r2 - a12 * r1) / det;
    if det > 0.0 && db.is_finite() {
        db
    } else {
        Vec2::ZERO
    }
}

/// The derivative of a per-vertex attribute for barycentric derivatives `db` (from
/// [`barycentric_derivatives`]); `None` if an index is out of range for `values`.
#[inline]
pub fn attribute_derivative<T>(values: &[T], vertices: [u32; 3], db: Vec2) -> Option<T>
where
    T: Copy
        + std::ops::Sub<Output = T>
        + std::ops::Mul<f32, Output = T>
        + std::ops::Add<Output = T>,
{
    let [a0, a1, a2] = [
        *values.get(vertices[0] as usize)?,
        *values.get(vertices[1] as usize)?,
        *values.get(vertices[2] as usize)?,
    ];
    Some((a1 - a0) * db.x + (a2 - a0) * db.y)
}

/// The derivative of the unit shading normal `n / |n|` given the unnormalised interpolated
/// normal `n` and its derivative `dn`; zero when `n` vanishes.
pub fn unit_normal_derivative(n: Vec3, dn: Vec3) -> Vec3 {
    let length = n.length();
    if length.is_nan() || length <= 0.0 {
        return Vec3::ZERO;
    }
    let unit = n / length;
    let d = (dn - unit * unit.dot(dn)) / length;
    if d.is_finite() { d } else { Vec3::ZERO }
}

/// What a mirror reflection needs to carry differentials on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MirrorHit {
    /// The hit point.
    pub p: Vec3,
    /// Unit direction back along the incoming ray.
    pub wo: Vec3,
    /// Unit shading normal on `wo`'s side.
    pub ns: Vec3,
    /// ∂ns/∂x and ∂ns/∂y (zero for flat shading).
    pub dn_dx: Vec3,
    /// ∂ns/∂y.
    pub dn_dy: Vec3,
    /// The reflected direction `2(wo·ns)ns − wo`.
    pub wi: Vec3,
}

/// The reflected ray's differential (pbrt's specular-reflection transfer): origins move by
/// ∂p/∂x, ∂p/∂y; directions turn by the change of `wo` and of the normal. Non-finite results
/// (from a clamped footprint) become parallel neighbours [`MAX_FOOTPRINT`] away, which the
/// next hit reads as an unbounded footprint.
pub fn reflect(
    rd: &RayDifferential,
    hit: &MirrorHit,
    dp: &SurfaceDifferentials,
) -> RayDifferential {
    let one = |r_dir: Vec3, dp: Vec3, dn: Vec3| {
        let dwo = -r_dir - hit.wo;
        let d_dn = dwo.dot(hit.ns) + hit.wo.dot(dn);
        let dir = hit.wi - dwo + 2.0 * (hit.wo.dot(hit.ns) * dn + d_dn * hit.ns);
        (hit.p + dp, dir)
    };
    let (rx_origin, rx_dir) = one(rd.rx_dir, dp.dp_dx, hit.dn_dx);
    let (ry_origin, ry_dir) = one(rd.ry_dir, dp.dp_dy, hit.dn_dy);
    let out = RayDifferential {
        rx_origin,
        rx_dir,
        ry_origin,
        ry_dir,
    };
    if out.is_finite() {
        out
    } else {
        let t = hit.ns.any_orthonormal_vector();
        let b = hit.ns.cross(t);
        RayDifferential {
            rx_origin: hit.p + t * MAX_FOOTPRINT,
            rx_dir: hit.wi,
            ry_origin: hit.p + b * MAX_FOOTPRINT,
            ry_dir: hit.wi,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn barycentric_derivatives_invert_the_edges() {
        let tri = [
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 4.0),
        ];
        let db = barycentric_derivatives(tri, Vec3::new(1.0, 0.0, 1.0));
        assert!((db - Vec2::new(0.5, 0.25)).abs().max_element() < 1e-6);
        let flat = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
        assert_eq!(barycentric_derivatives(flat, Vec3::Y), Vec2::ZERO);
    }

    #[test]
    fn flat_mirror_keeps_a_parallel_beam_parallel() {
        // Two parallel rays hit a flat mirror: the reflected neighbours stay parallel.
        let rd = RayDifferential {
            rx_origin: Vec3::new(0.1, 1.0, 0.0),
            rx_dir: Vec3::new(1.0, -1.0, 0.0).normalize(),
            ry_origin: Vec3::new(0.0, 1.0, 0.1),
            ry_dir: Vec3::new(1.0, -1.0, 0.0).normalize(),
        };
        let p = Vec3::new(1.0, 0.0, 0.0);
        let n = Vec3::Y;
        let dp = at_surface(&rd, p, n);
        let wo = Vec3::new(-1.0, 1.0, 0.0).normalize();
        let hit = MirrorHit {
            p,
            wo,
            ns: n,
            dn_dx: Vec3::ZERO,
            dn_dy: Vec3::ZERO,
            wi: Vec3::new(1.0, 1.0, 0.0).normalize(),
        };
        let out = reflect(&rd, &hit, &dp);
        assert!((out.rx_dir - hit.wi).length() < 1e-6 && (out.ry_dir - hit.wi).length() < 1e-6);
        assert!((out.rx_origin - (p + Vec3::new(0.1, 0.0, 0.0))).length() < 1e-6);
    }
}
