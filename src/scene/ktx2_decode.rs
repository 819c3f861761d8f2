//! Decoding KTX2 images with Basis Universal payloads (KHR_texture_basisu) into compact
//! texels ([`Texels`]).
//!
//! The container is read with the `ktx2` crate (header, Data Format Descriptor, key/value
//! metadata) and checked against what KHR_texture_basisu allows before anything is
//! transcoded: a 2D image (no depth, array layers or cube faces) whose payload is ETC1S with
//! BasisLZ supercompression or UASTC LDR with none or Zstandard. Its size is checked against
//! the caller's texel budget from the header, before the transcoder allocates. The base level
//! is then transcoded to RGBA8 by the pure-Rust `basisu` transcoder and stored like an 8-bit
//! PNG (see [`super::texture_decode`]): the file's own smaller levels are not used, because
//! glint builds one MIP chain per texture the same way for every image format, and a
//! file's levels are each lossily encoded on their own.
//!
//! Colour space follows the glTF use of the texture (base colour and emissive sRGB, data
//! maps linear), as for PNG and JPEG. KHR_texture_basisu requires the DFD transfer function to
//! agree with that use; when it does not, the use wins and a note says so.
//!
//! Orientation: glTF puts the image's first texel at the top left, which is KTX2's `rd`
//! (the default when `KTXorientation` is absent, and the only value KHR_texture_basisu
//! allows). A file that declares another orientation is flipped to `rd`, with a note.

use super::texels::Texels;
use super::texture_decode::{ColorSpace, DecodedImage, u8_texels};

/// Why a KTX2 image cannot be used. Each message says what is wrong and how to fix it.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum Ktx2Error {
    /// The bytes are not a well-formed KTX2 container (wrong magic, truncated, sections out
    /// of range).
    #[error("not a readable KTX2 file ({0}); re-export the texture")]
    Container(String),
    /// The container holds something other than a Basis Universal ETC1S or UASTC payload.
    #[error(
        "{0}; KHR_texture_basisu allows only Basis Universal ETC1S (BasisLZ) and UASTC payloads (re-encode it with `basisu` or `toktx --encode`)"
    )]
    NotBasis(String),
    /// The container is not a single 2D image.
    #[error("{0}; KHR_texture_basisu material textures must be single 2D images")]
    Layout(String),
    /// The base level is larger than the texel budget.
    #[error(
        "it is {width}×{height} = {pixels} texels, over the budget of {max} \
         (raise it with --max-texture-pixels {pixels}, or downscale the image)"
    )]
    TooLarge {
        /// Width from the header.
        width: u32,
        /// Height from the header.
        height: u32,
        /// width × height.
        pixels: u64,
        /// The budget.
        max: u64,
    },
    /// The transcoder panicked on the payload (a corrupt file it does not check for); the
    /// caught panic's message and location.
    #[error(
        "the Basis Universal transcoder failed on a corrupt payload ({0}); re-export the texture"
    )]
    TranscoderPanicked(crate::panics::Panic),
    /// The payload does not transcode (corrupt or truncated level data or codebooks).
    #[error("the Basis Universal payload does not transcode ({0}); re-export the texture")]
    Transcode(String),
}

/// The payload kinds KHR_texture_basisu allows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BasisPayload {
    /// ETC1S with BasisLZ supercompression (lossy, small).
    Etc1s,
    /// UASTC LDR 4×4, optionally Zstandard-supercompressed (near-lossless).
    Uastc {
        /// Whether the levels are Zstandard frames.
        zstd: bool,
    },
}

/// What the header says about a KTX2 image, read without transcoding it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Ktx2Info {
    /// Base-level width in texels.
    pub width: u32,
    /// Base-level height in texels.
    pub height: u32,
    /// ETC1S or UASTC.
    pub payload: BasisPayload,
    /// The colour space the DFD's transfer function names (`None` when it names neither
    /// linear nor sRGB).
    pub transfer: Option<ColorSpace>,
    /// Whether the DFD marks the colour as premultiplied by alpha.
    pub premultiplied: bool,
    /// `KTXorientation` (e.g. `rd`), when present.
    pub orientation: Option<String>,
}

/// Whether `bytes` start with the KTX2 file identifier.
pub fn is_ktx2(bytes: &[u8]) -> bool {
    bytes.starts_with(&::ktx2::MAGIC)
}

/// Reads and checks the container's header, DFD and metadata without transcoding.
pub fn probe(bytes: &[u8]) -> Result<Ktx2Info, Ktx2Error> {
    let reader = read_container(bytes)?;
    let header = reader.header();
    if let Some(format) = header.format {
        return Err(Ktx2Error::NotBasis(format!(
            "its vkFormat is {} ({format:?}), a GPU format rather than VK_FORMAT_UNDEFINED",
            format.value()
        )));
    }
    if header.pixel_height == 0 || header.pixel_depth != 0 {
        return Err(Ktx2Error::Layout(format!(
            "it is {}-dimensional (pixelHeight {}, pixelDepth {})",
            if header.pixel_height == 0 { 1 } else { 3 },
            header.pixel_height,
            header.pixel_depth
        )));
    }
    if header.layer_count > 1 || header.face_count != 1 {
        return Err(Ktx2Error::Layout(format!(
            "it has {} array layers and {} faces",
            header.layer_count, header.face_count
        )));
    }
    let model = reader.color_model();
    let scheme = header.supercompression_scheme;
    let payload = match (model, scheme) {
        (Some(::ktx2::ColorModel::ETC1S), Some(::ktx2::SupercompressionScheme::BasisLZ)) => {
            BasisPayload::Etc1s
        }
        (Some(::ktx2::ColorModel::UASTC), None) => BasisPayload::Uastc { zstd: false },
        (Some(::ktx2::ColorModel::UASTC), Some(::ktx2::SupercompressionScheme::Zstandard)) => {
            BasisPayload::Uastc { zstd: true }
        }
        (Some(model @ (::ktx2::ColorModel::ETC1S | ::ktx2::ColorModel::UASTC)), scheme) => {
            return Err(Ktx2Error::NotBasis(format!(
                "its DFD colour model is {model:?} with supercompression {}, a combination KHR_texture_basisu \
                 does not allow (ETC1S needs BasisLZ; UASTC needs none or Zstandard)",
                describe_scheme(scheme)
            )));
        }
        (model, _) => {
            return Err(Ktx2Error::NotBasis(format!(
                "its DFD colour model is {}",
                model.map_or_else(|| "missing or unknown".to_string(), |m| format!("{m:?}"))
            )));
        }
    };
    let transfer = match reader.transfer_function() {
        Some(::ktx2::TransferFunction::SRGB) => Some(ColorSpace::Srgb),
        Some(::ktx2::TransferFunction::Linear) => Some(ColorSpace::Linear),
        _ => None,
    };
    let orientation = reader
        .key_value_data()
        .find(|(key, _)| *key == "KTXorientation")
        .map(|(_, value)| {
            let text = value.split(|&b| b == 0).next().unwrap_or_default();
            String::from_utf8_lossy(text).into_owned()
        });
    Ok(Ktx2Info {
        width: header.pixel_width,
        height: header.pixel_height,
        payload,
        transfer,
        premultiplied: reader.is_alpha_premultiplied().unwrap_or(false),
        orientation,
    })
}

/// Checks the base level's stored size against the header's dimensions. The transcoder
/// inflates a Zstandard level into a buffer of the length the level index declares, and
/// indexes plain levels by block: both must be the base level's exact size (16 bytes per
/// 4×4 UASTC block), or a hostile file could ask for any allocation. (BasisLZ levels are
/// bounded by the file: their slices are located through the global data.)
fn check_base_level(bytes: &[u8], info: &Ktx2Info) -> Result<(), Ktx2Error> {
    let BasisPayload::Uastc { zstd } = info.payload else {
        return Ok(());
    };
    let reader = read_container(bytes)?;
    let blocks = u64::from(info.width.div_ceil(4)) * u64::from(info.height.div_ceil(4));
    let want = blocks * 16;
    let level = reader
        .levels()
        .next()
        .ok_or_else(|| Ktx2Error::Container("it has no levels".to_string()))?;
    let declared = if zstd {
        level.uncompressed_byte_length
    } else {
        level.data.len() as u64
    };
    if declared != want {
        return Err(Ktx2Error::Container(format!(
            "its base level holds {declared} bytes of UASTC blocks, but a {}×{} image has {want}",
            info.width, info.height
        )));
    }
    Ok(())
}

/// Parses the container with the `ktx2` crate, after refusing the one malformation that
/// crate panics on (see [`check_dfd_block_dimensions`]).
fn read_container(bytes: &[u8]) -> Result<::ktx2::Reader<&[u8]>, Ktx2Error> {
    check_dfd_block_dimensions(bytes)?;
    check_kvd_alignment(bytes)?;
    ::ktx2::Reader::new(bytes).map_err(|err| Ktx2Error::Container(err.to_string()))
}

/// Refuses a basic DFD block whose `texelBlockDimension` bytes hold 255: the block
/// dimension is stored minus one, and `ktx2` 0.5 adds the one back in a `u8` and unwraps a
/// `NonZeroU8`, which panics on 255 (found by `tests/textures/ktx2.rs`'s corruption test). The walk
/// follows the crate's own: the DFD starts with its total length, then blocks of an 8-byte
/// header (vendor id and descriptor type, version, block size) and their data. Anything it
/// cannot follow is left for the crate to refuse.
fn check_dfd_block_dimensions(bytes: &[u8]) -> Result<(), Ktx2Error> {
    let word = |at: usize| -> Option<u32> {
        Some(u32::from_le_bytes(
            bytes.get(at..at.checked_add(4)?)?.try_into().ok()?,
        ))
    };
    let (Some(offset), Some(length)) = (word(48), word(52)) else {
        return Ok(());
    };
    let (offset, length) = (offset as usize, length as usize);
    let Some(dfd) = offset
        .checked_add(length)
        .and_then(|end| bytes.get(offset..end))
        .and_then(|dfd| dfd.get(4..))
    else {
        return Ok(());
    };
    let mut rest = dfd;
    while rest.len() >= 8 {
        let kind = u32::from_le_bytes([rest[0], rest[1], rest[2], rest[3]]);
        let size = usize::from(u16::from_le_bytes([rest[6], rest[7]]));
        // Vendor 0, type 0: the Khronos basic block (whatever its version; refusing more
        // than the crate would parse is harmless here).
        if kind == 0 && rest.get(12..16).is_some_and(|d| d.contains(&255)) {
            return Err(Ktx2Error::Container(
                "its data format descriptor declares a texel block dimension of 256".to_string(),
            ));
        }
        if size == 0 || size > rest.len() {
            break;
        }
        rest = &rest[size..];
    }
    Ok(())
}

/// Refuses key/value data that does not end on a 4-byte boundary. KTX2 pads every entry to 4
/// bytes and the section starts aligned, so a valid file always passes; the `basisu`
/// transcoder's metadata scan rounds its position up to 4 and subtracts it from the end,
/// which underflows (a panic) when the end is unaligned (found by `tests/textures/ktx2.rs`).
fn check_kvd_alignment(bytes: &[u8]) -> Result<(), Ktx2Error> {
    let word = |at: usize| -> Option<u32> {
        Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?))
    };
    if let (Some(offset), Some(length)) = (word(56), word(60))
        && length > 0
        && !(u64::from(offset) + u64::from(length)).is_multiple_of(4)
    {
        return Err(Ktx2Error::Container(format!(
            "its key/value data ends at byte {}, not on a 4-byte boundary",
            u64::from(offset) + u64::from(length)
        )));
    }
    Ok(())
}

fn describe_scheme(scheme: Option<::ktx2::SupercompressionScheme>) -> String {
    scheme.map_or_else(|| "none".to_string(), |s| format!("{s:?}"))
}

/// Decodes a KTX2 / Basis Universal image held in memory to texels read in `space`.
///
/// `max_pixels` bounds the base level's texel count; it is checked from the header before
/// the transcoder allocates anything. Returns the image and notes about what was adjusted
/// (a DFD transfer function that disagrees with `space`, a non-`rd` orientation, a
/// premultiplied-alpha flag), for the caller to pass on as warnings.
pub fn decode_ktx2(
    bytes: &[u8],
    space: ColorSpace,
    max_pixels: u64,
) -> Result<(DecodedImage, Vec<String>), Ktx2Error> {
    let info = probe(bytes)?;
    let (width, height) = (info.width, info.height);
    let pixels = u64::from(width) * u64::from(height);
    if pixels > max_pixels {
        return Err(Ktx2Error::TooLarge {
            width,
            height,
            pixels,
            max: max_pixels,
        });
    }
    check_base_level(bytes, &info)?;
    let mut notes = Vec::new();
    if let Some(declared) = info.transfer.filter(|&t| t != space) {
        notes.push(format!(
            "its DFD transfer function says {} but glTF uses the texture as {} data; decoded as {}",
            space_name(declared),
            space_name(space),
            space_name(space)
        ));
    }
    if info.premultiplied {
        notes.push(
            "its DFD marks alpha as premultiplied, which KHR_texture_basisu forbids for material \
             textures; the colour is used as stored"
                .to_string(),
        );
    }
    let expected = match info.payload {
        BasisPayload::Etc1s => ::basisu::SourceFormat::Etc1s,
        BasisPayload::Uastc { .. } => ::basisu::SourceFormat::UastcLdr,
    };
    // The transcoder is young; the checks above and in `read_container` refuse the hostile
    // inputs it is known to panic on, and any other panic it raises on a corrupt payload is
    // turned into an error here rather than taking the process down (it only reads `bytes`
    // and returns a new buffer, so nothing is left half-updated).
    let transcoded = crate::panics::catch(|| {
        let transcoder =
            ::basisu::Transcoder::new(bytes).map_err(|err| Ktx2Error::Transcode(describe(&err)))?;
        if transcoder.source_format() != expected {
            return Err(Ktx2Error::NotBasis(format!(
                "the DFD says {:?} but the payload is {:?}",
                info.payload,
                transcoder.source_format()
            )));
        }
        transcoder
            .transcode(
                0,
                ::basisu::TargetFormat::Rgba32,
                ::basisu::DecodeFlags::NONE,
            )
            .map_err(|err| Ktx2Error::Transcode(describe(&err)))
    });
    let rgba = transcoded.map_err(Ktx2Error::TranscoderPanicked)??;
    // `pixels` is at most `max_pixels`, which the caller sized to fit memory.
    let texel_count = usize::try_from(pixels).unwrap_or(usize::MAX);
    if rgba.len() != texel_count.saturating_mul(4) {
        return Err(Ktx2Error::Transcode(format!(
            "the base level decoded to {} bytes, not {width}×{height}×4",
            rgba.len()
        )));
    }
    let rgba = match info.orientation.as_deref() {
        None | Some("rd") => rgba,
        Some(orientation) => {
            let (flip_x, flip_y) = orientation_flips(orientation);
            notes.push(format!(
                "its KTXorientation is \"{orientation}\" (KHR_texture_basisu requires \"rd\"); the image \
                 is flipped to glTF's top-left origin"
            ));
            flip(rgba, width as usize, height as usize, flip_x, flip_y)
        }
    };
    let texels: Texels = u8_texels(4, space, rgba);
    Ok((
        DecodedImage {
            width,
            height,
            texels,
        },
        notes,
    ))
}

fn space_name(space: ColorSpace) -> &'static str {
    match space {
        ColorSpace::Srgb => "sRGB",
        ColorSpace::Linear => "linear",
    }
}

/// Which axes to mirror to turn a `KTXorientation` into `rd`: its first letter is the
/// direction of increasing x (`r` or `l`), its second that of increasing y (`d` or `u`).
fn orientation_flips(orientation: &str) -> (bool, bool) {
    let mut letters = orientation.chars();
    let flip_x = letters.next() == Some('l');
    let flip_y = letters.next() == Some('u');
    (flip_x, flip_y)
}

/// Mirrors an RGBA8 image (`width × height` texels, rows top first) about the chosen axes.
fn flip(rgba: Vec<u8>, width: usize, height: usize, flip_x: bool, flip_y: bool) -> Vec<u8> {
    if !flip_x && !flip_y {
        return rgba;
    }
    let row = width * 4;
    let mut out = Vec::with_capacity(rgba.len());
    for y in 0..height {
        let source_y = if flip_y { height - 1 - y } else { y };
        let source = &rgba[source_y * row..(source_y + 1) * row];
        if flip_x {
            for texel in source.chunks_exact(4).rev() {
                out.extend_from_slice(texel);
            }
        } else {
            out.extend_from_slice(source);
        }
    }
    out
}

/// The transcoder's error in words (its type has no `Display`).
fn describe(err: &::basisu::Error) -> String {
    match err {
        ::basisu::Error::InvalidData => "corrupt or unsupported data".to_string(),
        ::basisu::Error::Truncated => "truncated, or an offset is out of range".to_string(),
        ::basisu::Error::ZstdRequired => {
            "Zstandard-compressed levels need the transcoder's zstd support".to_string()
        }
        other => format!("{other:?}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orientation_letters_pick_the_mirrored_axes() {
        assert_eq!(orientation_flips("rd"), (false, false));
        assert_eq!(orientation_flips("ru"), (false, true));
        assert_eq!(orientation_flips("ld"), (true, false));
        assert_eq!(orientation_flips("lu"), (true, true));
    }

    /// A 2×2 image whose texels are numbered 0..4 row-major comes back mirrored.
    #[test]
    fn flip_mirrors_rows_and_columns() {
        let image: Vec<u8> = (0u8..4).flat_map(|i| [i, 0, 0, 255]).collect();
        let red = |v: &[u8]| v.chunks_exact(4).map(|t| t[0]).collect::<Vec<_>>();
        assert_eq!(red(&flip(image.clone(), 2, 2, false, true)), [2, 3, 0, 1]);
        assert_eq!(red(&flip(image.clone(), 2, 2, true, false)), [1, 0, 3, 2]);
        assert_eq!(red(&flip(image, 2, 2, true, true)), [3, 2, 1, 0]);
    }

    /// A basic DFD block with a texel block dimension byte of 255 is refused before the
    /// `ktx2` crate (which panics on it) parses the container.
    #[test]
    fn a_dfd_block_dimension_of_256_is_refused_not_a_panic() {
        let mut file = ::ktx2::MAGIC.to_vec();
        file.resize(80, 0);
        file[20..24].copy_from_slice(&4u32.to_le_bytes()); // width
        file[24..28].copy_from_slice(&4u32.to_le_bytes()); // height
        file[36..40].copy_from_slice(&1u32.to_le_bytes()); // faces
        let dfd_offset = 104u32; // after the header and one 24-byte level index entry
        file[48..52].copy_from_slice(&dfd_offset.to_le_bytes());
        file[52..56].copy_from_slice(&(4u32 + 24).to_le_bytes());
        file.resize(dfd_offset as usize, 0);
        file.extend_from_slice(&28u32.to_le_bytes()); // DFD total size
        file.extend_from_slice(&[0, 0, 0, 0, 2, 0, 24, 0]); // basic block header, size 24
        file.extend_from_slice(&[166, 1, 2, 0, 255, 3, 0, 0]); // model..flags, dims
        file.extend_from_slice(&[0; 8]);
        file.extend_from_slice(&[0; 16]);
        file.extend_from_slice(&[0; 16]); // the crate wants bytes after the DFD
        let err = probe(&file).expect_err("refused");
        assert!(err.to_string().contains("texel block dimension"), "{err}");
    }

    #[test]
    fn wrong_magic_and_truncation_are_container_errors() {
        assert!(matches!(
            probe(b"not a ktx2 file at all"),
            Err(Ktx2Error::Container(_))
        ));
        let mut header = ::ktx2::MAGIC.to_vec();
        header.extend_from_slice(&[0; 20]);
        assert!(is_ktx2(&header));
        assert!(matches!(probe(&header), Err(Ktx2Error::Container(_))));
    }
}
