//! Discrete and piecewise-constant distributions, for choosing lights by power and environment
//! texels by radiance.
//!
//! [`Distribution1D`] turns `n` non-negative weights `f_i` into the piecewise-constant density
//! on `[0, 1)`
//!
//! ```text
//! p(x) = f_⌊n x⌋ / I,   I = (1/n) Σ_i f_i   (the integral of the step function)
//! ```
//!
//! and, read as a discrete distribution, the probabilities `P(i) = f_i / Σ_j f_j`. Both are
//! sampled by inverting the cumulative distribution, which is accumulated in `f64` so that a
//! million tiny weights do not lose their tail, then stored as `f32`.
//!
//! [`Distribution2D`] is the product of a marginal over rows and one conditional per row,
//! giving the density `p(u, v) = f(u, v) / I` over the unit square for a piecewise-constant
//! `f` on an `nu × nv` grid (`I` is its integral over the square).
//!
//! Weights that are negative or not finite are treated as zero. All-zero (or empty) weights
//! have no distribution: the constructors return `None`, so a caller cannot sample from
//! nothing and must handle "no light" explicitly.

use glam::Vec2;

/// The largest `f32` below 1: remapped uniforms are clamped to it so they stay in `[0, 1)`.
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// A piecewise-constant distribution over `[0, 1)` with `n` equal bins, which is also a
/// discrete distribution over the bin indices.
#[derive(Clone, Debug)]
pub struct Distribution1D {
    /// The weights, sanitised (negative and non-finite weights are 0).
    func: Vec<f32>,
    /// `cdf[i] = Σ_{j<i} f_j / Σ_j f_j`; `n + 1` entries, `cdf[0] = 0`, `cdf[n] = 1`.
    cdf: Vec<f32>,
    /// `Σ_i f_i`.
    sum: f32,
    /// A guide table (Chen and Asau's cutpoints): `guide[k]` is the number of `cdf[1..]`
    /// entries at or below `k / n`, so a search for `u` only looks between the cutpoints
    /// around it instead of over every bin.
    guide: Vec<u32>,
}

impl Distribution1D {
    /// The distribution proportional to `weights`, or `None` when there is no positive weight
    /// (empty or all zero): there is nothing to sample.
    pub fn new(weights: &[f32]) -> Option<Self> {
        let func: Vec<f32> = weights
            .iter()
            .map(|&w| if w.is_finite() && w > 0.0 { w } else { 0.0 })
            .collect();
        let total: f64 = func.iter().map(|&w| f64::from(w)).sum();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let mut cdf = Vec::with_capacity(func.len() + 1);
        cdf.push(0.0);
        let mut acc = 0.0f64;
        for &w in &func {
            acc += f64::from(w);
            // Dividing the running sum by the same total it ends at makes the last positive
            // bin end exactly at 1.0, so zero bins at the end keep zero width.
            cdf.push((acc / total) as f32);
        }
        // Bins beyond u32 indices are not sampled anywhere (images and light lists are far
        // smaller); the guide then stays empty and `find` searches the whole table.
        let n = func.len();
        let guide = if u32::try_from(n).is_ok() {
            let mut guide = Vec::with_capacity(n);
            let mut i = 0usize;
            for k in 0..n {
                let v = k as f32 / n as f32;
                while i < n && cdf[i + 1] <= v {
                    i += 1;
                }
                // Fits: i ≤ n, checked above.
                guide.push(i as u32);
            }
            guide
        } else {
            Vec::new()
        };
        Some(Self {
            func,
            cdf,
            sum: total as f32,
            guide,
        })
    }

    /// Number of bins.
    pub fn len(&self) -> usize {
        self.func.len()
    }

    /// Whether there are no bins (never true for a constructed distribution).
    pub fn is_empty(&self) -> bool {
        self.func.is_empty()
    }

    /// The integral of the step function over `[0, 1)`: `(1/n) Σ f_i`.
    pub fn integral(&self) -> f32 {
        self.sum / self.func.len() as f32
    }

    /// `Σ f_i`, the normaliser of the discrete probabilities.
    pub fn sum(&self) -> f32 {
        self.sum
    }

    /// The (sanitised) weight of bin `index`, 0 outside.
    pub fn weight(&self, index: usize) -> f32 {
        self.func.get(index).copied().unwrap_or(0.0)
    }

    /// The bin holding `u`: `cdf[i] <= u < cdf[i+1]`, which is never a zero-weight bin.
    #[inline]
    fn find(&self, u: f32) -> usize {
        // Number of cdf[1..] entries <= u; a bin of zero width is skipped because its end
        // equals its start. The guide narrows the search to the entries between the cutpoints
        // (k − 1)/n ≤ u and (k + 2)/n ≥ u (a bucket of margin on each side absorbs the
        // rounding of k = ⌊u·n⌋); the count is the same as over the whole table.
        let n = self.func.len();
        let g = self.guide.len();
        let (lo, hi) = if g == n && (0.0..1.0).contains(&u) {
            let k = (u * n as f32) as usize;
            let lo = self.guide[k.saturating_sub(1).min(g - 1)] as usize;
            let hi = if k + 2 < g {
                self.guide[k + 2] as usize
            } else {
                n
            };
            (lo, hi.max(lo))
        } else {
            (0, n)
        };
        let i = lo + self.cdf[1 + lo..1 + hi].partition_point(|&c| c <= u);
        i.min(n - 1)
    }

    /// Samples `x ∈ [0, 1)` with density [`pdf`](Self::pdf): returns `(x, p(x), bin index)`.
    /// `u` is a uniform sample in `[0, 1)`.
    #[inline]
    pub fn sample_continuous(&self, u: f32) -> (f32, f32, usize) {
        let i = self.find(u);
        let (c0, c1) = (self.cdf[i], self.cdf[i + 1]);
        let du = if c1 > c0 { (u - c0) / (c1 - c0) } else { 0.0 };
        let n = self.func.len() as f32;
        let mut x = ((i as f32 + du.clamp(0.0, 1.0)) / n).min(ONE_MINUS_EPSILON);
        // Rounding can put x on the next bin's edge (or just below its own): step it back by
        // ulps into bin i, so that `pdf(x)` is the density this sample was drawn with.
        for _ in 0..8 {
            let bin = (x * n) as usize;
            if bin > i {
                x = f32::from_bits(x.to_bits() - 1);
            } else if bin < i {
                x = f32::from_bits(x.to_bits() + 1);
            } else {
                break;
            }
        }
        (x, self.func[i] / self.integral(), i)
    }

    /// Samples a bin index with probability [`pmf`](Self::pmf): returns `(index, P(index),
    /// u_remapped)`, where `u_remapped` is the position of `u` inside the chosen bin's CDF
    /// interval, again uniform in `[0, 1)` and independent of the choice, so one random
    /// number can choose a light and then sample it.
    #[inline]
    pub fn sample_discrete(&self, u: f32) -> (usize, f32, f32) {
        let i = self.find(u);
        let (c0, c1) = (self.cdf[i], self.cdf[i + 1]);
        let du = if c1 > c0 { (u - c0) / (c1 - c0) } else { 0.0 };
        (i, self.func[i] / self.sum, du.clamp(0.0, ONE_MINUS_EPSILON))
    }

    /// The density at `x ∈ [0, 1)` (0 outside).
    #[inline]
    pub fn pdf(&self, x: f32) -> f32 {
        if !(0.0..1.0).contains(&x) {
            return 0.0;
        }
        let i = ((x * self.func.len() as f32) as usize).min(self.func.len() - 1);
        self.func[i] / self.integral()
    }

    /// The probability of bin `index` (0 outside).
    #[inline]
    pub fn pmf(&self, index: usize) -> f32 {
        self.weight(index) / self.sum
    }
}

/// A piecewise-constant distribution over the unit square on an `nu × nv` grid: a marginal
/// over the rows (v) and one conditional over the columns (u) of each row.
#[derive(Clone, Debug)]
pub struct Distribution2D {
    /// Per row, the conditional over u; `None` for a row of zeros (never chosen).
    conditional: Vec<Option<Distribution1D>>,
    /// Over the rows, weighted by each row's integral.
    marginal: Distribution1D,
    nu: usize,
}

impl Distribution2D {
    /// The distribution proportional to `weights`, `nv` rows of `nu` values each (row-major,
    /// row 0 at v = 0). `None` when there is no positive weight or the length is not
    /// `nu × nv` (with both non-zero).
    pub fn new(weights: &[f32], nu: usize, nv: usize) -> Option<Self> {
        if nu == 0 || nv == 0 || nu.checked_mul(nv) != Some(weights.len()) {
            return None;
        }
        let conditional: Vec<Option<Distribution1D>> =
            weights.chunks_exact(nu).map(Distribution1D::new).collect();
        let row_integrals: Vec<f32> = conditional
            .iter()
            .map(|row| row.as_ref().map_or(0.0, Distribution1D::integral))
            .collect();
        let marginal = Distribution1D::new(&row_integrals)?;
        Some(Self {
            conditional,
            marginal,
            nu,
        })
    }

    /// Grid size `(nu, nv)`.
    pub fn size(&self) -> (usize, usize) {
        (self.nu, self.conditional.len())
    }

    /// The integral of the step function over the unit square.
    pub fn integral(&self) -> f32 {
        self.marginal.integral()
    }

    /// Samples a point of the unit square: `(uv, p(uv))`, the density with respect to area on
    /// the square. `u` is uniform in `[0, 1)²`; `u.y` chooses the row, `u.x` the column.
    #[inline]
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (v, pdf_v, row) = self.marginal.sample_continuous(u.y);
        match &self.conditional[row] {
            Some(cond) => {
                let (x, pdf_u, _) = cond.sample_continuous(u.x);
                (Vec2::new(x, v), pdf_u * pdf_v)
            }
            // Unreachable: the marginal never picks a zero row. Answer with zero density
            // rather than panic, which a caller reads as "no sample".
            None => (Vec2::new(u.x, v), 0.0),
        }
    }

    /// The density at `uv` (0 outside the unit square).
    #[inline]
    pub fn pdf(&self, uv: Vec2) -> f32 {
        if !(0.0..1.0).contains(&uv.x) || !(0.0..1.0).contains(&uv.y) {
            return 0.0;
        }
        let nv = self.conditional.len();
        let row = ((uv.y * nv as f32) as usize).min(nv - 1);
        let col = ((uv.x * self.nu as f32) as usize).min(self.nu - 1);
        match &self.conditional[row] {
            Some(cond) => cond.weight(col) / self.marginal.integral(),
            None => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {

    /// The guided search finds the bin a search over the whole table finds, for peaked
    /// distributions, zero-weight runs and every kind of `u` (bucket edges included).
    #[test]
    fn guided_search_finds_what_a_full_search_finds() {
        let mut weights = vec![1e-6f32; 1000];
        weights[10] = 5000.0;
        weights[500..600].iter_mut().for_each(|w| *w = 0.0);
        weights[999] = 0.0;
        weights[700] = 300.0;
        for w in [weights, vec![1.0; 7], vec![0.0, 0.0, 3.0, 0.0, 1.0, 0.0]] {
            let d = Distribution1D::new(&w).unwrap();
            let n = d.len();
            let full = |u: f32| d.cdf[1..].partition_point(|&c| c <= u).min(n - 1);
            let mut us: Vec<f32> = (0..20_000).map(|i| i as f32 / 20_000.0).collect();
            us.extend(d.cdf.iter().flat_map(|&c| {
                [
                    c,
                    f32::from_bits(c.to_bits().saturating_sub(1)),
                    f32::from_bits(c.to_bits() + 1),
                ]
            }));
            us.extend((0..=n).map(|k| k as f32 / n as f32));
            us.push(ONE_MINUS_EPSILON);
            for u in us.into_iter().filter(|u| (0.0..1.0).contains(u)) {
                assert_eq!(d.find(u), full(u), "u = {u}");
            }
        }
    }

    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_pcg::Pcg64;

    /// Pearson's χ² statistic of `counts` against `expected` (bins with expectation < 5 are
    /// pooled), and its degrees of freedom.
    fn chi_square(counts: &[u64], expected: &[f64]) -> (f64, usize) {
        let (mut chi, mut bins) = (0.0, 0usize);
        let (mut pool_c, mut pool_e) = (0.0, 0.0);
        for (&c, &e) in counts.iter().zip(expected) {
            if e < 5.0 {
                pool_c += c as f64;
                pool_e += e;
                assert!(e > 0.0 || c == 0, "a sample fell in a zero-probability bin");
                continue;
            }
            chi += (c as f64 - e).powi(2) / e;
            bins += 1;
        }
        if pool_e > 5.0 {
            chi += (pool_c - pool_e).powi(2) / pool_e;
            bins += 1;
        }
        (chi, bins.saturating_sub(1))
    }

    /// The χ² quantile at p = 1 − 1e-6 for `dof` degrees of freedom (Wilson–Hilferty), a
    /// threshold a correct sampler exceeds once in a million runs.
    fn chi_square_threshold(dof: usize) -> f64 {
        let k = dof as f64;
        let z = 4.753_424; // standard normal quantile at 1 − 1e-6
        k * (1.0 - 2.0 / (9.0 * k) + z * (2.0 / (9.0 * k)).sqrt()).powi(3)
    }

    #[test]
    fn all_zero_or_empty_weights_have_no_distribution() {
        assert!(Distribution1D::new(&[]).is_none());
        assert!(Distribution1D::new(&[0.0, 0.0]).is_none());
        assert!(Distribution1D::new(&[-1.0, f32::NAN]).is_none());
        assert!(Distribution2D::new(&[0.0; 6], 3, 2).is_none());
        assert!(
            Distribution2D::new(&[1.0; 5], 3, 2).is_none(),
            "wrong length"
        );
    }

    #[test]
    fn discrete_sampling_matches_pmf_and_skips_zero_bins() {
        let w = [0.0, 1.0, 0.0, 3.0, 0.5, 0.0, 2.0, 0.0];
        let d = Distribution1D::new(&w).unwrap();
        let total: f32 = w.iter().sum();
        for (i, &wi) in w.iter().enumerate() {
            assert!((d.pmf(i) - wi / total).abs() < 1e-7);
        }
        let mut rng = Pcg64::seed_from_u64(1);
        let n = 200_000;
        let mut counts = [0u64; 8];
        for _ in 0..n {
            let (i, pmf, ur) = d.sample_discrete(rng.random());
            assert!(w[i] > 0.0, "chose a zero-weight bin");
            assert_eq!(pmf, d.pmf(i));
            assert!((0.0..1.0).contains(&ur));
            counts[i] += 1;
        }
        let expected: Vec<f64> = w.iter().map(|&x| (x / total) as f64 * n as f64).collect();
        let (chi, dof) = chi_square(&counts, &expected);
        assert!(chi < chi_square_threshold(dof), "χ² {chi} with {dof} dof");
        // The edges: u = 0 and the largest u below 1 land in the first and last positive bin.
        assert_eq!(d.sample_discrete(0.0).0, 1);
        assert_eq!(d.sample_discrete(ONE_MINUS_EPSILON).0, 6);
    }

    #[test]
    fn continuous_pdf_integrates_to_one_and_matches_samples() {
        let mut rng = Pcg64::seed_from_u64(2);
        let w: Vec<f32> = (0..37)
            .map(|i| {
                if i % 5 == 0 {
                    0.0
                } else {
                    rng.random::<f32>() * 4.0
                }
            })
            .collect();
        let d = Distribution1D::new(&w).unwrap();
        // The density is constant per bin: its integral is the sum over bin midpoints / n.
        let integral: f32 = (0..w.len())
            .map(|i| d.pdf((i as f32 + 0.5) / w.len() as f32) / w.len() as f32)
            .sum();
        assert!((integral - 1.0).abs() < 1e-5, "∫p = {integral}");
        // Samples in 4 sub-bins per bin (uniform inside a bin): χ² against p.
        let n = 400_000;
        let sub = 4;
        let mut counts = vec![0u64; w.len() * sub];
        for _ in 0..n {
            let (x, pdf, i) = d.sample_continuous(rng.random());
            assert!((0.0..1.0).contains(&x));
            assert_eq!(i, (x * w.len() as f32) as usize);
            assert!((pdf - d.pdf(x)).abs() <= 1e-6 * pdf);
            let k = ((x * (w.len() * sub) as f32) as usize).min(w.len() * sub - 1);
            counts[k] += 1;
        }
        let expected: Vec<f64> = (0..counts.len())
            .map(|k| {
                let x = (k as f32 + 0.5) / counts.len() as f32;
                d.pdf(x) as f64 / counts.len() as f64 * n as f64
            })
            .collect();
        let (chi, dof) = chi_square(&counts, &expected);
        assert!(chi < chi_square_threshold(dof), "χ² {chi} with {dof} dof");
    }

    #[test]
    fn two_d_sampling_matches_pdf() {
        let (nu, nv) = (9, 7);
        let mut rng = Pcg64::seed_from_u64(3);
        let mut w: Vec<f32> = (0..nu * nv).map(|_| rng.random::<f32>()).collect();
        // A zero row and a zero column entry.
        w[2 * nu..3 * nu].fill(0.0);
        w[5 * nu + 4] = 0.0;
        let d = Distribution2D::new(&w, nu, nv).unwrap();
        let cell = 1.0 / (nu * nv) as f32;
        let integral: f32 = (0..nv)
            .flat_map(|j| (0..nu).map(move |i| (i, j)))
            .map(|(i, j)| {
                d.pdf(Vec2::new(
                    (i as f32 + 0.5) / nu as f32,
                    (j as f32 + 0.5) / nv as f32,
                )) * cell
            })
            .sum();
        assert!((integral - 1.0).abs() < 1e-5, "∫p = {integral}");
        let n = 300_000;
        let mut counts = vec![0u64; nu * nv];
        for _ in 0..n {
            let (uv, pdf) = d.sample(Vec2::new(rng.random(), rng.random()));
            assert!(pdf > 0.0);
            assert!(
                (pdf - d.pdf(uv)).abs() <= 1e-5 * pdf,
                "{pdf} vs {}",
                d.pdf(uv)
            );
            let i = (uv.x * nu as f32) as usize;
            let j = (uv.y * nv as f32) as usize;
            counts[j * nu + i] += 1;
        }
        let expected: Vec<f64> = (0..nu * nv)
            .map(|k| {
                let (i, j) = (k % nu, k / nu);
                let uv = Vec2::new((i as f32 + 0.5) / nu as f32, (j as f32 + 0.5) / nv as f32);
                (d.pdf(uv) * cell) as f64 * n as f64
            })
            .collect();
        let (chi, dof) = chi_square(&counts, &expected);
        assert!(chi < chi_square_threshold(dof), "χ² {chi} with {dof} dof");
    }

    #[test]
    fn a_wrong_sampler_fails_the_chi_square_test() {
        // The test's power: counts from a slightly different distribution must be rejected.
        let w = [1.0f32, 2.0, 3.0, 4.0];
        let n = 200_000.0;
        let expected: Vec<f64> = w.iter().map(|&x| x as f64 / 10.0 * n).collect();
        let skewed: Vec<u64> = [1.05, 2.0, 3.0, 3.95]
            .iter()
            .map(|&x: &f64| (x / 10.0 * n) as u64)
            .collect();
        let (chi, dof) = chi_square(&skewed, &expected);
        assert!(chi > chi_square_threshold(dof));
    }
}
