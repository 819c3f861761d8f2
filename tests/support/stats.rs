//! Statistical helpers shared by the light-sampling tests.

#![allow(dead_code)]

/// Pearson's χ² statistic of `counts` against `expected` and its degrees of freedom. Bins
/// expecting fewer than 5 samples are pooled into one; a sample in a bin of probability 0
/// fails the test at once.
pub fn chi_square(counts: &[u64], expected: &[f64]) -> (f64, usize) {
    let (mut chi, mut bins) = (0.0, 0usize);
    let (mut pool_c, mut pool_e) = (0.0, 0.0);
    for (k, (&c, &e)) in counts.iter().zip(expected).enumerate() {
        assert!(e > 0.0 || c == 0, "{c} samples in bin {k} of probability 0");
        if e < 5.0 {
            pool_c += c as f64;
            pool_e += e;
            continue;
        }
        chi += (c as f64 - e).powi(2) / e;
        bins += 1;
    }
    if pool_e >= 5.0 {
        chi += (pool_c - pool_e).powi(2) / pool_e;
        bins += 1;
    }
    (chi, bins.saturating_sub(1))
}

/// The χ² quantile at 1 − 1e-6 for `dof` degrees of freedom (Wilson–Hilferty): a correct
/// sampler exceeds it once in a million runs.
pub fn chi_square_threshold(dof: usize) -> f64 {
    let k = dof.max(1) as f64;
    let z = 4.753_424; // standard normal quantile at 1 − 1e-6
    k * (1.0 - 2.0 / (9.0 * k) + z * (2.0 / (9.0 * k)).sqrt()).powi(3)
}

/// Mean and standard error of the mean.
pub fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}
