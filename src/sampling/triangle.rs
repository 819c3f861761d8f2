//! Sampling a triangle: uniformly by area, or uniformly by the solid angle it subtends.
//!
//! # By area
//!
//! For a uniform `u ∈ [0, 1)²`, with `s = √u₀`, the barycentrics
//!
//! ```text
//! b₀ = 1 − s,   b₁ = u₁ s,   b₂ = 1 − b₀ − b₁
//! ```
//!
//! give the point `b₀ p₀ + b₁ p₁ + b₂ p₂` with density `1 / A` over the triangle of area `A`:
//! `s` picks the distance from vertex 0 with density ∝ `s` (the width of the triangle grows
//! linearly with it) and `u₁` a uniform position across it.
//!
//! # By solid angle (Arvo 1995)
//!
//! Seen from a point, the triangle projects to a spherical triangle with unit vertices `A, B,
//! C`, interior angles `α, β, γ` and solid angle `Ω = α + β + γ − π` (computed instead by the
//! Van Oosterom–Strackee formula `tan(Ω/2) = |A·(B×C)| / (1 + A·B + B·C + C·A)`, which does
//! not cancel for small triangles). [`spherical_triangle`] inverts the solid angle as a
//! function of a point `C'` moved along the arc AC: it picks the sub-triangle `ABC'` of area
//! `u₀ Ω`, then a direction on the arc from `B` to `C'` such that the result is uniform over the
//! spherical triangle, with density `1/Ω`.

use glam::{Vec2, Vec3};

/// Barycentrics `[b₀, b₁, b₂]` of a point uniformly distributed by area (see the module doc).
#[inline]
pub fn uniform_triangle(u: Vec2) -> [f32; 3] {
    let s = u.x.max(0.0).sqrt();
    let b0 = 1.0 - s;
    let b1 = u.y * s;
    [b0, b1, (1.0 - b0 - b1).max(0.0)]
}

/// The point with barycentrics `b` on the triangle `p`.
#[inline]
pub fn triangle_point(p: [Vec3; 3], b: [f32; 3]) -> Vec3 {
    b[0] * p[0] + b[1] * p[1] + b[2] * p[2]
}

/// The solid angle subtended by the triangle with unit vertex directions `a, b, c`.
#[inline]
pub fn spherical_triangle_area(a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let numerator = a.dot(b.cross(c)).abs();
    let denominator = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
    2.0 * numerator.atan2(denominator)
}

/// A unit direction uniformly distributed over the spherical triangle with unit vertices
/// `a, b, c` (density `1 / Ω` per solid angle, see the module doc), or `None` for a degenerate
/// triangle.
pub fn spherical_triangle(a: Vec3, b: Vec3, c: Vec3, u: Vec2) -> Option<Vec3> {
    // Unit normals of the great circles through each side.
    let n_ab = a.cross(b).try_normalize()?;
    let n_bc = b.cross(c).try_normalize()?;
    let n_ca = c.cross(a).try_normalize()?;
    // Interior angles: between the planes of the two sides meeting at each vertex.
    let alpha = (-n_ab.dot(n_ca)).clamp(-1.0, 1.0).acos();
    let beta = (-n_bc.dot(n_ab)).clamp(-1.0, 1.0).acos();
    let gamma = (-n_ca.dot(n_bc)).clamp(-1.0, 1.0).acos();
    let area = alpha + beta + gamma - std::f32::consts::PI;
    if area.is_nan() || area <= 0.0 {
        return None;
    }
    // The sub-triangle A B C' with area u₀ Ω fixes C' on the arc AC.
    let area_sub = u.x * area;
    let (s, t) = (area_sub - alpha).sin_cos();
    let (sin_a, cos_a) = alpha.sin_cos();
    let cos_c = a.dot(b);
    let uu = t - cos_a;
    let vv = s + sin_a * cos_c;
    let denom = (vv * s + uu * t) * sin_a;
    let q = if denom != 0.0 {
        (((vv * t - uu * s) * cos_a - vv) / denom).clamp(-1.0, 1.0)
    } else {
        1.0
    };
    let c_perp = (c - c.dot(a) * a).try_normalize()?;
    let c_sub = q * a + (1.0 - q * q).max(0.0).sqrt() * c_perp;
    // Then a point on the arc from B toward C', cos θ uniform between 1 and B·C'.
    let z = 1.0 - u.y * (1.0 - c_sub.dot(b));
    let w_perp = (c_sub - c_sub.dot(b) * b).try_normalize()?;
    Some((z * b + (1.0 - z * z).max(0.0).sqrt() * w_perp).normalize())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_pcg::Pcg64;

    #[test]
    fn spherical_samples_are_uniform_over_the_solid_angle() {
        // The octant triangle X, Y, Z subtends π/2. Uniform over it: the fraction of samples
        // with x > 0.5 is the solid angle of that cap within the octant over π/2. The cap
        // {x > ½} on the sphere has solid angle 2π(1 − ½) = π; a quarter of it (y, z > 0) is
        // in the octant: π/4, so the fraction is ½. n = 200 000: σ = √(n/4) ≈ 224; 6σ.
        let (a, b, c) = (Vec3::X, Vec3::Y, Vec3::Z);
        assert!((spherical_triangle_area(a, b, c) - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
        let mut rng = Pcg64::seed_from_u64(8);
        let n = 200_000;
        let mut cap = 0;
        for _ in 0..n {
            let w = spherical_triangle(a, b, c, Vec2::new(rng.random(), rng.random())).unwrap();
            assert!((w.length() - 1.0).abs() < 1e-5);
            assert!(w.min_element() >= -1e-5, "outside the octant: {w}");
            if w.x > 0.5 {
                cap += 1;
            }
        }
        assert!((cap as f64 - n as f64 / 2.0).abs() < 6.0 * 224.0, "{cap}");
    }

    #[test]
    fn barycentrics_are_uniform_by_area() {
        // Split the triangle into its 4 midpoint sub-triangles (equal area): each must get a
        // quarter of the samples. With n = 400 000, one count's standard deviation is
        // √(n · 3/16) ≈ 274; 6σ bounds it.
        let mut rng = Pcg64::seed_from_u64(7);
        let n = 400_000;
        let mut counts = [0u32; 4];
        for _ in 0..n {
            let b = uniform_triangle(Vec2::new(rng.random(), rng.random()));
            assert!(b.iter().all(|&x| (0.0..=1.0).contains(&x)));
            assert!((b.iter().sum::<f32>() - 1.0).abs() < 1e-6);
            let k = b.iter().position(|&x| x > 0.5).unwrap_or(3);
            counts[k] += 1;
        }
        for c in counts {
            assert!(
                (c as f64 - n as f64 / 4.0).abs() < 6.0 * 274.0,
                "{counts:?}"
            );
        }
    }
}
