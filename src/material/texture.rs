//! Texture lookup: bilinear (or nearest) filtering with glTF's wrap modes. No MIP maps yet:
//! minified textures alias.

use crate::scene::{MagFilter, Texture, WrapMode};
use glam::{Vec2, Vec4};

/// Maps an integer texel coordinate into `[0, size)` under `mode`.
#[inline]
pub fn wrap(i: i64, size: u32, mode: WrapMode) -> usize {
    let n = size.max(1) as i64;
    let wrapped = match mode {
        WrapMode::Repeat => i.rem_euclid(n),
        WrapMode::MirroredRepeat => {
            let m = i.rem_euclid(2 * n);
            if m >= n { 2 * n - 1 - m } else { m }
        }
        WrapMode::ClampToEdge => i.clamp(0, n - 1),
    };
    wrapped as usize
}

/// The texel at integer coordinates (wrapped); white if the texel array is shorter than the
/// texture claims (the loader guarantees it is not).
#[inline]
fn texel(texture: &Texture, x: i64, y: i64) -> Vec4 {
    let ix = wrap(x, texture.width, texture.wrap_s);
    let iy = wrap(y, texture.height, texture.wrap_t);
    texture
        .texels
        .get(iy * texture.width as usize + ix)
        .copied()
        .unwrap_or(Vec4::ONE)
}

/// Filters `texture` at `uv` (glTF convention: (0, 0) is the top-left corner of the image,
/// texel centres at half-integers after scaling by the size). Non-finite `uv` reads texel 0.
pub fn sample(texture: &Texture, uv: Vec2) -> Vec4 {
    let uv = if uv.is_finite() { uv } else { Vec2::ZERO };
    let size = Vec2::new(texture.width.max(1) as f32, texture.height.max(1) as f32);
    let st = uv * size;
    match texture.mag_filter {
        MagFilter::Nearest => {
            let p = st.floor();
            texel(texture, p.x as i64, p.y as i64)
        }
        MagFilter::Linear => {
            let p = st - 0.5;
            let p0 = p.floor();
            let f = p - p0;
            let (x, y) = (p0.x as i64, p0.y as i64);
            let top = texel(texture, x, y).lerp(texel(texture, x + 1, y), f.x);
            let bottom = texel(texture, x, y + 1).lerp(texel(texture, x + 1, y + 1), f.x);
            top.lerp(bottom, f.y)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn checker() -> Texture {
        Texture {
            name: "2x2".into(),
            width: 2,
            height: 2,
            texels: vec![Vec4::ZERO, Vec4::ONE, Vec4::ONE, Vec4::ZERO],
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

    #[test]
    fn wrap_modes() {
        assert_eq!(wrap(-1, 4, WrapMode::Repeat), 3);
        assert_eq!(wrap(-1, 4, WrapMode::MirroredRepeat), 0);
        assert_eq!(wrap(5, 4, WrapMode::MirroredRepeat), 2);
        assert_eq!(wrap(9, 4, WrapMode::ClampToEdge), 3);
        assert_eq!(wrap(i64::MIN, 4, WrapMode::ClampToEdge), 0);
    }
}
