//! Directional light: parallel light from infinitely far away.
//!
//! | parameter | units | default |
//! |---|---|---|
//! | direction of travel (unit) | — | — |
//! | irradiance E on a surface facing the light | W/m² per channel | — |
//!
//! Shadow rays go to infinity (`tfar = ∞`).

use super::{Incident, PunctualLight, ShadowTarget, Unlit};
use glam::Vec3;

/// A directional light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionalLight {
    /// Unit direction toward the light (the opposite of the direction light travels).
    pub to_light: Vec3,
    /// Irradiance on a surface facing the light, W/m².
    pub irradiance: Vec3,
}

impl DirectionalLight {
    /// A light travelling along the unit vector `direction`.
    pub fn new(direction: Vec3, irradiance: Vec3) -> Self {
        Self {
            to_light: -direction,
            irradiance,
        }
    }
}

impl PunctualLight for DirectionalLight {
    #[inline(always)]
    fn incident(&self, _p: Vec3) -> Result<Incident, Unlit> {
        Ok(Incident {
            wi: self.to_light,
            irradiance: self.irradiance,
            target: ShadowTarget::Infinity,
        })
    }
}
