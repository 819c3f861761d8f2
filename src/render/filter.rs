//! Pixel reconstruction filters, applied by filter importance sampling.
//!
//! A pixel's value is `I = ∫ f(x − c) L(x) dx / ∫ f(x − c) dx`, with `c` the pixel centre and
//! `f` the filter. glint samples film positions `x − c` with density proportional to `|f|`
//! (tabulated in 256 bins per axis; the box is sampled exactly), gives each sample the weight
//! `sign f` (±1), and the film stores `Σ w·L / Σ w`. So every sample belongs to exactly one pixel: no splatting across pixels or
//! tiles, which keeps images bit-identical whatever the thread count, and every filter
//! integrates to 1 by construction (a constant scene gives that constant at every pixel,
//! borders included, since camera rays may leave the image).
//!
//! All filters are separable, `f(x, y) = f₁(x)·f₁(y)`, with a radius `r` in pixels:
//!
//! | name | f₁(x) on \|x\| < r | default r |
//! |---|---|---|
//! | box | 1 | 0.5 |
//! | tent | r − \|x\| | 1 |
//! | gaussian | exp(−x²/2σ²) − exp(−r²/2σ²), σ = r/3 | 1.5 |
//! | mitchell | Mitchell–Netravali cubic with B = C = 1/3, on 2\|x\|/r ∈ [0, 2] | 2 |
//! | blackman-harris | 4-term Blackman–Harris window over [−r, r] | 2 |
//!
//! Mitchell has negative lobes: its samples carry negative weights there.

use glam::Vec2;
use std::fmt;
use std::sync::Arc;

/// Which reconstruction filter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FilterKind {
    /// Box: the average over the pixel (radius 0.5) or a wider square.
    #[default]
    Box,
    /// Tent (triangle).
    Tent,
    /// Gaussian with σ = radius/3, shifted to reach 0 at the radius.
    Gaussian,
    /// Mitchell–Netravali, B = C = 1/3.
    Mitchell,
    /// Blackman–Harris window.
    BlackmanHarris,
}

impl FilterKind {
    /// Every filter.
    pub const ALL: [FilterKind; 5] = [
        FilterKind::Box,
        FilterKind::Tent,
        FilterKind::Gaussian,
        FilterKind::Mitchell,
        FilterKind::BlackmanHarris,
    ];

    /// Name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            FilterKind::Box => "box",
            FilterKind::Tent => "tent",
            FilterKind::Gaussian => "gaussian",
            FilterKind::Mitchell => "mitchell",
            FilterKind::BlackmanHarris => "blackman-harris",
        }
    }

    /// Default radius in pixels.
    pub fn default_radius(self) -> f32 {
        match self {
            FilterKind::Box => 0.5,
            FilterKind::Tent => 1.0,
            FilterKind::Gaussian => 1.5,
            FilterKind::Mitchell | FilterKind::BlackmanHarris => 2.0,
        }
    }

    /// The 1D profile `f₁(x)` for radius `r` (0 outside `|x| < r`).
    pub fn eval_1d(self, x: f32, r: f32) -> f32 {
        let ax = x.abs();
        if ax >= r {
            return 0.0;
        }
        match self {
            FilterKind::Box => 1.0,
            FilterKind::Tent => r - ax,
            FilterKind::Gaussian => {
                let sigma = r / 3.0;
                let g = |v: f32| (-v * v / (2.0 * sigma * sigma)).exp();
                (g(ax) - g(r)).max(0.0)
            }
            FilterKind::Mitchell => mitchell_1d(2.0 * ax / r),
            FilterKind::BlackmanHarris => {
                let (a0, a1, a2, a3) = (0.35875, 0.48829, 0.14128, 0.01168);
                let t = std::f32::consts::TAU * (x + r) / (2.0 * r);
                a0 - a1 * t.cos() + a2 * (2.0 * t).cos() - a3 * (3.0 * t).cos()
            }
        }
    }
}

/// Mitchell–Netravali cubic on `x ∈ [0, 2]` with B = C = 1/3 (Mitchell & Netravali 1988).
fn mitchell_1d(x: f32) -> f32 {
    const B: f32 = 1.0 / 3.0;
    const C: f32 = 1.0 / 3.0;
    let x2 = x * x;
    let x3 = x2 * x;
    let v = if x < 1.0 {
        (12.0 - 9.0 * B - 6.0 * C) * x3 + (-18.0 + 12.0 * B + 6.0 * C) * x2 + (6.0 - 2.0 * B)
    } else if x < 2.0 {
        (-B - 6.0 * C) * x3
            + (6.0 * B + 30.0 * C) * x2
            + (-12.0 * B - 48.0 * C) * x
            + (8.0 * B + 24.0 * C)
    } else {
        0.0
    };
    v / 6.0
}

impl fmt::Display for FilterKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A filter and its radius, as chosen on the command line (`NAME` or `NAME:RADIUS`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterSpec {
    /// The filter.
    pub kind: FilterKind,
    /// Radius in pixels (> 0).
    pub radius_px: f32,
}

impl Default for FilterSpec {
    fn default() -> Self {
        FilterSpec::new(FilterKind::default())
    }
}

/// Largest accepted filter radius in pixels: wider filters blur the image away and need
/// camera rays far outside it.
pub const MAX_FILTER_RADIUS_PX: f32 = 16.0;

impl FilterSpec {
    /// `kind` with its default radius.
    pub fn new(kind: FilterKind) -> Self {
        Self {
            kind,
            radius_px: kind.default_radius(),
        }
    }

    /// Checks the radius.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.radius_px > 0.0 && self.radius_px <= MAX_FILTER_RADIUS_PX) {
            return Err(format!(
                "filter radius {} px must be in (0, {MAX_FILTER_RADIUS_PX}]",
                self.radius_px
            ));
        }
        Ok(())
    }
}

impl fmt::Display for FilterSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.kind, self.radius_px)
    }
}

impl std::str::FromStr for FilterSpec {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let (name, radius) = match s.split_once(':') {
            Some((name, radius)) => (name, Some(radius)),
            None => (s, None),
        };
        let kind = FilterKind::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(name.trim()))
            .ok_or_else(|| {
                format!(
                    "unknown filter '{name}': use box, tent, gaussian, mitchell or \
                     blackman-harris, optionally with :RADIUS in pixels"
                )
            })?;
        let mut spec = FilterSpec::new(kind);
        if let Some(radius) = radius {
            spec.radius_px = radius.trim().parse().map_err(|_| {
                format!("filter radius '{radius}' is not a number (e.g. mitchell:2)")
            })?;
        }
        spec.validate()?;
        Ok(spec)
    }
}

/// Bins of the tabulated 1D sampling density: the filter glint applies is this tabulation,
/// within ~1e-3 of the profile's moments (checked by the tests).
const TABLE_BINS: usize = 256;

/// Samples film offsets from a filter: `|f₁|` tabulated as a piecewise-constant density per
/// axis (the box filter is sampled exactly).
#[derive(Clone, Debug)]
pub struct FilterSampler {
    spec: FilterSpec,
    /// `|f₁|` averaged over each bin of `[−r, r]`.
    bin_value: Arc<[f32]>,
    /// Cumulative distribution at the bins' right edges, last = 1.
    cdf: Arc<[f32]>,
}

impl FilterSampler {
    /// The sampler of `spec` (which must be valid).
    pub fn new(spec: FilterSpec) -> Self {
        let r = spec.radius_px;
        let width = 2.0 * r / TABLE_BINS as f32;
        // Bin averages by an 8-point midpoint rule: good to ~1e-4 for these smooth profiles.
        const SUB: usize = 8;
        let bin_value: Vec<f32> = (0..TABLE_BINS)
            .map(|i| {
                let x0 = -r + i as f32 * width;
                (0..SUB)
                    .map(|k| {
                        spec.kind
                            .eval_1d(x0 + (k as f32 + 0.5) * width / SUB as f32, r)
                            .abs()
                    })
                    .sum::<f32>()
                    / SUB as f32
            })
            .collect();
        let total: f64 = bin_value.iter().map(|&v| v as f64).sum();
        let mut running = 0.0f64;
        let cdf: Vec<f32> = bin_value
            .iter()
            .map(|&v| {
                running += v as f64;
                (running / total) as f32
            })
            .collect();
        Self {
            spec,
            bin_value: bin_value.into(),
            cdf: cdf.into(),
        }
    }

    /// The filter this samples.
    pub fn spec(&self) -> FilterSpec {
        self.spec
    }

    /// Maps a uniform point `u ∈ [0, 1)²` to an offset from the pixel centre (pixels) and the
    /// sample's weight `sign f` (`f/p` up to the constant `∫|f|`, which the film's
    /// `Σ w·L / Σ w` cancels, and up to the tabulation).
    #[inline]
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        if self.spec.kind == FilterKind::Box {
            return ((u * 2.0 - Vec2::ONE) * self.spec.radius_px, 1.0);
        }
        let (x, wx) = self.sample_1d(u.x);
        let (y, wy) = self.sample_1d(u.y);
        (Vec2::new(x, y), wx * wy)
    }

    #[inline]
    fn sample_1d(&self, u: f32) -> (f32, f32) {
        let r = self.spec.radius_px;
        let bins = self.cdf.len();
        let bin = self.cdf.partition_point(|&c| c <= u).min(bins - 1);
        let lo = if bin == 0 { 0.0 } else { self.cdf[bin - 1] };
        let hi = self.cdf[bin];
        let t = if hi > lo { (u - lo) / (hi - lo) } else { 0.5 };
        let width = 2.0 * r / bins as f32;
        let x = (-r + (bin as f32 + t.clamp(0.0, 1.0)) * width).clamp(-r, r);
        // The weight is the sign of f alone, so the film samples the 256-bin tabulation of f
        // exactly. Weights of exactly ±1 keep a pixel's Σw an integer: with negative lobes
        // (Mitchell) it can be 0 at low spp (the pixel is then 0), but never so near 0 that
        // Σ w·L / Σ w explodes, which continuous weights f/p allow.
        let w = if self.bin_value[bin] <= 0.0 {
            0.0
        } else if self.spec.kind.eval_1d(x, r) < 0.0 {
            -1.0
        } else {
            1.0
        };
        (x, w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ f₁ over [−r, r] by a fine midpoint rule.
    fn integral(kind: FilterKind, r: f32, g: impl Fn(f32) -> f64) -> f64 {
        let n = 200_000;
        let h = 2.0 * r as f64 / n as f64;
        (0..n)
            .map(|i| {
                let x = -r as f64 + (i as f64 + 0.5) * h;
                kind.eval_1d(x as f32, r) as f64 * g(x as f32) * h
            })
            .sum()
    }

    #[test]
    fn profiles_vanish_at_the_radius_and_peak_at_the_centre() {
        for kind in FilterKind::ALL {
            let r = kind.default_radius();
            assert_eq!(kind.eval_1d(r, r), 0.0, "{kind}");
            assert!(kind.eval_1d(0.0, r) > 0.0, "{kind}");
            if kind != FilterKind::Box {
                assert!(kind.eval_1d(0.99 * r, r).abs() < 0.02 * kind.eval_1d(0.0, r));
            }
        }
        // Mitchell B = C = 1/3 at 0 is (6 − 2B)/6 = 8/9 and has a negative lobe.
        assert!((mitchell_1d(0.0) - 8.0 / 9.0).abs() < 1e-6);
        assert!(FilterKind::Mitchell.eval_1d(1.5, 2.0) < 0.0);
    }

    #[test]
    fn importance_sampling_reproduces_filter_moments() {
        // E[w·g(x)] / E[w] must equal ∫ f g / ∫ f: checked for g = x² (the filter's
        // variance), on a stratified grid of u so the check is deterministic.
        for kind in FilterKind::ALL {
            for r in [kind.default_radius(), 1.25] {
                let sampler = FilterSampler::new(FilterSpec { kind, radius_px: r });
                let exact = integral(kind, r, |x| (x * x) as f64) / integral(kind, r, |_| 1.0);
                let n = 4096;
                let (mut sum_wg, mut sum_w) = (0.0f64, 0.0f64);
                for i in 0..n {
                    let u = (i as f32 + 0.5) / n as f32;
                    let (offset, w) = sampler.sample(Vec2::new(u, 0.5));
                    assert!(offset.x.abs() <= r && offset.y.abs() <= r);
                    sum_wg += w as f64 * (offset.x * offset.x) as f64;
                    sum_w += w as f64;
                }
                let estimate = sum_wg / sum_w;
                assert!(
                    (estimate - exact).abs() < 2e-3 * r as f64 * r as f64,
                    "{kind}:{r}: {estimate} vs {exact}"
                );
            }
        }
    }

    #[test]
    fn parses_names_and_radii() {
        assert_eq!(
            "mitchell:1.5".parse::<FilterSpec>(),
            Ok(FilterSpec {
                kind: FilterKind::Mitchell,
                radius_px: 1.5
            })
        );
        assert_eq!(
            "Blackman-Harris".parse::<FilterSpec>().map(|s| s.radius_px),
            Ok(2.0)
        );
        assert!("lanczos".parse::<FilterSpec>().is_err());
        assert!("box:0".parse::<FilterSpec>().is_err());
        assert!("box:x".parse::<FilterSpec>().is_err());
        assert!("tent:1000".parse::<FilterSpec>().is_err());
    }
}
