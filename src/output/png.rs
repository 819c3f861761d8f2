//! PNG output: exposure, the sRGB transfer function, clipping, quantisation.
//!
//! For each channel of linear radiance L: `v = L · 2^EV`, clipped to [0, 1] (NaN → 0), then
//! encoded with the exact piecewise sRGB curve (IEC 61966-2-1):
//! `12.92·v` for `v ≤ 0.0031308`, else `1.055·v^(1/2.4) − 0.055`; then rounded to the nearest
//! of 255 (8-bit) or 65535 (16-bit) levels. No tone mapping: radiance above 1 clips.

use super::{OutputError, write_atomically};
use crate::render::Image;
use glam::Vec3;
use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder};
use std::path::Path;

/// Bits per channel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PngDepth {
    /// 8 bits per channel.
    #[default]
    Eight,
    /// 16 bits per channel.
    Sixteen,
}

/// How radiance becomes PNG pixel values.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PngOptions {
    /// Exposure in stops: radiance is multiplied by 2^EV before encoding.
    pub exposure_ev: f32,
    /// Bits per channel.
    pub depth: PngDepth,
}

/// Linear value at which the sRGB curve switches from its linear to its power segment.
pub const SRGB_LINEAR_THRESHOLD: f32 = 0.003_130_8;

/// The sRGB encoding of a linear value, clipped to [0, 1] first (NaN → 0).
#[inline]
pub fn srgb_encode(linear: f32) -> f32 {
    // NaN (a bug upstream, never a colour) encodes as 0 rather than propagating.
    let v = if linear.is_nan() {
        0.0
    } else {
        linear.clamp(0.0, 1.0)
    };
    if v <= SRGB_LINEAR_THRESHOLD {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// A linear value as an 8-bit sRGB code.
#[inline]
pub fn srgb8(linear: f32) -> u8 {
    (srgb_encode(linear) * 255.0).round() as u8
}

/// A linear value as a 16-bit sRGB code.
#[inline]
pub fn srgb16(linear: f32) -> u16 {
    (srgb_encode(linear) * 65535.0).round() as u16
}

/// Writes `image` (linear radiance) as an sRGB PNG, atomically.
pub fn write_png(path: &Path, image: &Image<Vec3>, options: PngOptions) -> Result<(), OutputError> {
    let expected = image.width as usize * image.height as usize;
    if image.pixels.len() != expected || expected == 0 {
        return Err(OutputError::Encode {
            path: path.to_path_buf(),
            format: "PNG",
            message: format!(
                "the image has {} pixels for {}×{}",
                image.pixels.len(),
                image.width,
                image.height
            ),
        });
    }
    let scale = options.exposure_ev.exp2();
    let values = image.pixels.iter().flat_map(|p| (*p * scale).to_array());
    let (bytes, color) = match options.depth {
        PngDepth::Eight => (
            values.map(srgb8).collect::<Vec<u8>>(),
            ExtendedColorType::Rgb8,
        ),
        // The encoder takes 16-bit samples in native byte order and swaps them itself.
        PngDepth::Sixteen => (
            values.flat_map(|v| srgb16(v).to_ne_bytes()).collect(),
            ExtendedColorType::Rgb16,
        ),
    };
    write_atomically(path, |writer| {
        PngEncoder::new(writer)
            .write_image(&bytes, image.width, image.height, color)
            .map_err(|e| OutputError::Encode {
                path: path.to_path_buf(),
                format: "PNG",
                message: e.to_string(),
            })
    })
}
