//! Decoding texture images (PNG, JPEG, WebP) into compact texels ([`Texels`]) that read as
//! linear RGBA.
//!
//! Colour textures (base colour, emissive) are stored sRGB-encoded; they are decoded to linear
//! with the exact piecewise sRGB EOTF (IEC 61966-2-1), not a 2.2 gamma, so that shading works
//! on radiometric quantities. The codes are kept as the file had them (8 or 16 bits) and the
//! EOTF is applied through a table when a texel is read. Data textures (metallic-roughness, normals) are
//! stored linear and only rescaled to [0, 1]. Alpha is linear in both cases.

use super::texels::Texels;
use glam::Vec4;

/// How the numbers in an image file encode colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ColorSpace {
    /// sRGB-encoded RGB (colour textures); alpha linear.
    Srgb,
    /// Linear values (data textures).
    Linear,
}

/// An image decoded to linear texels, before sampler settings are attached.
#[derive(Clone, Debug, PartialEq)]
pub struct DecodedImage {
    /// Width in texels (≥ 1).
    pub width: u32,
    /// Height in texels (≥ 1).
    pub height: u32,
    /// Texels at the file's precision, row-major, top row first (read as linear RGBA).
    pub texels: Texels,
}

/// The exact sRGB electro-optical transfer function: encoded value in [0, 1] to linear.
///
/// The linear segment below 0.04045 matters: a 2.2 power law is off by up to 10 % for dark
/// texels.
pub fn srgb_to_linear(encoded: f32) -> f32 {
    if encoded <= 0.04045 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

/// Width and height from the image's header, without decoding it (the format is sniffed).
pub fn image_dimensions(bytes: &[u8]) -> Result<(u32, u32), image::ImageError> {
    // Header parsing is decoder code too: a panic there is the image's error (see
    // `decode_image`).
    crate::panics::catch(|| {
        image::ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .map_err(image::ImageError::IoError)?
            .into_dimensions()
    })
    .map_err(|panic| {
        image::ImageError::IoError(std::io::Error::other(format!(
            "the decoder failed on this file's header (it panicked: {}); the file is corrupt, \
             re-export it",
            panic.message
        )))
    })?
}

/// Decodes a PNG or JPEG held in memory (the format is sniffed from the bytes, since glTF's
/// `mimeType` is optional and sometimes wrong). The error is the decoder's own message; a
/// panic inside the decoder is caught and becomes the error.
///
/// `max_pixels` bounds the texel count, checked from the header before any texel memory is
/// allocated; the decoder's own allocation is bounded to match (8 bytes per texel covers
/// 16-bit RGBA).
pub fn decode_image(
    bytes: &[u8],
    space: ColorSpace,
    max_pixels: u64,
) -> Result<DecodedImage, image::ImageError> {
    let (width, height) = image_dimensions(bytes)?;
    if u64::from(width) * u64::from(height) > max_pixels {
        return Err(image::ImageError::Limits(
            image::error::LimitError::from_kind(image::error::LimitErrorKind::DimensionError),
        ));
    }
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(image::ImageError::IoError)?;
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(max_pixels.saturating_mul(8).max(1 << 20));
    reader.limits(limits);
    // The decoders panic on some corrupt files (fuzzing found an index out of range in the
    // png crate's palette expansion and an overflow in zune-jpeg's MCU arithmetic); they only
    // read `bytes` and return a new image, so a panic is this image's decode error.
    let image = crate::panics::catch(|| reader.decode()).map_err(|panic| {
        image::ImageError::IoError(std::io::Error::other(format!(
            "the decoder failed on this file (it panicked: {}); the file is corrupt, re-export it",
            panic.message
        )))
    })??;
    let (width, height) = (image.width(), image.height());
    Ok(DecodedImage {
        width,
        height,
        texels: compact_texels(image, space),
    })
}

/// The decoded image's texels at the precision it was stored with (8 or 16 bits, or float),
/// in the fewest channels that hold it exactly: grey when R = G = B everywhere, no alpha
/// when every texel is opaque. The values read back are the ones an RGBA decode gives.
fn compact_texels(image: image::DynamicImage, space: ColorSpace) -> Texels {
    use image::DynamicImage as D;
    match image {
        D::ImageLuma8(b) => u8_texels(1, space, b.into_raw()),
        D::ImageLumaA8(b) => u8_texels(2, space, b.into_raw()),
        D::ImageRgb8(b) => u8_texels(3, space, b.into_raw()),
        D::ImageRgba8(b) => u8_texels(4, space, b.into_raw()),
        D::ImageLuma16(b) => u16_texels(1, space, b.into_raw()),
        D::ImageLumaA16(b) => u16_texels(2, space, b.into_raw()),
        D::ImageRgb16(b) => u16_texels(3, space, b.into_raw()),
        D::ImageRgba16(b) => u16_texels(4, space, b.into_raw()),
        D::ImageRgb32F(_) | D::ImageRgba32F(_) => {
            // Float images are linear already: the colour space does not apply.
            let texels = image
                .into_rgba32f()
                .pixels()
                .map(|p| Vec4::from_array(p.0))
                .collect();
            Texels::from_linear(texels)
        }
        // Formats added to the image crate later: through 8 or 16 bits as their depth says.
        other if other.color().bytes_per_pixel() <= 4 => {
            u8_texels(4, space, other.into_rgba8().into_raw())
        }
        other => u16_texels(4, space, other.into_rgba16().into_raw()),
    }
}

/// Drops what the codes do not need: alpha that is everywhere the maximum code, and G, B
/// when they equal R everywhere. Returns the new channel count and codes.
fn shrink_layout<T: Copy + PartialEq>(channels: u8, max: T, codes: Vec<T>) -> (u8, Vec<T>) {
    let n = usize::from(channels);
    let has_alpha = n == 2 || n == 4;
    let colour = if n >= 3 { 3 } else { 1 };
    let opaque = has_alpha && codes.chunks_exact(n).all(|t| t[n - 1] == max);
    let grey = colour == 3 && codes.chunks_exact(n).all(|t| t[0] == t[1] && t[1] == t[2]);
    let keep: &[usize] = match (grey || colour == 1, has_alpha && !opaque) {
        (true, false) => &[0],
        (true, true) => &[0, n - 1],
        (false, false) => &[0, 1, 2],
        (false, true) => return (channels, codes),
    };
    if keep.len() == n {
        return (channels, codes);
    }
    let out = codes
        .chunks_exact(n)
        .flat_map(|t| keep.iter().map(move |&k| t[k]))
        .collect();
    // `keep` has 1 to 3 entries.
    (keep.len() as u8, out)
}

/// 8-bit codes with `channels` samples per texel, in the fewest channels that hold them exactly
/// (as [`shrink_layout`] says).
pub(crate) fn u8_texels(channels: u8, space: ColorSpace, codes: Vec<u8>) -> Texels {
    let (channels, codes) = shrink_layout(channels, u8::MAX, codes);
    // Callers (the image crate's buffers, the KTX2 transcoder's checked output) hold whole
    // pixels of `channels` samples.
    Texels::from_u8(channels, space, codes).unwrap_or_else(|| Texels::from_linear(Vec::new()))
}

fn u16_texels(channels: u8, space: ColorSpace, codes: Vec<u16>) -> Texels {
    let (channels, codes) = shrink_layout(channels, u16::MAX, codes);
    // As for `u8_texels`.
    Texels::from_u16(channels, space, codes).unwrap_or_else(|| Texels::from_linear(Vec::new()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The EOTF's two pieces meet at 0.04045 (continuity), and it maps 0 and 1 to themselves.
    #[test]
    fn srgb_eotf_is_continuous_and_fixes_endpoints() {
        let knee = 0.04045_f32;
        let below = knee / 12.92;
        let above = ((knee + 0.055) / 1.055).powf(2.4);
        assert!((below - above).abs() < 1e-6, "{below} vs {above}");
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
    }

    /// A 16-bit PNG keeps its precision: code 32768 decodes to the EOTF of 32768/65535, not to
    /// that of the nearest 8-bit code.
    #[test]
    fn sixteen_bit_png_keeps_precision() {
        let image = image::ImageBuffer::<image::Rgba<u16>, _>::from_raw(
            1,
            1,
            vec![32768u16, 0, 65535, 65535],
        )
        .expect("1x1 buffer");
        let mut png = Vec::new();
        image::DynamicImage::ImageRgba16(image)
            .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .expect("encode");
        let decoded = decode_image(&png, ColorSpace::Srgb, 1 << 20).expect("decode");
        let expected = srgb_to_linear(32768.0 / 65535.0);
        assert!((decoded.texels.texel(0).x - expected).abs() < 1e-6);
        assert_eq!(decoded.texels.texel(0).z, 1.0);
        let linear = decode_image(&png, ColorSpace::Linear, 1 << 20).expect("decode");
        assert!((linear.texels.texel(0).x - 32768.0 / 65535.0).abs() < 1e-7);
    }
}
