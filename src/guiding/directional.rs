//! The directional half of the guide: a histogram of incident radiance over the sphere of
//! world directions, on the cylindrical equal-area map `(u, v) = (φ / 2π, (cos θ + 1) / 2)`
//! (Müller et al. 2017 use the same map for their quadtrees). The map has a constant
//! Jacobian, `dω = 4π du dv`, so a histogram bin is a fixed solid angle of `4π / BINS` and
//! the density of a direction is the density of its map point divided by 4π.
//!
//! [`Directional::from_weights`] turns per-bin sums of `L / p` (incident radiance over the
//! density of the sample that measured it, which estimates `∫ L dω` over the bin) into a
//! piecewise-constant distribution; [`Directional::sample`] draws a direction from it and
//! [`Directional::pdf`] is the solid-angle density of that draw.

use crate::sampling::distribution::Distribution2D;
use glam::{Vec2, Vec3};
use std::f32::consts::{PI, TAU};

/// Bins along φ.
pub const PHI_BINS: usize = 64;
/// Bins along cos θ.
pub const Z_BINS: usize = 32;
/// Bins of one histogram: each covers `4π / BINS` sr (about 3.6° × 5.6° at the equator).
pub const BINS: usize = PHI_BINS * Z_BINS;

/// The map point `(φ / 2π, (z + 1) / 2)` of a unit direction (world `z` is the map's pole).
#[inline]
pub fn to_map(dir: Vec3) -> Vec2 {
    let phi = dir.y.atan2(dir.x);
    let phi = if phi < 0.0 { phi + TAU } else { phi };
    Vec2::new(
        (phi / TAU).clamp(0.0, ONE_BELOW),
        ((dir.z + 1.0) * 0.5).clamp(0.0, ONE_BELOW),
    )
}

/// The unit direction of map point `uv`.
#[inline]
pub fn from_map(uv: Vec2) -> Vec3 {
    let z = (2.0 * uv.y - 1.0).clamp(-1.0, 1.0);
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (s, c) = (TAU * uv.x).sin_cos();
    Vec3::new(r * c, r * s, z)
}

/// The largest `f32` below 1, so map coordinates stay inside the unit square.
const ONE_BELOW: f32 = 1.0 - f32::EPSILON / 2.0;

/// The histogram bin (row-major, φ fastest) of a unit direction.
#[inline]
pub fn bin_of(dir: Vec3) -> usize {
    let uv = to_map(dir);
    let col = ((uv.x * PHI_BINS as f32) as usize).min(PHI_BINS - 1);
    let row = ((uv.y * Z_BINS as f32) as usize).min(Z_BINS - 1);
    row * PHI_BINS + col
}

/// A piecewise-constant density over directions, one value per bin.
#[derive(Clone, Debug)]
pub struct Directional {
    map: Distribution2D,
}

impl Directional {
    /// The distribution proportional to `weights` (one per bin, [`BINS`] of them), or `None`
    /// when there is no positive weight or the length is wrong.
    pub fn from_weights(weights: &[f32]) -> Option<Self> {
        if weights.len() != BINS {
            return None;
        }
        Distribution2D::new(weights, PHI_BINS, Z_BINS).map(|map| Self { map })
    }

    /// Draws a unit direction from two uniforms in `[0, 1)`: `(direction, solid-angle
    /// density)`; the density is 0 only when rounding left the drawn bin (never in practice).
    #[inline]
    pub fn sample(&self, u: Vec2) -> (Vec3, f32) {
        let (uv, pdf_uv) = self.map.sample(u);
        (from_map(uv), pdf_uv / (4.0 * PI))
    }

    /// The solid-angle density with which [`Directional::sample`] draws the unit direction
    /// `dir`.
    #[inline]
    pub fn pdf(&self, dir: Vec3) -> f32 {
        self.map.pdf(to_map(dir)) / (4.0 * PI)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_map_round_trips_and_bins_agree() {
        for i in 0..500 {
            let uv = Vec2::new(
                (i as f32 * 0.618_034).fract(),
                (i as f32 * 0.414_213).fract(),
            );
            let d = from_map(uv);
            assert!((d.length() - 1.0).abs() < 1e-5);
            let back = to_map(d);
            // φ wraps at the seam; compare on the circle.
            let du = (back.x - uv.x).abs();
            assert!(
                du.min(1.0 - du) < 1e-4 && (back.y - uv.y).abs() < 1e-4,
                "{uv} {back}"
            );
        }
    }
}
