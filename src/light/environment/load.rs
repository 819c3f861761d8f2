//! Reading equirectangular environment images: Radiance `.hdr` (through the image crate) and
//! OpenEXR `.exr` (through the exr crate, every compression it decodes, DWAA/DWAB included).
//!
//! The format is recognised by the file's magic bytes, not its name. The size in the header
//! is checked against a pixel budget before any pixel is decoded. Texels are linear RGB
//! radiance; the rule for bad values:
//!
//! - negative channels are clamped to 0 (real HDRIs hold tiny negatives from lossy
//!   compression; negative radiance has no meaning);
//! - a non-finite channel (NaN, ±∞) refuses the whole file with [`EnvironmentError::NonFinite`]
//!   naming the first such pixel: an infinite texel would make every estimate infinite, and
//!   silently zeroing a hot spot (e.g. a clipped sun) would change the lighting unnoticed.

use super::EnvironmentError;
use glam::Vec3;
use std::io::Read;
use std::path::Path;

/// The default pixel budget: 16384 × 8192 texels (2²⁷). The light keeps about 28 bytes per
/// texel (the radiance, the sampling weight and its two CDFs), so a map at the budget needs
/// about 3.5 GiB.
pub const DEFAULT_PIXEL_BUDGET: u64 = 1 << 27;

/// An equirectangular image of linear RGB radiance, row 0 at the top (v = 0).
#[derive(Clone, Debug)]
pub struct EnvImage {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width × height` texels, row-major from the top-left.
    pub texels: Vec<Vec3>,
}

/// Reads `path` (`.hdr` or `.exr`, recognised by content), refusing images over
/// `pixel_budget` texels before decoding them.
pub fn read_env_image(path: &Path, pixel_budget: u64) -> Result<EnvImage, EnvironmentError> {
    let io = |source| EnvironmentError::Io {
        path: path.to_path_buf(),
        source,
    };
    let mut magic = [0u8; 4];
    let mut file = std::fs::File::open(path).map_err(io)?;
    let got = file.read(&mut magic).map_err(io)?;
    drop(file);
    let image = if got == 4 && magic == [0x76, 0x2f, 0x31, 0x01] {
        read_exr(path, pixel_budget)?
    } else if got >= 2 && &magic[..2] == b"#?" {
        read_hdr(path, pixel_budget)?
    } else {
        return Err(EnvironmentError::UnknownFormat {
            path: path.to_path_buf(),
        });
    };
    sanitise(path, image)
}

fn check_budget(path: &Path, width: u64, height: u64, budget: u64) -> Result<(), EnvironmentError> {
    if width == 0 || height == 0 {
        return Err(EnvironmentError::Empty {
            path: path.to_path_buf(),
        });
    }
    if width.saturating_mul(height) > budget {
        return Err(EnvironmentError::TooLarge {
            path: path.to_path_buf(),
            width,
            height,
            budget,
        });
    }
    Ok(())
}

fn read_hdr(path: &Path, budget: u64) -> Result<EnvImage, EnvironmentError> {
    use image::ImageDecoder;
    let decode = |message: String| EnvironmentError::Decode {
        path: path.to_path_buf(),
        format: "Radiance HDR",
        message,
    };
    let file = std::fs::File::open(path).map_err(|source| EnvironmentError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let decoder = image::codecs::hdr::HdrDecoder::new(std::io::BufReader::new(file))
        .map_err(|e| decode(e.to_string()))?;
    let (width, height) = decoder.dimensions();
    check_budget(path, width.into(), height.into(), budget)?;
    let rgb = image::DynamicImage::from_decoder(decoder)
        .map_err(|e| decode(e.to_string()))?
        .into_rgb32f();
    let texels = rgb
        .as_raw()
        .chunks_exact(3)
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect();
    Ok(EnvImage {
        width: width as usize,
        height: height as usize,
        texels,
    })
}

fn read_exr(path: &Path, budget: u64) -> Result<EnvImage, EnvironmentError> {
    let meta =
        exr::meta::MetaData::read_from_file(path, false).map_err(|e| EnvironmentError::Decode {
            path: path.to_path_buf(),
            format: "OpenEXR",
            message: e.to_string(),
        })?;
    let Some(header) = meta.headers.first() else {
        return Err(EnvironmentError::Empty {
            path: path.to_path_buf(),
        });
    };
    // Every layer is checked: the reader takes the first with RGB channels.
    for h in meta.headers.iter() {
        check_budget(
            path,
            h.layer_size.width() as u64,
            h.layer_size.height() as u64,
            budget,
        )?;
        // The reader sizes each block's buffer from the tile size the header declares, not
        // from the bytes present: a 783-byte file declaring 4 × 67 108 868 tiles made it
        // allocate 1.9 GB (found by fuzzing). A tile may hold no more texels than the budget.
        if let exr::meta::BlockDescription::Tiles(tiles) = &h.blocks {
            let (w, h) = (
                tiles.tile_size.width() as u64,
                tiles.tile_size.height() as u64,
            );
            if w.saturating_mul(h) > budget {
                return Err(EnvironmentError::Decode {
                    path: path.to_path_buf(),
                    format: "OpenEXR",
                    message: format!(
                        "its tiles are {w} × {h} texels, more than the {budget} texels an \
                         environment map may have; the file is corrupt"
                    ),
                });
            }
        }
    }
    let compression = header.compression;
    let pixels_error = |message: String| EnvironmentError::ExrPixels {
        path: path.to_path_buf(),
        compression: compression.to_string(),
        message,
    };
    // On this thread, not the crate's own rayon pool: the decompressors panic on some corrupt
    // blocks (fuzzing found an overflow in B44), and a panic on a rayon worker aborts the
    // process, while here it is caught and becomes this file's error.
    let image = crate::panics::catch(|| {
        use exr::prelude::traits::{ReadChannels as _, ReadLayers as _};
        exr::prelude::read()
            .no_deep_data()
            .largest_resolution_level()
            .rgba_channels(
                |size, _| EnvImage {
                    width: size.width(),
                    height: size.height(),
                    texels: vec![Vec3::ZERO; size.width() * size.height()],
                },
                |image: &mut EnvImage, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
                    // The reader only hands out positions inside the size it created the
                    // image with.
                    if let Some(t) = image.texels.get_mut(pos.y() * image.width + pos.x()) {
                        *t = Vec3::new(r, g, b);
                    }
                },
            )
            .first_valid_layer()
            .all_attributes()
            .non_parallel()
            .from_file(path)
    })
    .map_err(|panic| {
        pixels_error(format!(
            "the decoder failed on this file (it panicked: {}); the file is corrupt",
            panic.message
        ))
    })?
    .map_err(|e| pixels_error(e.to_string()))?;
    Ok(image.layer_data.channel_data.pixels)
}

/// Clamps negatives to zero and refuses non-finite texels (see the module doc).
fn sanitise(path: &Path, mut image: EnvImage) -> Result<EnvImage, EnvironmentError> {
    let mut bad = 0usize;
    let mut first = None;
    for (k, t) in image.texels.iter_mut().enumerate() {
        if !t.is_finite() {
            bad += 1;
            first.get_or_insert(k);
            continue;
        }
        *t = t.max(Vec3::ZERO);
    }
    if let Some(k) = first {
        return Err(EnvironmentError::NonFinite {
            path: path.to_path_buf(),
            count: bad,
            x: k % image.width,
            y: k / image.width,
        });
    }
    Ok(image)
}
