//! KHR_mesh_quantization: the integer attribute layouts it allows, and one accessor reader
//! that turns any component type into `f32`.
//!
//! The `gltf` crate's typed readers assume the core spec's component types (POSITION is
//! always FLOAT there), so a quantized POSITION would be read as garbage. Every vertex,
//! morph, skin, instancing and animation accessor therefore goes through [`read`], which
//! converts each component as glTF §3.11 defines:
//!
//! - FLOAT: as is;
//! - integer, `normalized: true`: unsigned `c / (2ⁿ − 1)`, signed `max(c / (2ⁿ⁻¹ − 1), −1)`;
//! - integer, not normalized: the integer's value (the node transform or the texture
//!   transform carries the dequantization scale and offset).
//!
//! The reader handles byteStride and sparse substitution. It trusts that
//! [`accessors::check`](super::accessors::check) has already proven every byte in range; a
//! byte it cannot find reads as zero rather than panicking.

use super::accessors::Layout;
use ::gltf::accessor::{Accessor, DataType, Dimensions};

const fn layout(dimensions: Dimensions, data_type: DataType, normalized: bool) -> Layout {
    Layout {
        dimensions,
        data_type,
        normalized,
    }
}

/// Every integer type, normalized or not, plus FLOAT, for one element shape: the layouts
/// KHR_mesh_quantization allows for POSITION and TEXCOORD_n.
macro_rules! any_integer {
    ($dims:expr) => {
        &[
            layout($dims, DataType::F32, false),
            layout($dims, DataType::I8, false),
            layout($dims, DataType::I8, true),
            layout($dims, DataType::U8, false),
            layout($dims, DataType::U8, true),
            layout($dims, DataType::I16, false),
            layout($dims, DataType::I16, true),
            layout($dims, DataType::U16, false),
            layout($dims, DataType::U16, true),
        ]
    };
}

/// POSITION under KHR_mesh_quantization: FLOAT or any 8/16-bit integer, normalized or not.
pub const POSITION: &[Layout] = any_integer!(Dimensions::Vec3);
/// TEXCOORD_n under KHR_mesh_quantization: FLOAT or any 8/16-bit integer.
pub const TEXCOORD: &[Layout] = any_integer!(Dimensions::Vec2);
/// NORMAL under KHR_mesh_quantization: FLOAT, or normalized BYTE / SHORT.
pub const NORMAL: &[Layout] = &[
    layout(Dimensions::Vec3, DataType::F32, false),
    layout(Dimensions::Vec3, DataType::I8, true),
    layout(Dimensions::Vec3, DataType::I16, true),
];
/// TANGENT under KHR_mesh_quantization: FLOAT, or normalized BYTE / SHORT.
pub const TANGENT: &[Layout] = &[
    layout(Dimensions::Vec4, DataType::F32, false),
    layout(Dimensions::Vec4, DataType::I8, true),
    layout(Dimensions::Vec4, DataType::I16, true),
];
/// Morph-target POSITION deltas: FLOAT, or signed BYTE / SHORT, normalized or not.
pub const MORPH_POSITION: &[Layout] = &[
    layout(Dimensions::Vec3, DataType::F32, false),
    layout(Dimensions::Vec3, DataType::I8, false),
    layout(Dimensions::Vec3, DataType::I8, true),
    layout(Dimensions::Vec3, DataType::I16, false),
    layout(Dimensions::Vec3, DataType::I16, true),
];
/// Morph-target NORMAL and TANGENT deltas (VEC3): FLOAT, or normalized BYTE / SHORT.
pub const MORPH_DIRECTION: &[Layout] = &[
    layout(Dimensions::Vec3, DataType::F32, false),
    layout(Dimensions::Vec3, DataType::I8, true),
    layout(Dimensions::Vec3, DataType::I16, true),
];
/// EXT_mesh_gpu_instancing TRANSLATION and SCALE: FLOAT, or (with quantization) signed
/// BYTE / SHORT, normalized or not.
pub const INSTANCE_VEC3: &[Layout] = MORPH_POSITION;
/// EXT_mesh_gpu_instancing ROTATION: FLOAT, or normalized BYTE / SHORT quaternions.
pub const INSTANCE_ROTATION: &[Layout] = &[
    layout(Dimensions::Vec4, DataType::F32, false),
    layout(Dimensions::Vec4, DataType::I8, true),
    layout(Dimensions::Vec4, DataType::I16, true),
];

/// Whether the document declares KHR_mesh_quantization in `extensionsUsed`: only then may
/// vertex attributes use the integer layouts above (the core spec forbids them).
pub fn enabled(document: &::gltf::Document) -> bool {
    document
        .extensions_used()
        .any(|e| e == "KHR_mesh_quantization")
}

/// One component at the start of `bytes`, converted to `f32` as glTF defines for
/// `data_type` and `normalized` (see the module docs). Missing bytes read as zero.
pub fn component(bytes: &[u8], data_type: DataType, normalized: bool) -> f32 {
    let mut word = [0u8; 4];
    let size = data_type.size().min(4);
    for (dst, src) in word.iter_mut().zip(bytes.iter().take(size)) {
        *dst = *src;
    }
    match data_type {
        DataType::F32 => f32::from_le_bytes(word),
        DataType::U32 => u32::from_le_bytes(word) as f32,
        DataType::I8 => {
            let c = f32::from(i8::from_le_bytes([word[0]]));
            if normalized { (c / 127.0).max(-1.0) } else { c }
        }
        DataType::U8 => {
            let c = f32::from(word[0]);
            if normalized { c / 255.0 } else { c }
        }
        DataType::I16 => {
            let c = f32::from(i16::from_le_bytes([word[0], word[1]]));
            if normalized {
                (c / 32767.0).max(-1.0)
            } else {
                c
            }
        }
        DataType::U16 => {
            let c = f32::from(u16::from_le_bytes([word[0], word[1]]));
            if normalized { c / 65535.0 } else { c }
        }
    }
}

/// The bytes of the accessor's buffer view (empty if it has none or they are out of range).
fn view_slice<'b>(view: &::gltf::buffer::View<'_>, buffers: &'b [Vec<u8>]) -> &'b [u8] {
    let buffer = buffers
        .get(view.buffer().index())
        .map_or(&[][..], Vec::as_slice);
    view.offset()
        .checked_add(view.length())
        .and_then(|end| buffer.get(view.offset()..end))
        .unwrap_or(&[])
}

/// Element `index` of a tightly or stride-packed array, as `N` floats.
fn element<const N: usize>(
    bytes: &[u8],
    start: usize,
    data_type: DataType,
    normalized: bool,
) -> [f32; N] {
    let size = data_type.size();
    std::array::from_fn(|c| {
        let at = start.saturating_add(c * size);
        bytes
            .get(at..)
            .map_or(0.0, |b| component(b, data_type, normalized))
    })
}

/// Reads `accessor` as `count` elements of `N` floats, converting components as the module
/// docs say and applying sparse substitution. An accessor without a buffer view starts as
/// zeros, as glTF defines. `N` must be the accessor's component count (callers check the
/// layout first); extra components read as zero.
pub fn read<const N: usize>(accessor: &Accessor<'_>, buffers: &[Vec<u8>]) -> Vec<[f32; N]> {
    let count = accessor.count();
    let data_type = accessor.data_type();
    let normalized = accessor.normalized();
    let element_size = accessor.size();
    let mut out = Vec::with_capacity(count);
    match accessor.view() {
        Some(view) => {
            let bytes = view_slice(&view, buffers);
            let stride = view.stride().unwrap_or(element_size);
            for i in 0..count {
                let start = accessor.offset().saturating_add(i.saturating_mul(stride));
                out.push(element::<N>(bytes, start, data_type, normalized));
            }
        }
        None => out.resize(count, [0.0; N]),
    }
    if let Some(sparse) = accessor.sparse() {
        let indices = sparse.indices();
        let index_bytes = view_slice(&indices.view(), buffers);
        let index_type = match indices.index_type() {
            ::gltf::accessor::sparse::IndexType::U8 => DataType::U8,
            ::gltf::accessor::sparse::IndexType::U16 => DataType::U16,
            ::gltf::accessor::sparse::IndexType::U32 => DataType::U32,
        };
        let values = sparse.values();
        let value_bytes = view_slice(&values.view(), buffers);
        for k in 0..sparse.count() {
            let index_at = indices
                .offset()
                .saturating_add(k.saturating_mul(index_type.size()));
            let target = index_bytes
                .get(index_at..)
                .map_or(0.0, |b| component(b, index_type, false)) as usize;
            let value_at = values
                .offset()
                .saturating_add(k.saturating_mul(element_size));
            if let Some(slot) = out.get_mut(target) {
                *slot = element::<N>(value_bytes, value_at, data_type, normalized);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalized_integers_follow_the_spec_table() {
        assert_eq!(component(&[255], DataType::U8, true), 1.0);
        assert_eq!(component(&[0x81], DataType::I8, true), -1.0); // −127
        assert_eq!(component(&[0x80], DataType::I8, true), -1.0); // −128 clamps
        assert_eq!(component(&[0xff, 0x7f], DataType::I16, true), 1.0);
        assert_eq!(component(&[0x00, 0x80], DataType::I16, true), -1.0);
        assert!((component(&[0x00, 0x80], DataType::U16, true) - 32768.0 / 65535.0).abs() < 1e-7);
        assert_eq!(component(&[7], DataType::U8, false), 7.0);
        assert_eq!(component(&[0xf9], DataType::I8, false), -7.0);
        assert_eq!(component(&[0x18, 0xfc], DataType::I16, false), -1000.0);
        assert_eq!(component(&1.5f32.to_le_bytes(), DataType::F32, false), 1.5);
        // Short input reads as zero bytes, never out of bounds.
        assert_eq!(component(&[], DataType::I16, false), 0.0);
    }
}
