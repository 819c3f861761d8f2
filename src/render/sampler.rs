//! Where inside a pixel each sample goes.
//!
//! Deterministic: the position of sample `s` of pixel `(x, y)` depends only on the seed, the
//! pixel and `s`, never on thread scheduling or tile order, so renders are reproducible. The
//! sampler sits behind this small type so that a later low-discrepancy sequence (Sobol) can
//! replace it without touching the integrator.

use glam::Vec2;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;

/// How sample positions are chosen inside a pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PixelSampling {
    /// Stratified jitter: the pixel is split into `spp` cells (as square a grid as `spp`
    /// allows) and each sample is uniformly random inside its own cell.
    #[default]
    Stratified,
    /// Every sample at the pixel centre (for closed-form tests; aliased images).
    PixelCenter,
}

/// Sample positions for one render.
#[derive(Clone, Copy, Debug)]
pub struct PixelSampler {
    mode: PixelSampling,
    seed: u64,
    /// Strata along x and y, `columns × rows = spp`.
    columns: u32,
    rows: u32,
}

impl PixelSampler {
    /// A sampler for `spp` samples per pixel (at least 1).
    pub fn new(mode: PixelSampling, spp: u32, seed: u64) -> Self {
        let spp = spp.max(1);
        // The largest divisor of spp not above √spp gives the squarest grid.
        let mut rows = (spp as f64).sqrt() as u32;
        while rows > 1 && !spp.is_multiple_of(rows) {
            rows -= 1;
        }
        let rows = rows.max(1);
        Self {
            mode,
            seed,
            columns: spp / rows,
            rows,
        }
    }

    /// The strata grid as (columns, rows).
    pub fn strata(&self) -> (u32, u32) {
        (self.columns, self.rows)
    }

    /// Position of sample `sample` inside pixel `(x, y)`, in `[0, 1)²` from the pixel's
    /// top-left corner.
    #[inline]
    pub fn offset(&self, x: u32, y: u32, sample: u32) -> Vec2 {
        match self.mode {
            PixelSampling::PixelCenter => Vec2::splat(0.5),
            PixelSampling::Stratified => {
                let mut rng = Pcg32::seed_from_u64(sample_key(self.seed, x, y, sample));
                let cell = sample % (self.columns * self.rows);
                let (cx, cy) = (cell % self.columns, cell / self.columns);
                let jitter = Vec2::new(rng.random::<f32>(), rng.random::<f32>());
                let p = (Vec2::new(cx as f32, cy as f32) + jitter)
                    / Vec2::new(self.columns as f32, self.rows as f32);
                // Rounding in the division can reach exactly 1.0; keep the sample in its pixel.
                p.min(Vec2::splat(1.0 - f32::EPSILON / 2.0))
            }
        }
    }
}

/// One 64-bit key per (seed, pixel, sample). Pcg32's seeding hashes the key further, so it only
/// needs to be distinct: pixel coordinates and sample index go to separate bit ranges (x in
/// 20 bits, y in 20, sample in 24) before the seed is mixed in with an odd multiplier.
#[inline]
fn sample_key(seed: u64, x: u32, y: u32, sample: u32) -> u64 {
    const GOLDEN: u64 = 0x9E37_79B9_7F4A_7C15;
    let pixel_sample =
        ((x as u64 & 0xF_FFFF) << 44) | ((y as u64 & 0xF_FFFF) << 24) | (sample as u64 & 0xFF_FFFF);
    pixel_sample ^ seed.wrapping_mul(GOLDEN).rotate_left(17)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_sample_stays_in_its_stratum_and_is_reproducible() {
        let sampler = PixelSampler::new(PixelSampling::Stratified, 8, 42);
        assert_eq!(sampler.strata(), (4, 2));
        for s in 0..8 {
            let p = sampler.offset(3, 5, s);
            let (cx, cy) = (s % 4, s / 4);
            assert!(p.x >= cx as f32 / 4.0 && p.x < (cx + 1) as f32 / 4.0, "{p}");
            assert!(p.y >= cy as f32 / 2.0 && p.y < (cy + 1) as f32 / 2.0, "{p}");
            assert_eq!(p, sampler.offset(3, 5, s));
        }
        let other_seed = PixelSampler::new(PixelSampling::Stratified, 8, 43);
        assert_ne!(sampler.offset(3, 5, 0), other_seed.offset(3, 5, 0));
        assert_ne!(sampler.offset(3, 5, 0), sampler.offset(5, 3, 0));
    }

    #[test]
    fn pixel_centre_mode() {
        let sampler = PixelSampler::new(PixelSampling::PixelCenter, 4, 0);
        assert_eq!(sampler.offset(0, 0, 3), Vec2::splat(0.5));
    }

    #[test]
    fn prime_counts_fall_back_to_strips() {
        assert_eq!(
            PixelSampler::new(PixelSampling::Stratified, 7, 0).strata(),
            (7, 1)
        );
        assert_eq!(
            PixelSampler::new(PixelSampling::Stratified, 16, 0).strata(),
            (4, 4)
        );
        assert_eq!(
            PixelSampler::new(PixelSampling::Stratified, 0, 0).strata(),
            (1, 1)
        );
    }
}
