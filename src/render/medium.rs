//! The medium a path travels in: the minimal tracking KHR_materials_volume needs.
//!
//! A path starts outside every volume. At a transmission event through a surface whose
//! material has a volume, the side of the geometric normal decides: a ray that hit the front
//! face enters the volume (its medium becomes the material's), one that hit the back face
//! leaves it (back to the outside, glint's vacuum). Reflections and thin-walled transmission
//! keep the medium. Over a segment of length `d` inside a medium of attenuation coefficient
//! σ the throughput is multiplied by the Beer-Lambert transmittance `exp(−σ d)`, per channel.
//!
//! Nested or overlapping volumes are not tracked (one medium at a time: leaving any volume
//! returns to the outside), which is exact for disjoint closed objects such as a glass in air.
//! A path whose material has no volume never leaves [`Medium::OUTSIDE`], and the path tracer
//! tests `is_outside` once per hit only — scenes without volumes pay nothing else.

use glam::Vec3;

/// The medium of a path segment: its attenuation coefficient σ (1/scene unit, per channel).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Medium {
    /// σ; zero outside every volume.
    pub sigma: Vec3,
}

impl Medium {
    /// Outside every volume (no attenuation).
    pub const OUTSIDE: Medium = Medium { sigma: Vec3::ZERO };

    /// Whether the segment attenuates nothing.
    #[inline]
    pub fn is_outside(&self) -> bool {
        self.sigma == Vec3::ZERO
    }

    /// The transmittance `exp(−σ d)` over a segment of length `d` (an infinite segment inside
    /// an absorbing medium transmits nothing).
    #[inline]
    pub fn transmittance(&self, d: f32) -> Vec3 {
        if self.is_outside() {
            return Vec3::ONE;
        }
        let t = (-self.sigma * d.max(0.0)).exp();
        // 0 · ∞ channels (σ = 0, d = ∞) transmit fully.
        Vec3::select(self.sigma.cmpeq(Vec3::ZERO), Vec3::ONE, t)
    }

    /// The medium after a transmission through a surface whose material's volume has
    /// coefficient `volume` (`None`: thin-walled, the medium is unchanged), hit on its front
    /// face (`entering`) or its back face.
    #[inline]
    pub fn after_transmission(self, volume: Option<Vec3>, entering: bool) -> Medium {
        match volume {
            None => self,
            Some(sigma) if entering => Medium { sigma },
            Some(_) => Medium::OUTSIDE,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A slab of thickness d and coefficient σ transmits exp(−σ d): entering through the
    /// front face, one segment of length d, leaving through the back face.
    #[test]
    fn a_slab_transmits_beer_lambert() {
        let sigma = Vec3::new(0.5, 2.0, 0.0);
        let d = 0.75;
        let inside = Medium::OUTSIDE.after_transmission(Some(sigma), true);
        let beta = Vec3::ONE * inside.transmittance(d);
        let after = inside.after_transmission(Some(sigma), false);
        let expect = Vec3::new((-0.375f32).exp(), (-1.5f32).exp(), 1.0);
        assert!((beta - expect).abs().max_element() < 1e-6, "{beta}");
        assert!(after.is_outside());
        assert_eq!(after.transmittance(10.0), Vec3::ONE);
        // Thin walls do not change the medium; infinite segments inside absorb.
        assert_eq!(inside.after_transmission(None, false), inside);
        assert_eq!(
            inside.transmittance(f32::INFINITY),
            Vec3::new(0.0, 0.0, 1.0)
        );
    }
}
