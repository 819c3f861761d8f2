//! Adaptive sampling: pixels whose estimated error is already below a threshold stop taking
//! samples, so the rest of the budget goes where the image is still noisy.
//!
//! After each pass (from [`first_pass`] samples on), every pixel not yet decided gets a
//! relative error estimate from the film's two half-buffers (even and odd samples):
//! `e² = mean over its 3×3 neighbourhood of Var(Y)/(Y² + ε²)`, with `Var(Y) = (A − B)²/4` in
//! luminance and `ε` = [`super::film::RELATIVE_ERROR_FLOOR`] × the image's mean luminance, as
//! the progressive stop rule measures it. A pixel with `e ≥ threshold` keeps sampling. A pixel
//! with `e < threshold` is decided once, by Russian roulette: it continues with probability
//! `q = max(e²/threshold², Q_MIN)` and stops otherwise.
//!
//! **Unbiased.** Let `F_k` be the pixel's mean after the `k` samples it had when decided and
//! `F` its mean after every sample of the render (what uniform sampling would return). A
//! stopped pixel returns `F_k`; a continuing one returns `F_k + (F − F_k)/q`. The coin is
//! independent of everything else, so the expectation given the first `k` samples is
//! `E[F | first k samples]`, and the expectation of the result is `E[F]`: exactly the
//! uniform render's, whatever rule chose `q` from those samples (no assumption that later
//! samples are independent of earlier ones, so Owen-scrambled Sobol points are fine). A plain
//! "stop when converged" rule is biased: pixels whose rare bright paths have not shown up yet
//! look converged and stop dark. The price is variance: a continuing pixel's late samples
//! count `1/q` times, which `q ≥ e²/threshold²` keeps at about the threshold's error.
//!
//! **Deterministic.** Decisions run on the calling thread over the whole film after each
//! pass, and the coin of pixel `p` at decision `d` is a hash of the seed, `p` and `d`, so the
//! image is the same for any thread count.

use super::film::{Film, Image, error_floor, luminance};
use super::sampler::mix64;
use glam::Vec3;

/// Smallest probability of continuing a converged pixel: at most 1 − `Q_MIN` of a converged
/// pixel's remaining samples are saved, and a continuing pixel's late samples weigh at most
/// `1/Q_MIN`.
pub const Q_MIN: f32 = 1.0 / 16.0;

/// Fewest samples before the first decision (at 16 spp: decided after 8).
pub const MIN_SAMPLES: u32 = 8;

/// Samples of the first pass of an adaptive render of `spp` samples: an eighth of them, at
/// least [`MIN_SAMPLES`], even (both halves equal), never more than `spp`.
pub fn first_pass(spp: u32) -> u32 {
    ((spp / 8).max(MIN_SAMPLES) & !1).min(spp)
}

/// Pass sizes of an adaptive render of `spp` samples: [`first_pass`], then doubling the total
/// until `spp` (e.g. 128 → 16, 16, 32, 64).
pub fn schedule(spp: u32) -> Vec<u32> {
    let mut passes = Vec::new();
    let mut done = 0u32;
    while done < spp {
        let pass = if done == 0 {
            first_pass(spp).max(1)
        } else {
            done.min(spp - done)
        };
        passes.push(pass);
        done += pass;
    }
    passes
}

/// Adaptive sampling's threshold from a render's options, the same for the command line, job
/// files and Python: `adaptive` if given (0 turns it off), else the target error of a
/// progressive render if any, else off.
pub fn threshold_for(
    adaptive: Option<f32>,
    target_error: Option<f64>,
) -> Result<Option<f32>, String> {
    match adaptive {
        Some(0.0) => Ok(None),
        Some(t) if t > 0.0 && t.is_finite() => Ok(Some(t)),
        Some(t) => Err(format!(
            "adaptive threshold {t}: give a positive relative error, e.g. 0.01, or 0 to turn \
             it off"
        )),
        None => Ok(target_error
            .filter(|e| *e > 0.0 && e.is_finite())
            .map(|e| e as f32)),
    }
}

/// Per-pixel state of an adaptive render.
#[derive(Clone, Debug)]
pub struct Adaptive {
    threshold: f32,
    seed: u64,
    width: u32,
    height: u32,
    /// Whether the pixel still takes samples.
    active: Vec<bool>,
    /// Whether the pixel's roulette has been played.
    decided: Vec<bool>,
    /// For pixels that continued after their roulette: their mean then and `1/q`.
    anchor: Vec<Option<(Vec3, f32)>>,
    /// Samples each pixel took.
    samples: Vec<u32>,
    /// Decisions made so far (the coins' index).
    decisions: u32,
}

impl Adaptive {
    /// Every pixel active. `threshold` is the per-pixel relative RMS error below which a
    /// pixel may stop; `seed` the render's.
    pub fn new(width: u32, height: u32, threshold: f32, seed: u64) -> Self {
        let n = width as usize * height as usize;
        Self {
            threshold,
            seed,
            width,
            height,
            active: vec![true; n],
            decided: vec![false; n],
            anchor: vec![None; n],
            samples: vec![0; n],
            decisions: 0,
        }
    }

    /// Which pixels take the next pass's samples, row-major.
    pub fn active(&self) -> &[bool] {
        &self.active
    }

    /// Counts a pass of `spp` samples for the active pixels.
    pub fn record_pass(&mut self, spp: u32) {
        for (n, &on) in self.samples.iter_mut().zip(&self.active) {
            if on {
                *n = n.saturating_add(spp);
            }
        }
    }

    /// Fraction of pixels still taking samples.
    pub fn active_fraction(&self) -> f64 {
        let on = self.active.iter().filter(|&&a| a).count();
        on as f64 / self.active.len().max(1) as f64
    }

    /// Plays the roulette of every undecided pixel whose error estimate (from `film`) is below
    /// the threshold.
    pub fn decide(&mut self, film: &Film) {
        let image = film.radiance();
        let variance = film.variance();
        let (w, h) = (self.width as usize, self.height as usize);
        let floor = error_floor(&image);
        let relative: Vec<f32> = image
            .pixels
            .iter()
            .zip(&variance.pixels)
            .map(|(&p, &v)| {
                let y = luminance(p) as f64;
                (luminance(v) as f64 / (y * y + floor * floor)) as f32
            })
            .collect();
        let threshold2 = self.threshold * self.threshold;
        let decision = self.decisions;
        for y in 0..h {
            for x in 0..w {
                let i = y * w + x;
                if self.decided[i] {
                    continue;
                }
                let e2 = neighbourhood_mean(&relative, w, h, x, y);
                if e2.is_nan() || e2 >= threshold2 {
                    continue;
                }
                self.decided[i] = true;
                let q = (e2 / threshold2).max(Q_MIN);
                if coin(self.seed, i as u64, decision) < q {
                    self.anchor[i] = Some((image.pixels[i], 1.0 / q));
                } else {
                    self.active[i] = false;
                }
            }
        }
        self.decisions += 1;
    }

    /// The estimate of each pixel from the film's plain means `radiance`: unchanged for
    /// pixels that stopped or never played, `F_k + (F − F_k)/q` for those that continued.
    pub fn resolve(&self, mut radiance: Image<Vec3>) -> Image<Vec3> {
        for (p, anchor) in radiance.pixels.iter_mut().zip(&self.anchor) {
            if let Some((f_k, inv_q)) = *anchor {
                *p = f_k + (*p - f_k) * inv_q;
            }
        }
        radiance
    }

    /// Samples each pixel took.
    pub fn sample_counts(&self) -> Image<u32> {
        Image {
            width: self.width,
            height: self.height,
            pixels: self.samples.clone(),
        }
    }
}

/// Mean of `values` over the 3×3 neighbourhood of `(x, y)` inside the image.
fn neighbourhood_mean(values: &[f32], w: usize, h: usize, x: usize, y: usize) -> f32 {
    let (mut sum, mut count) = (0.0f32, 0u32);
    for ny in y.saturating_sub(1)..(y + 2).min(h) {
        for nx in x.saturating_sub(1)..(x + 2).min(w) {
            sum += values[ny * w + nx];
            count += 1;
        }
    }
    sum / count.max(1) as f32
}

/// A uniform number in `[0, 1)` from the seed, the pixel and the decision index.
fn coin(seed: u64, pixel: u64, decision: u32) -> f32 {
    let h = mix64(seed ^ mix64(pixel.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ decision as u64));
    (h >> 40) as f32 / (1u64 << 24) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schedule_sums_to_spp_and_starts_with_an_even_first_pass() {
        for spp in [1, 2, 3, 7, 8, 16, 17, 100, 128, 512] {
            let s = schedule(spp);
            assert_eq!(s.iter().sum::<u32>(), spp, "{spp}: {s:?}");
            assert!(s.iter().all(|&p| p > 0));
        }
        assert_eq!(schedule(128), vec![16, 16, 32, 64]);
        assert_eq!(schedule(16), vec![8, 8]);
    }

    #[test]
    fn coins_are_uniform() {
        let n = 100_000;
        let mean: f64 = (0..n).map(|i| coin(7, i, 3) as f64).sum::<f64>() / n as f64;
        // σ of the mean of n uniforms: 1/√(12 n) ≈ 0.0009.
        assert!((mean - 0.5).abs() < 0.004, "{mean}");
    }
}
