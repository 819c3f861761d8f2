//! STUB (replaced by the light-sampling branch): a constant environment.

use glam::{Vec2, Vec3};

/// A light at infinity surrounding the scene.
#[derive(Clone, Debug)]
pub struct EnvironmentLight {
    radiance: Vec3,
}

/// A direction drawn from the environment.
#[derive(Clone, Copy, Debug)]
pub struct EnvSample {
    /// Unit world direction toward the environment.
    pub wi: Vec3,
    /// Radiance arriving from `wi`.
    pub radiance: Vec3,
    /// Solid-angle density.
    pub pdf: f32,
}

impl EnvironmentLight {
    /// A uniform environment.
    pub fn constant(radiance: Vec3) -> Self {
        Self { radiance }
    }
    /// Radiance from `dir`.
    pub fn radiance(&self, _dir: Vec3) -> Vec3 {
        self.radiance
    }
    /// Uniform sphere sample.
    pub fn sample(&self, u: Vec2) -> Option<EnvSample> {
        let z = 1.0 - 2.0 * u.x;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * std::f32::consts::PI * u.y;
        Some(EnvSample {
            wi: Vec3::new(r * phi.cos(), z, r * phi.sin()),
            radiance: self.radiance,
            pdf: 1.0 / (4.0 * std::f32::consts::PI),
        })
    }
    /// Density of `sample`.
    pub fn pdf(&self, _dir: Vec3) -> f32 {
        1.0 / (4.0 * std::f32::consts::PI)
    }
}
