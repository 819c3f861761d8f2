//! Warps from the unit square `[0, 1)²` to directions and points, each with its density:
//! the concentric disk, cosine-weighted and uniform hemispheres, the uniform sphere, and
//! uniform points on triangles (as barycentrics).

use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4, TAU};

/// Shirley-Chiu concentric map of the square onto the unit disk (area preserving up to π).
#[inline]
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, FRAC_PI_4 * (o.y / o.x))
    } else {
        (o.y, FRAC_PI_2 - FRAC_PI_4 * (o.x / o.y))
    };
    r * Vec2::new(theta.cos(), theta.sin())
}

/// A direction about +Z with density cos θ / π (Malley's method).
#[inline]
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = concentric_disk(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// The solid-angle density of [`cosine_hemisphere`] at a direction with cos θ = `cos_theta`.
#[inline]
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * FRAC_1_PI
}

/// A uniformly distributed direction on the unit sphere (density [`UNIFORM_SPHERE_PDF`]):
/// `z = 1 − 2u₀`, `φ = 2π u₁`.
#[inline]
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = TAU * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// The solid-angle density of [`uniform_sphere`], 1/(4π).
pub const UNIFORM_SPHERE_PDF: f32 = 0.25 * FRAC_1_PI;

/// A uniformly distributed direction on the hemisphere about +Z (density
/// [`UNIFORM_HEMISPHERE_PDF`]): `z = u₀`, `φ = 2π u₁`.
#[inline]
pub fn uniform_hemisphere(u: Vec2) -> Vec3 {
    let z = u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = TAU * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// The solid-angle density of [`uniform_hemisphere`], 1/(2π).
pub const UNIFORM_HEMISPHERE_PDF: f32 = 0.5 * FRAC_1_PI;

/// Barycentrics `(b0, b1, b2)` of a point uniformly distributed over a triangle, by the
/// low-distortion square-to-triangle map of Heitz (2019, "A Low-Distortion Map Between
/// Triangle and Square"): the square's diagonal halves fold onto the triangle, so nearby
/// `u` give nearby points (which keeps stratification). The point is `b0·p0 + b1·p1 + b2·p2`;
/// its density per unit area is `1 / area` of the triangle.
#[inline]
pub fn uniform_triangle(u: Vec2) -> Vec3 {
    let (b0, b1) = if u.x < u.y {
        let b0 = 0.5 * u.x;
        (b0, u.y - b0)
    } else {
        let b1 = 0.5 * u.y;
        (u.x - b1, b1)
    };
    Vec3::new(b0, b1, (1.0 - b0 - b1).max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize) -> impl Iterator<Item = Vec2> {
        (0..n * n).map(move |k| {
            Vec2::new(
                ((k % n) as f32 + 0.5) / n as f32,
                ((k / n) as f32 + 0.5) / n as f32,
            )
        })
    }

    #[test]
    fn sphere_and_hemisphere_are_unit_and_balanced() {
        // A stratified grid of u: each octant of the sphere gets 1/8 of the points (±1 row).
        let n = 64;
        let mut octants = [0usize; 8];
        for u in grid(n) {
            let w = uniform_sphere(u);
            assert!((w.length() - 1.0).abs() < 1e-5);
            let h = uniform_hemisphere(u);
            assert!((h.length() - 1.0).abs() < 1e-5 && h.z >= 0.0);
            octants[(w.x > 0.0) as usize + 2 * (w.y > 0.0) as usize + 4 * (w.z > 0.0) as usize] +=
                1;
        }
        for c in octants {
            assert!(
                (c as i64 - (n * n / 8) as i64).abs() <= n as i64,
                "{octants:?}"
            );
        }
        // Mean z of the uniform hemisphere is 1/2; of the cosine hemisphere 2/3.
        let mz = grid(n).map(|u| uniform_hemisphere(u).z).sum::<f32>() / (n * n) as f32;
        assert!((mz - 0.5).abs() < 1e-3, "{mz}");
        let cz = grid(n).map(|u| cosine_hemisphere(u).z).sum::<f32>() / (n * n) as f32;
        assert!((cz - 2.0 / 3.0).abs() < 2e-3, "{cz}");
    }

    #[test]
    fn triangle_map_is_uniform_and_inside() {
        // Uniform over the triangle: the mean barycentric is (1/3, 1/3, 1/3) and the four
        // sub-triangles of the midpoint subdivision each get a quarter.
        let n = 128;
        let mut sum = Vec3::ZERO;
        let mut quarters = [0usize; 4];
        for u in grid(n) {
            let b = uniform_triangle(u);
            assert!(
                b.min_element() >= 0.0 && (b.element_sum() - 1.0).abs() < 1e-6,
                "{b}"
            );
            sum += b;
            let q = if b.x > 0.5 {
                0
            } else if b.y > 0.5 {
                1
            } else if b.z > 0.5 {
                2
            } else {
                3
            };
            quarters[q] += 1;
        }
        let mean = sum / (n * n) as f32;
        assert!(
            (mean - Vec3::splat(1.0 / 3.0)).abs().max_element() < 1e-3,
            "{mean}"
        );
        for q in quarters {
            assert!(
                (q as i64 - (n * n / 4) as i64).abs() <= 2 * n as i64,
                "{quarters:?}"
            );
        }
    }
}
