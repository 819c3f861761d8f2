//! Texture lookup for shading: delegates to [`crate::texture`], which holds the MIP maps,
//! the filters and the ray differentials. Kept so that callers that filter a [`Texture`]
//! directly at a point (no footprint) have a one-call path.

use crate::scene::Texture;
use crate::texture::image::{TexelGrid, Wrap};
use glam::{Vec2, Vec4};

pub use crate::texture::image::wrap;

/// Reconstructs `texture` at `uv` with its sampler's magnification filter on the base level
/// (no footprint, so no MIP mapping). Non-finite `uv` reads at (0, 0). A texture whose texel
/// count disagrees with its size reads white.
pub fn sample(texture: &Texture, uv: Vec2) -> Vec4 {
    let Some(grid) = TexelGrid::new(texture.width, texture.height, texture.texels.clone()) else {
        return Vec4::ONE;
    };
    let wrap = Wrap {
        s: texture.wrap_s,
        t: texture.wrap_t,
    };
    match texture.mag_filter {
        crate::scene::MagFilter::Nearest => grid.nearest(uv, wrap),
        crate::scene::MagFilter::Linear => grid.bilinear(uv, wrap),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{MagFilter, WrapMode};

    fn checker() -> Texture {
        Texture {
            name: "2x2".into(),
            width: 2,
            height: 2,
            texels: vec![Vec4::ZERO, Vec4::ONE, Vec4::ONE, Vec4::ZERO].into(),
            wrap_s: WrapMode::Repeat,
            wrap_t: WrapMode::Repeat,
            mag_filter: MagFilter::Linear,
        }
    }

    #[test]
    fn texel_centres_are_exact_and_midpoints_average() {
        let t = checker();
        assert_eq!(sample(&t, Vec2::new(0.25, 0.25)), Vec4::ZERO);
        assert_eq!(sample(&t, Vec2::new(0.75, 0.25)), Vec4::ONE);
        assert_eq!(sample(&t, Vec2::new(0.5, 0.25)), Vec4::splat(0.5));
        // Repeat: one period over is the same.
        assert_eq!(sample(&t, Vec2::new(1.25, -0.75)), Vec4::ZERO);
        assert_eq!(sample(&t, Vec2::new(f32::NAN, 0.0)), sample(&t, Vec2::ZERO));
    }
}
