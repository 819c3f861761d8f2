//! Uniform sampling of a triangle by area.
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

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_pcg::Pcg64;

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
