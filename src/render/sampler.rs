//! Where inside a pixel each sample goes.
//!
//! Deterministic: the position of sample `s` of pixel `(x, y)` depends only on the seed, the
//! pixel and `s`, never on thread scheduling or tile order, so renders are reproducible (the
//! same bytes with 1 thread or many).
//!
//! Three sequences:
//! - [`PixelSampling::Sobol`] (default): Owen-scrambled Sobol points (Burley 2020, crate
//!   `sobol_burley`), each pixel with its own scramble seed. Any prefix of the sequence is
//!   well stratified, so progressive rendering can stop after any number of samples.
//! - [`PixelSampling::Stratified`]: jittered strata; needs the sample count up front.
//! - [`PixelSampling::Independent`]: uniform random points, the baseline a low-discrepancy
//!   sequence is measured against.
//!
//! Dimensions are assigned per use ([`DIM_PIXEL`]); the returned point is uniform in `[0, 1)²`
//! and the pixel filter ([`super::filter`]) turns it into a film position and a weight.

use glam::Vec2;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;

/// How sample positions are chosen inside a pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PixelSampling {
    /// Stratified jitter: the pixel is split into `spp` cells (as square a grid as `spp`
    /// allows) and each sample is uniformly random inside its own cell.
    Stratified,
    /// Every sample at the pixel centre (for closed-form tests; aliased images).
    PixelCenter,
    /// Owen-scrambled Sobol points, scrambled per pixel; progressive (any prefix is good).
    #[default]
    Sobol,
    /// Independent uniform random points (plain Monte Carlo, for comparison).
    Independent,
}

/// Sobol dimensions of the pixel position (x, y). Later uses (lens, light) take the next ones.
pub const DIM_PIXEL: u32 = 0;
// The pixel position is read as the first pair of a 4D set (`sample_4d`).
const _: () = assert!(DIM_PIXEL.is_multiple_of(4));

/// Sobol points per scramble seed: `sobol_burley` indexes at most 2¹⁶ samples, so longer
/// renders move to a fresh, independently scrambled sequence every 2¹⁶ samples.
const SOBOL_BLOCK: u32 = 1 << 16;

impl PixelSampling {
    /// Every sampling mode, for listings and comparisons.
    pub const ALL: [PixelSampling; 4] = [
        PixelSampling::Sobol,
        PixelSampling::Stratified,
        PixelSampling::Independent,
        PixelSampling::PixelCenter,
    ];

    /// The mode's name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            PixelSampling::Stratified => "stratified",
            PixelSampling::PixelCenter => "center",
            PixelSampling::Sobol => "sobol",
            PixelSampling::Independent => "independent",
        }
    }

    /// Whether sample `s` is as good at every prefix length (needed by progressive rendering;
    /// stratified jitter only stratifies the whole count it was built for).
    pub fn progressive(self) -> bool {
        !matches!(self, PixelSampling::Stratified)
    }
}

impl std::fmt::Display for PixelSampling {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for PixelSampling {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| {
                format!("unknown sampler '{s}': use sobol, stratified, independent or center")
            })
    }
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
            PixelSampling::Independent => {
                let mut rng = Pcg32::seed_from_u64(sample_key(self.seed, x, y, sample));
                Vec2::new(rng.random::<f32>(), rng.random::<f32>())
            }
            PixelSampling::Sobol => {
                let block = sample / SOBOL_BLOCK;
                let scramble = pixel_scramble(self.seed, x, y, block);
                let index = sample % SOBOL_BLOCK;
                // DIM_PIXEL is 0: the first two dimensions of the first 4D set.
                let [x, y, _, _] = sobol_burley::sample_4d(index, DIM_PIXEL / 4, scramble);
                Vec2::new(x, y)
            }
        }
    }
}

/// The random numbers one path consumes after its pixel position: light choice, light
/// point, BSDF lobe and direction, Russian roulette, bounce after bounce.
///
/// Each request takes the next *slot* and draws one or two numbers from it. With Sobol
/// sampling every slot is its own 2D Owen-scrambled Sobol sequence, indexed by the sample
/// number and seeded by (pixel, slot): pbrt-v4's and Cycles' "padded" construction. Any slot
/// is a well-stratified (0, 2)-sequence over the pixel's samples, slots are independent of
/// each other, and the dimension count is unlimited (a long path never runs out of Sobol
/// dimensions). The other modes draw independent uniform numbers per slot. Slot 0 is the pixel
/// position ([`PixelSampler::offset`]), so a path's own slots start at 1.
#[derive(Clone, Copy, Debug)]
pub struct SampleStream {
    sobol: bool,
    index: u32,
    /// The pixel's scramble (Sobol) or key (random modes).
    key: u64,
    slot: u32,
}

impl PixelSampler {
    /// The stream of sample `sample` of pixel `(x, y)`.
    #[inline]
    pub fn stream(&self, x: u32, y: u32, sample: u32) -> SampleStream {
        match self.mode {
            PixelSampling::Sobol => SampleStream {
                sobol: true,
                index: sample % SOBOL_BLOCK,
                key: pixel_scramble(self.seed, x, y, sample / SOBOL_BLOCK) as u64,
                slot: 1,
            },
            _ => SampleStream {
                sobol: false,
                index: sample,
                key: sample_key(self.seed, x, y, sample),
                slot: 1,
            },
        }
    }
}

impl SampleStream {
    /// The next two numbers in `[0, 1)²`, stratified together.
    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        let slot = self.slot;
        self.slot = self.slot.wrapping_add(1);
        let h = mix64(self.key ^ (slot as u64).wrapping_mul(0xD1B5_4A32_D192_ED03));
        if self.sobol {
            let seed = (h ^ (h >> 32)) as u32;
            // Dimensions 0 and 1 of the slot's sequence, computed together (the crate's
            // `sample_4d` is bit-identical to `sample` per dimension, one SIMD pass).
            let [x, y, _, _] = sobol_burley::sample_4d(self.index, 0, seed);
            Vec2::new(x, y)
        } else {
            let mut rng = Pcg32::seed_from_u64(h);
            Vec2::new(rng.random::<f32>(), rng.random::<f32>())
        }
    }

    /// The next number in `[0, 1)` (a slot of its own: the first of [`next_2d`]'s pair,
    /// computed alone).
    ///
    /// [`next_2d`]: Self::next_2d
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        let slot = self.slot;
        self.slot = self.slot.wrapping_add(1);
        let h = mix64(self.key ^ (slot as u64).wrapping_mul(0xD1B5_4A32_D192_ED03));
        if self.sobol {
            sobol_burley::sample(self.index, 0, (h ^ (h >> 32)) as u32)
        } else {
            Pcg32::seed_from_u64(h).random::<f32>()
        }
    }
}

/// SplitMix64's finaliser: every input bit affects every output bit.
#[inline]
pub(crate) fn mix64(mut h: u64) -> u64 {
    h = (h ^ (h >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    h = (h ^ (h >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    h ^ (h >> 31)
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

/// The Sobol scramble seed of pixel `(x, y)` (and sample block): a full-avalanche hash of
/// the render seed and the pixel, so neighbouring pixels get unrelated scrambles.
#[inline]
fn pixel_scramble(seed: u64, x: u32, y: u32, block: u32) -> u32 {
    let h = mix64(sample_key(seed, x, y, block));
    (h ^ (h >> 32)) as u32
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
    fn sobol_is_reproducible_in_range_and_differs_by_seed_and_pixel() {
        let a = PixelSampler::new(PixelSampling::Sobol, 1, 7);
        let b = PixelSampler::new(PixelSampling::Sobol, 1, 8);
        for s in [0, 1, 5, SOBOL_BLOCK - 1, SOBOL_BLOCK, 3 * SOBOL_BLOCK + 2] {
            let p = a.offset(2, 9, s);
            assert!(p.cmpge(Vec2::ZERO).all() && p.cmplt(Vec2::ONE).all(), "{p}");
            assert_eq!(p, a.offset(2, 9, s));
        }
        assert_ne!(a.offset(2, 9, 0), b.offset(2, 9, 0));
        assert_ne!(a.offset(2, 9, 0), a.offset(9, 2, 0));
    }

    #[test]
    fn sobol_prefixes_are_stratified() {
        // The first 16 points of a (0, 2)-sequence put exactly one point in each 4×4 cell.
        let sampler = PixelSampler::new(PixelSampling::Sobol, 16, 3);
        let mut cells = [0u8; 16];
        for s in 0..16 {
            let p = sampler.offset(11, 4, s) * 4.0;
            cells[p.y as usize * 4 + p.x as usize] += 1;
        }
        assert_eq!(cells, [1; 16]);
    }

    #[test]
    fn names_round_trip() {
        for mode in PixelSampling::ALL {
            assert_eq!(mode.name().parse::<PixelSampling>(), Ok(mode));
        }
        assert!("halton".parse::<PixelSampling>().is_err());
    }

    #[test]
    fn stream_slots_are_stratified_and_independent() {
        // Each slot's first 16 samples fill a 4×4 grid once (a (0, 2)-sequence), and two
        // slots of the same pixel differ.
        let sampler = PixelSampler::new(PixelSampling::Sobol, 16, 5);
        for slot in 0..4 {
            let mut cells = [0u8; 16];
            for s in 0..16 {
                let mut stream = sampler.stream(7, 3, s);
                for _ in 0..slot {
                    stream.next_2d();
                }
                let p = stream.next_2d() * 4.0;
                cells[p.y as usize * 4 + p.x as usize] += 1;
            }
            assert_eq!(cells, [1; 16], "slot {slot}");
        }
        let mut a = sampler.stream(7, 3, 0);
        assert_ne!(a.next_2d(), a.next_2d());
        let mut b = PixelSampler::new(PixelSampling::Independent, 16, 5).stream(7, 3, 0);
        let (x, y) = (b.next_2d(), b.next_1d());
        assert!(x.cmpge(Vec2::ZERO).all() && x.cmplt(Vec2::ONE).all() && (0.0..1.0).contains(&y));
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
