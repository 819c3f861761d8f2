//! Point light: radiant intensity I (W/sr) equal in all directions.
//!
//! | parameter | units | default |
//! |---|---|---|
//! | position | scene units | — |
//! | intensity I | W/sr per channel | — |
//! | range | scene units | none (infinite) |
//!
//! Irradiance on a surface facing the light at distance d: `E = I · W(d) / d²`, with W the
//! range window ([`super::range`]).

use super::{Incident, PunctualLight, RangeWindow, ShadowTarget, Unlit};
use glam::Vec3;

/// A point light with range window `R`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight<R> {
    /// World-space position.
    pub position: Vec3,
    /// Radiant intensity, W/sr.
    pub intensity: Vec3,
    /// Range window.
    pub range: R,
}

impl<R: RangeWindow> PointLight<R> {
    /// A point light.
    pub fn new(position: Vec3, intensity: Vec3, range: R) -> Self {
        Self {
            position,
            intensity,
            range,
        }
    }
}

/// The direction and squared distance from `p` to `position`, or `AtLight` when the squared
/// distance is zero or not finite (no direction can be formed). Shared with spot lights.
#[inline(always)]
pub(super) fn toward(position: Vec3, p: Vec3) -> Result<(Vec3, f32), Unlit> {
    let to_light = position - p;
    let distance_squared = to_light.length_squared();
    if !(distance_squared > 0.0 && distance_squared.is_finite()) {
        return Err(Unlit::AtLight);
    }
    Ok((to_light / distance_squared.sqrt(), distance_squared))
}

impl<R: RangeWindow> PunctualLight for PointLight<R> {
    #[inline(always)]
    fn incident(&self, p: Vec3) -> Result<Incident, Unlit> {
        let (wi, distance_squared) = toward(self.position, p)?;
        let window = self.range.window(distance_squared);
        if window <= 0.0 {
            return Err(Unlit::BeyondRange);
        }
        Ok(Incident {
            wi,
            irradiance: self.intensity * (window / distance_squared),
            target: ShadowTarget::Point(self.position),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Bounded, Unbounded};
    use super::*;

    #[test]
    fn inverse_square_law() {
        let light = PointLight::new(
            Vec3::new(0.0, 3.0, 4.0),
            Vec3::new(10.0, 20.0, 30.0),
            Unbounded,
        );
        let inc = light.incident(Vec3::ZERO).unwrap();
        let expected = Vec3::new(10.0, 20.0, 30.0) / 25.0;
        assert!((inc.irradiance - expected).abs().max_element() < 1e-6);
        assert!((inc.wi - Vec3::new(0.0, 0.6, 0.8)).length() < 1e-6);
        assert_eq!(light.incident(light.position), Err(Unlit::AtLight));
    }

    #[test]
    fn range_cuts_off() {
        let light = PointLight::new(Vec3::ZERO, Vec3::ONE, Bounded::new(2.0).unwrap());
        assert_eq!(light.incident(Vec3::X * 2.0), Err(Unlit::BeyondRange));
        let e = light.incident(Vec3::X).unwrap().irradiance.x;
        assert!((e - (1.0 - 1.0 / 16.0)).abs() < 1e-6);
    }
}
