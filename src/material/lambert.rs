//! The Lambertian BRDF.

use glam::Vec3;
use std::f32::consts::FRAC_1_PI;

/// Ideal diffuse reflection with albedo ρ: `f(wo, wi) = ρ / π` for both directions above the
/// surface. Its directional-hemispherical reflectance is ρ (energy conserving for ρ ≤ 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lambert {
    /// Albedo ρ per channel.
    pub albedo: Vec3,
}

impl Lambert {
    /// The BRDF value ρ/π (1/sr).
    #[inline(always)]
    pub fn f(&self) -> Vec3 {
        self.albedo * FRAC_1_PI
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ f cosθ dω over the hemisphere equals ρ (midpoint rule in θ; φ is trivial).
    #[test]
    fn reflectance_integrates_to_albedo() {
        let brdf = Lambert {
            albedo: Vec3::new(0.2, 0.5, 1.0),
        };
        let steps = 20_000;
        let dtheta = std::f64::consts::FRAC_PI_2 / steps as f64;
        let integral: f64 = (0..steps)
            .map(|i| {
                let theta = (i as f64 + 0.5) * dtheta;
                theta.cos() * theta.sin() * dtheta * 2.0 * std::f64::consts::PI
            })
            .sum();
        let r = brdf.f().as_dvec3() * integral;
        assert!((r - brdf.albedo.as_dvec3()).abs().max_element() < 1e-6);
    }
}
