//! Colour helpers shared by every layer: glint renders linear Rec. 709 RGB radiometry.

use glam::Vec3;

/// Rec. 709 relative-luminance weights of linear RGB.
pub const LUMINANCE: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

/// Relative luminance (Rec. 709) of a linear RGB value: the scalar that light powers, lobe
/// choices and error metrics weigh colours by.
#[inline]
pub fn luminance(rgb: Vec3) -> f32 {
    rgb.dot(LUMINANCE)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_has_unit_luminance() {
        assert!((luminance(Vec3::ONE) - 1.0).abs() < 1e-6);
        assert_eq!(luminance(Vec3::ZERO), 0.0);
    }
}
