//! The hit point of a triangle and a conservative bound on its floating-point error.

use super::float::gamma;
use glam::Vec3;

/// Reconstructs the point with barycentric coordinates `(b1, b2)` (weights of `p1` and `p2`)
/// as `b0·p0 + b1·p1 + b2·p2`, and returns it with a per-axis bound on its absolute error,
/// `γ(7)·(|b0·p0| + |b1·p1| + |b2·p2|)` (pbrt-v4's triangle interaction).
///
/// Reconstructing from barycentrics rather than evaluating `o + t·d` keeps the point's error
/// proportional to the triangle's coordinates instead of to the ray's length, so it stays
/// small for distant cameras, and the bound makes the later origin offset exact enough.
#[inline]
pub fn triangle_point(p0: Vec3, p1: Vec3, p2: Vec3, b1: f32, b2: f32) -> (Vec3, Vec3) {
    let b0 = 1.0 - b1 - b2;
    let (w0, w1, w2) = (b0 * p0, b1 * p1, b2 * p2);
    let point = w0 + w1 + w2;
    let error = gamma(7) * (w0.abs() + w1.abs() + w2.abs());
    (point, error)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The true point (computed in f64) lies inside the box the bound describes.
    #[test]
    fn bound_contains_the_exact_point() {
        let p0 = Vec3::new(1.0e5 + 0.1, -3.7, 2.2e-3);
        let p1 = Vec3::new(-2.5, 1.0e5 + 0.3, 7.0);
        let p2 = Vec3::new(0.33, 0.77, -1.0e5);
        for (b1, b2) in [(0.1f32, 0.2f32), (0.333, 0.333), (0.9, 0.05), (1e-6, 1e-6)] {
            let (p, err) = triangle_point(p0, p1, p2, b1, b2);
            let b0 = 1.0 - b1 - b2;
            for axis in 0..3 {
                let exact = b0 as f64 * p0[axis] as f64
                    + b1 as f64 * p1[axis] as f64
                    + b2 as f64 * p2[axis] as f64;
                assert!(
                    (p[axis] as f64 - exact).abs() <= err[axis] as f64,
                    "axis {axis}: {} vs {exact}, bound {}",
                    p[axis],
                    err[axis]
                );
            }
        }
    }
}
