//! Rendering in passes: a fixed sample count, a time budget, or a target error.
//!
//! Passes are rendered by the [`TileScheduler`]; pass `k` continues the sample sequence where
//! pass `k − 1` stopped, so `n` samples in any number of passes give the same image as `n`
//! samples in one (Sobol and independent sampling; stratified jitter needs the count up front
//! and is refused here).
//!
//! [`render_progressive`] stops on whichever comes first:
//! - the time budget: each pass is sized from the measured time per sample so that it ends
//!   within the budget; rendering stops when not even one more sample fits. The overshoot is
//!   the error of that prediction (a few percent; at worst the first 2-sample pass).
//! - the target error: after each pass the film's estimated relative RMS error (two
//!   half-buffers of independent samples, [`Film::relative_error`]) is compared with it.
//! - the sample cap.
//!
//! Pass sizes at most double the total (2, 2, 4, 8, … samples), so the film is scanned for the
//! error a logarithmic number of times; with a target error, a pass is cut to the samples the
//! target still needs, predicted from error ∝ spp^−½ (+10%), so the last pass does not
//! overshoot the target by a whole doubling.
//!
//! With adaptive sampling ([`RenderSettings::adaptive`], on by default with a target error on
//! the command line) converged pixels stop before each pass ([`super::adaptive`]).

use super::film::Image;
use super::scheduler::TileScheduler;
use super::{Progress, RenderError, RenderInputs, RenderOutput, RenderSettings};
use crate::accel::Accel;
use crate::scene::{Camera, Scene};
use glam::Vec3;
use std::time::Duration;

/// When a progressive render stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StopRule {
    /// Stop before the render time would exceed this.
    pub time_budget: Option<Duration>,
    /// Stop once the estimated relative RMS error is at or below this.
    pub target_error: Option<f64>,
    /// Never render more samples per pixel than this.
    pub max_spp: u32,
}

/// Default sample cap of a progressive render.
pub const DEFAULT_MAX_SPP: u32 = 1 << 16;

impl Default for StopRule {
    fn default() -> Self {
        Self {
            time_budget: None,
            target_error: None,
            max_spp: DEFAULT_MAX_SPP,
        }
    }
}

/// Why a progressive render stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// Another pass would not have fitted in the time budget.
    TimeBudget,
    /// The error estimate reached the target.
    TargetError,
    /// The sample cap was reached.
    MaxSpp,
}

/// A finished progressive render.
#[derive(Clone, Debug)]
pub struct ProgressiveOutput {
    /// The image, AOVs and statistics.
    pub output: RenderOutput,
    /// Per-pixel variance of the image (from the two half-buffers).
    pub variance: Image<Vec3>,
    /// Samples per pixel rendered.
    pub spp: u32,
    /// Passes rendered.
    pub passes: u32,
    /// The final relative RMS error estimate.
    pub relative_error: f64,
    /// Why it stopped.
    pub reason: StopReason,
}

/// Renders passes until `rule` says stop. `settings.spp` is ignored; `settings.sampling` must
/// be progressive (Sobol or independent).
pub fn render_progressive(
    scene: &Scene,
    accel: &dyn Accel,
    camera: &Camera,
    settings: &RenderSettings,
    rule: &StopRule,
    progress: Option<Progress<'_>>,
) -> Result<ProgressiveOutput, RenderError> {
    let inputs = RenderInputs::of_scene(scene, accel, camera);
    render_progressive_with(&inputs, settings, rule, progress)
}

/// [`render_progressive`] from [`RenderInputs`] (given lights, optionally a shared pool).
pub fn render_progressive_with(
    inputs: &RenderInputs<'_>,
    settings: &RenderSettings,
    rule: &StopRule,
    progress: Option<Progress<'_>>,
) -> Result<ProgressiveOutput, RenderError> {
    if !settings.sampling.progressive() {
        return Err(RenderError::Settings(format!(
            "the {} sampler needs the sample count up front; progressive rendering (time \
             budget, target error) needs --sampler sobol or independent",
            settings.sampling
        )));
    }
    if rule.time_budget.is_none() && rule.target_error.is_none() {
        return Err(RenderError::Settings(
            "a progressive render needs a time budget or a target error".into(),
        ));
    }
    if let Some(e) = rule.target_error
        && !(e > 0.0 && e.is_finite())
    {
        return Err(RenderError::Settings(format!(
            "target error {e} must be a positive number (e.g. 0.05 for 5%)"
        )));
    }
    let max_spp = rule.max_spp.max(2);
    let mut renderer = TileScheduler::with_inputs(inputs, settings)?;
    renderer.train_progressively();
    let mut passes = 0;
    // Two samples first: one in each half-buffer, the least the error estimate needs.
    let mut next = 2;
    let reason = loop {
        // Adaptive sampling (when on) stops converged pixels before each pass.
        renderer.adapt();
        renderer.render_pass(next, progress);
        if renderer.cancelled() {
            return Err(RenderError::Cancelled);
        }
        passes += 1;
        let spp = renderer.samples_per_pixel();
        // Samples the error target still asks for, from error ∝ spp^−½ (plain Monte Carlo;
        // Sobol converges at least as fast), plus 10% so one pass usually suffices.
        let mut wanted = spp;
        if let Some(target) = rule.target_error {
            let error = renderer.film().relative_error();
            if error <= target {
                break StopReason::TargetError;
            }
            if error.is_finite() {
                let more = spp as f64 * ((error / target).powi(2) * 1.1 - 1.0);
                wanted = wanted.min(more.ceil().clamp(2.0, u32::MAX as f64) as u32);
            }
        }
        if spp >= max_spp {
            break StopReason::MaxSpp;
        }
        // At most double the total, never past the cap and (with a budget) never past what
        // the measured time per sample says still fits.
        let mut pass = wanted.min(max_spp - spp);
        if let Some(budget) = rule.time_budget {
            let per_sample = renderer.elapsed().as_secs_f64() / spp as f64;
            let left = budget.as_secs_f64() - renderer.elapsed().as_secs_f64();
            let fits = (left / per_sample.max(1e-12)).floor();
            if fits < 1.0 {
                break StopReason::TimeBudget;
            }
            pass = pass.min(fits.min(u32::MAX as f64) as u32);
        }
        // Keep passes even so each half-buffer gets the same number of samples.
        next = if pass >= 2 { pass & !1 } else { pass };
    };
    let output = renderer.finish();
    Ok(ProgressiveOutput {
        variance: renderer.film().variance(),
        relative_error: renderer.film().relative_error(),
        spp: renderer.samples_per_pixel(),
        passes,
        reason,
        output,
    })
}
