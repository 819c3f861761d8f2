//! Statistical checks shared by the BSDF tests: a chi-square goodness-of-fit test of
//! `sample` against `pdf` (after Mitsuba's `chi2` test), the pdf's integral, the sample
//! weights, Monte Carlo albedo and reciprocity.

use glam::{Vec2, Vec3};
use glint::bsdf::Bsdf;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use statrs::distribution::{ChiSquared, ContinuousCDF};
use std::f64::consts::TAU;

/// Bins in cos θ ∈ [−1, 1] (equal solid angle) and in φ ∈ [0, 2π).
pub const COS_BINS: usize = 32;
/// Bins in φ.
pub const PHI_BINS: usize = 64;
/// Midpoint sub-cells per bin side for integrating the pdf over a bin.
const SUB: usize = 12;
/// Bins whose expected count falls below this are pooled (the chi-square approximation
/// needs about 5 per cell).
const MIN_EXPECTED: f64 = 5.0;
/// Reject when the p-value falls below this (Mitsuba uses 10⁻²; we run many configurations,
/// so 10⁻⁴ keeps the chance of a false alarm across the whole suite under 1%).
pub const P_THRESHOLD: f64 = 1e-4;

pub fn rng(seed: u64) -> Pcg64 {
    Pcg64::seed_from_u64(seed)
}

pub fn dir(cos_theta: f64, phi: f64) -> Vec3 {
    let s = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    Vec3::new(
        (s * phi.cos()) as f32,
        (s * phi.sin()) as f32,
        cos_theta as f32,
    )
}

fn bin_of(w: Vec3) -> usize {
    let c = ((w.z as f64 + 1.0) * 0.5 * COS_BINS as f64).floor() as isize;
    let mut phi = (w.y as f64).atan2(w.x as f64);
    if phi < 0.0 {
        phi += TAU;
    }
    let p = (phi / TAU * PHI_BINS as f64).floor() as isize;
    let c = c.clamp(0, COS_BINS as isize - 1) as usize;
    let p = p.clamp(0, PHI_BINS as isize - 1) as usize;
    c * PHI_BINS + p
}

/// ∫ pdf over each bin (solid angle = d cos θ dφ), midpoint rule on SUB×SUB sub-cells.
pub fn pdf_per_bin(bsdf: &impl Bsdf, wo: Vec3) -> Vec<f64> {
    let dc = 2.0 / (COS_BINS * SUB) as f64;
    let dp = TAU / (PHI_BINS * SUB) as f64;
    let mut out = vec![0.0; COS_BINS * PHI_BINS];
    for i in 0..COS_BINS * SUB {
        let c = -1.0 + (i as f64 + 0.5) * dc;
        for j in 0..PHI_BINS * SUB {
            let phi = (j as f64 + 0.5) * dp;
            let p = bsdf.pdf(wo, dir(c, phi)) as f64;
            out[(i / SUB) * PHI_BINS + j / SUB] += p * dc * dp;
        }
    }
    out
}

/// What [`check_sampling`] measured.
#[derive(Debug)]
pub struct SamplingReport {
    /// Chi-square p-value of the histogram of non-delta samples against the pdf.
    pub p_value: f64,
    /// ∫ pdf over the sphere (quadrature).
    pub pdf_integral: f64,
    /// Fraction of draws that returned a non-delta direction.
    pub non_delta_fraction: f64,
    /// Mean sample weight (including delta samples, zero for failed draws): the albedo.
    pub albedo: Vec3,
    /// Standard error of `albedo`, per channel.
    pub albedo_se: Vec3,
    /// Mean weight of the non-delta samples only (zero for the others): the albedo of the
    /// lobes `eval` describes.
    pub albedo_non_delta: Vec3,
    /// Standard error of `albedo_non_delta`.
    pub albedo_non_delta_se: Vec3,
}

/// Draws `n` samples for `wo` and checks them: each non-delta sample's `pdf` equals
/// `bsdf.pdf(wo, wi)` and its weight equals `eval·|cos|/pdf` (relative 10⁻³); then runs the
/// chi-square test of the histogram against [`pdf_per_bin`] and returns the figures. Fails the
/// calling test (panics) on a bad individual sample.
pub fn check_sampling(bsdf: &impl Bsdf, wo: Vec3, n: usize, seed: u64) -> SamplingReport {
    let mut r = rng(seed);
    let mut observed = vec![0.0f64; COS_BINS * PHI_BINS];
    let mut non_delta = 0usize;
    let mut sum = [0.0f64; 3];
    let mut sum2 = [0.0f64; 3];
    let mut nd_sum = [0.0f64; 3];
    let mut nd_sum2 = [0.0f64; 3];
    for _ in 0..n {
        let u_lobe: f32 = r.random();
        let u = Vec2::new(r.random(), r.random());
        let Some(s) = bsdf.sample(wo, u_lobe, u) else {
            continue;
        };
        assert!(
            s.weight.is_finite() && s.weight.min_element() >= 0.0,
            "weight {s:?}"
        );
        assert!((s.wi.length() - 1.0).abs() < 1e-4, "non-unit wi {s:?}");
        for k in 0..3 {
            let w = s.weight[k] as f64;
            sum[k] += w;
            sum2[k] += w * w;
        }
        if s.delta {
            continue;
        }
        assert_eq!(
            s.transmission,
            s.wi.z * wo.z < 0.0,
            "transmission flag {s:?} for wo {wo}"
        );
        let pdf = bsdf.pdf(wo, s.wi);
        assert!(
            (pdf - s.pdf).abs() <= 1e-3 * pdf.max(s.pdf),
            "sample pdf {} vs pdf() {pdf} for wo {wo}, wi {}",
            s.pdf,
            s.wi
        );
        let expect = bsdf.eval(wo, s.wi) * s.wi.z.abs() / pdf;
        assert!(
            (expect - s.weight).abs().max_element() <= 1e-3 * expect.max_element().max(1e-3),
            "weight {} vs eval·cos/pdf {expect} for wo {wo}, wi {}",
            s.weight,
            s.wi
        );
        for k in 0..3 {
            let w = s.weight[k] as f64;
            nd_sum[k] += w;
            nd_sum2[k] += w * w;
        }
        non_delta += 1;
        observed[bin_of(s.wi)] += 1.0;
    }
    let expected: Vec<f64> = pdf_per_bin(bsdf, wo).iter().map(|p| p * n as f64).collect();
    let pdf_integral = expected.iter().sum::<f64>() / n as f64;
    let p_value = chi2_p_value(&observed, &expected);
    let nf = n as f64;
    let mean = |s: &[f64; 3]| Vec3::new((s[0] / nf) as f32, (s[1] / nf) as f32, (s[2] / nf) as f32);
    let se = |s: &[f64; 3], s2: &[f64; 3]| {
        let e = |k: usize| (((s2[k] / nf - (s[k] / nf).powi(2)).max(0.0)) / nf).sqrt() as f32;
        Vec3::new(e(0), e(1), e(2))
    };
    SamplingReport {
        p_value,
        pdf_integral,
        non_delta_fraction: non_delta as f64 / nf,
        albedo: mean(&sum),
        albedo_se: se(&sum, &sum2),
        albedo_non_delta: mean(&nd_sum),
        albedo_non_delta_se: se(&nd_sum, &nd_sum2),
    }
}

/// Pearson's chi-square p-value, pooling cells with expected counts below [`MIN_EXPECTED`]
/// into one cell. A sample in a cell of zero expected count is an outright failure (p = 0).
pub fn chi2_p_value(observed: &[f64], expected: &[f64]) -> f64 {
    let mut stat = 0.0;
    let mut cells = 0usize;
    let (mut pool_o, mut pool_e) = (0.0, 0.0);
    for (&o, &e) in observed.iter().zip(expected) {
        if e <= 0.0 && o > 0.0 {
            return 0.0;
        }
        if e < MIN_EXPECTED {
            pool_o += o;
            pool_e += e;
        } else {
            stat += (o - e) * (o - e) / e;
            cells += 1;
        }
    }
    if pool_e >= MIN_EXPECTED {
        stat += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        cells += 1;
    } else if pool_o > 4.0 * MIN_EXPECTED {
        // Many samples where the pdf says almost none.
        return 0.0;
    }
    if cells < 2 {
        return 1.0;
    }
    // The total is not fixed (failed and delta draws fall outside the histogram), but the
    // counts are then Poisson-like and cells − 1 degrees of freedom is the conservative choice.
    match ChiSquared::new((cells - 1) as f64) {
        Ok(d) => d.sf(stat),
        Err(_) => 0.0,
    }
}

/// Maximum relative asymmetry |f(a, b) − f(b, a)| / max(f) over `n` random pairs of
/// directions in the upper hemisphere (skipping pairs where f is tiny).
pub fn reciprocity_error(bsdf: &impl Bsdf, n: usize, seed: u64) -> f32 {
    let mut r = rng(seed);
    let mut worst = 0.0f32;
    for _ in 0..n {
        let a = dir(r.random_range(0.02..1.0), r.random_range(0.0..TAU));
        let b = dir(r.random_range(0.02..1.0), r.random_range(0.0..TAU));
        let fab = bsdf.eval(a, b);
        let fba = bsdf.eval(b, a);
        let m = fab.max_element().max(fba.max_element());
        if m > 1e-6 {
            worst = worst.max((fab - fba).abs().max_element() / m);
        }
    }
    worst
}
