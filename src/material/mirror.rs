//! The perfect mirror: a delta BRDF that reflects a fraction R of the radiance arriving from
//! the mirror direction. It is never evaluated toward a light (a delta lobe has measure zero
//! for point lights); instead a reflection ray is traced and its radiance scaled by R.

use glam::Vec3;

/// Reflects `wo` (pointing away from the surface) about the unit normal `n`.
#[inline(always)]
pub fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    2.0 * wo.dot(n) * n - wo
}

/// A mirror with reflectance R per channel (glint: `mirror_weight × ρ`; Fresnel is not
/// modelled).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mirror {
    /// Reflectance R.
    pub reflectance: Vec3,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflection_keeps_the_angle_and_the_plane() {
        let n = Vec3::new(0.0, 1.0, 0.0);
        let wo = Vec3::new(0.6, 0.8, 0.0);
        let wr = reflect(wo, n);
        assert!((wr - Vec3::new(-0.6, 0.8, 0.0)).length() < 1e-6);
        assert!((wr.dot(n) - wo.dot(n)).abs() < 1e-6);
        assert!(wr.cross(wo).dot(n).abs() < 1e-6 || wr.cross(wo).normalize().dot(n).abs() < 1e-6);
    }
}
