//! Spot light: a point light restricted to a cone, with KHR_lights_punctual's falloff.
//!
//! | parameter | units | default |
//! |---|---|---|
//! | position | scene units | — |
//! | direction (cone axis, unit) | — | — |
//! | intensity I on the axis | W/sr per channel | — |
//! | cos inner, cos outer | cosines of the half-angles | glTF: inner 0, outer π/4 |
//! | range | scene units | none |
//!
//! With `cd` the cosine between the axis and the direction from the light to the point, the
//! falloff is the extension's reference code, exactly:
//! `scale = 1 / max(0.001, cos_inner − cos_outer)`,
//! `t = clamp((cd − cos_outer) · scale, 0, 1)`, `s = t²`.
//! So s = 1 inside the inner cone, 0 at and outside the outer cone (no shadow ray is traced
//! there), and falls off smoothly between. The 0.001 floor is the extension's guard for equal
//! cone angles. Irradiance on a facing surface: `E = I · s · W(d) / d²`.

use super::point::toward;
use super::{Incident, PunctualLight, RangeWindow, ShadowTarget, Unlit};
use glam::Vec3;

/// Smallest `cos_inner − cos_outer` the falloff divides by (KHR_lights_punctual).
pub const MIN_COS_DIFFERENCE: f32 = 0.001;

/// A spot light with range window `R`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotLight<R> {
    /// World-space position.
    pub position: Vec3,
    /// Unit axis of the cone (the direction the light shines).
    pub direction: Vec3,
    /// Radiant intensity on the axis, W/sr.
    pub intensity: Vec3,
    /// cos(inner cone angle).
    pub cos_inner: f32,
    /// cos(outer cone angle).
    pub cos_outer: f32,
    /// `1 / max(0.001, cos_inner − cos_outer)`.
    angle_scale: f32,
    /// Range window.
    pub range: R,
}

impl<R: RangeWindow> SpotLight<R> {
    /// A spot light; `direction` must be unit length.
    pub fn new(
        position: Vec3,
        direction: Vec3,
        intensity: Vec3,
        cos_inner: f32,
        cos_outer: f32,
        range: R,
    ) -> Self {
        Self {
            position,
            direction,
            intensity,
            cos_inner,
            cos_outer,
            angle_scale: 1.0 / (cos_inner - cos_outer).max(MIN_COS_DIFFERENCE),
            range,
        }
    }

    /// The angular falloff s for the unit direction `w` from the light toward the point.
    #[inline(always)]
    pub fn falloff(&self, w: Vec3) -> f32 {
        let cd = self.direction.dot(w);
        let t = ((cd - self.cos_outer) * self.angle_scale).clamp(0.0, 1.0);
        t * t
    }
}

impl<R: RangeWindow> PunctualLight for SpotLight<R> {
    #[inline(always)]
    fn incident(&self, p: Vec3) -> Result<Incident, Unlit> {
        let (wi, distance_squared) = toward(self.position, p)?;
        let falloff = self.falloff(-wi);
        if falloff <= 0.0 {
            return Err(Unlit::OutsideCone);
        }
        let window = self.range.window(distance_squared);
        if window <= 0.0 {
            return Err(Unlit::BeyondRange);
        }
        Ok(Incident {
            wi,
            irradiance: self.intensity * (falloff * window / distance_squared),
            target: ShadowTarget::Point(self.position),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::Unbounded;
    use super::*;

    #[test]
    fn falloff_is_the_khr_reference_curve() {
        let (inner, outer) = (0.2f32, 0.6f32);
        let light = SpotLight::new(
            Vec3::ZERO,
            -Vec3::Y,
            Vec3::ONE,
            inner.cos(),
            outer.cos(),
            Unbounded,
        );
        for angle in [0.0f32, 0.1, 0.2, 0.3, 0.45, 0.59, 0.6, 0.7, 3.0] {
            let w = Vec3::new(angle.sin(), -angle.cos(), 0.0);
            let cd = angle.cos() as f64;
            let (ci, co) = (inner.cos() as f64, outer.cos() as f64);
            let t = ((cd - co) / (ci - co).max(0.001)).clamp(0.0, 1.0);
            let got = light.falloff(w) as f64;
            assert!(
                (got - t * t).abs() < 1e-5,
                "angle {angle}: {got} vs {}",
                t * t
            );
        }
        let outside = Vec3::new(0.7f32.sin(), -0.7f32.cos(), 0.0);
        assert_eq!(light.incident(outside), Err(Unlit::OutsideCone));
    }
}
