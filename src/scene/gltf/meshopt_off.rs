//! EXT_meshopt_compression without the `meshopt` feature: nothing is decoded.
//!
//! A file that *requires* the extension is refused by the extension check (it is then not
//! in `SUPPORTED_EXTENSIONS`), with advice. A file that merely *uses* it carries
//! uncompressed fallback data in its buffers, which the views already point at, so loading
//! it as plain glTF is right.

use super::LoadError;
use super::source::Origin;

/// Never a placeholder: without the decoder, fallback buffers are the data.
pub fn is_fallback(_buffer: &::gltf::Buffer<'_>) -> bool {
    false
}

/// Returns the document unchanged.
pub fn decode_views(
    document: ::gltf::Document,
    _buffers: &mut Vec<Vec<u8>>,
    _origin: Origin<'_>,
    _geometry: &mut super::limits::GeometryBudget,
) -> Result<::gltf::Document, LoadError> {
    Ok(document)
}
