//! The range window of KHR_lights_punctual.
//!
//! The extension recommends, for a light with `range` r at distance d, the attenuation
//! `max(min(1 − (d/r)⁴, 1), 0) / d²`. glint implements exactly that: the inverse-square
//! factor is the light's own physics and the window `W(d) = clamp(1 − (d/r)⁴, 0, 1)` is the
//! part this module provides. Without a range the window is identically 1 and is not computed.

/// A light's range window, chosen at compile time so unbounded lights pay nothing.
pub trait RangeWindow: Copy + Send + Sync + std::fmt::Debug {
    /// `W(d)` from the squared distance `d²`: in [0, 1], and 0 at or beyond the range.
    fn window(&self, distance_squared: f32) -> f32;
}

/// No range: the window is 1 everywhere.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Unbounded;

impl RangeWindow for Unbounded {
    #[inline(always)]
    fn window(&self, _distance_squared: f32) -> f32 {
        1.0
    }
}

/// A finite (or, for the general kernel, infinite) range r.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounded {
    /// The range r in scene units.
    pub range: f32,
    /// 1 / r², precomputed: the window needs (d/r)⁴ = (d² / r²)².
    inv_range_squared: f32,
}

impl Bounded {
    /// A window for range `range`, which must be positive (KHR_lights_punctual requires
    /// `range > 0`); `+∞` gives a window that is exactly 1.
    pub fn new(range: f32) -> Result<Self, String> {
        if range > 0.0 {
            Ok(Self {
                range,
                inv_range_squared: 1.0 / (range * range),
            })
        } else {
            Err(format!("range {range} must be positive"))
        }
    }

    /// The window for an optional range; `None` is an infinite range (window exactly 1).
    pub fn from_option(range: Option<f32>) -> Self {
        // Only ranges that passed `new` reach here; an invalid one becomes infinite rather
        // than panicking.
        range.and_then(|r| Self::new(r).ok()).unwrap_or(Self {
            range: f32::INFINITY,
            inv_range_squared: 0.0,
        })
    }
}

impl RangeWindow for Bounded {
    #[inline(always)]
    fn window(&self, distance_squared: f32) -> f32 {
        let ratio_squared = distance_squared * self.inv_range_squared;
        (1.0 - ratio_squared * ratio_squared).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn window_matches_the_khr_formula() {
        let w = Bounded::new(10.0).unwrap();
        for d in [0.0f32, 1.0, 5.0, 9.0, 9.999, 10.0, 11.0, 1e6] {
            let exact = (1.0 - (d as f64 / 10.0).powi(4)).clamp(0.0, 1.0);
            let got = w.window(d * d) as f64;
            assert!((got - exact).abs() < 1e-6, "d = {d}: {got} vs {exact}");
        }
        assert_eq!(w.window(100.0), 0.0);
        assert_eq!(Bounded::from_option(None).window(1e30), 1.0);
        assert_eq!(Unbounded.window(1e30), 1.0);
        assert!(Bounded::new(0.0).is_err() && Bounded::new(f32::NAN).is_err());
    }
}
