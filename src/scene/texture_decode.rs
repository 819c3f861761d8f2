//! Decoding texture images (PNG, JPEG) into linear RGBA texels.
//!
//! Colour textures (base colour, emissive) are stored sRGB-encoded; they are decoded to linear
//! here, once, with the exact piecewise sRGB EOTF (IEC 61966-2-1), not a 2.2 gamma, so that
//! shading works on radiometric quantities. Data textures (metallic-roughness, normals) are
//! stored linear and only rescaled to [0, 1]. Alpha is linear in both cases.

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
    /// Linear RGBA texels, row-major, top row first.
    pub texels: Vec<Vec4>,
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
    image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(image::ImageError::IoError)?
        .into_dimensions()
}

/// Decodes a PNG or JPEG held in memory (the format is sniffed from the bytes, since glTF's
/// `mimeType` is optional and sometimes wrong). The error is the decoder's own message.
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
    let image = reader.decode()?;
    let (width, height) = (image.width(), image.height());
    // 8-bit sources go through a 256-entry table; deeper ones (16-bit PNG) are converted per
    // channel so that no precision is thrown away.
    let texels = if image.color().bytes_per_pixel() <= 4 {
        let rgba = image.to_rgba8();
        let table = channel_table_u8(space);
        rgba.pixels()
            .map(|p| {
                Vec4::new(
                    table[usize::from(p[0])],
                    table[usize::from(p[1])],
                    table[usize::from(p[2])],
                    f32::from(p[3]) / 255.0,
                )
            })
            .collect()
    } else {
        let rgba = image.to_rgba16();
        let convert = |c: u16| {
            let encoded = f32::from(c) / 65535.0;
            match space {
                ColorSpace::Srgb => srgb_to_linear(encoded),
                ColorSpace::Linear => encoded,
            }
        };
        rgba.pixels()
            .map(|p| {
                Vec4::new(
                    convert(p[0]),
                    convert(p[1]),
                    convert(p[2]),
                    f32::from(p[3]) / 65535.0,
                )
            })
            .collect()
    };
    Ok(DecodedImage {
        width,
        height,
        texels,
    })
}

/// Linear value of each 8-bit code in `space`.
fn channel_table_u8(space: ColorSpace) -> [f32; 256] {
    std::array::from_fn(|code| {
        // `code` < 256, so the conversion to f32 is exact.
        let encoded = code as f32 / 255.0;
        match space {
            ColorSpace::Srgb => srgb_to_linear(encoded),
            ColorSpace::Linear => encoded,
        }
    })
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
        assert!((decoded.texels[0].x - expected).abs() < 1e-6);
        assert_eq!(decoded.texels[0].z, 1.0);
        let linear = decode_image(&png, ColorSpace::Linear, 1 << 20).expect("decode");
        assert!((linear.texels[0].x - 32768.0 / 65535.0).abs() < 1e-7);
    }
}
