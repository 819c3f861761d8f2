//! Checks an accessor before the `gltf` crate's reader touches it.
//!
//! The crate's reader trusts the file: a zero `count`, a stride shorter than an element, or a
//! component type the semantic does not allow make it panic or read garbage. Every accessor a
//! primitive uses goes through [`check`] first, so bad files become errors naming the
//! primitive, the attribute and the accessor.

use super::LoadError;
use super::source::{Origin, view_bytes};
use ::gltf::accessor::{Accessor, DataType, Dimensions};

/// One accepted layout of an attribute: element shape, component type, and whether integer
/// components must be flagged `normalized`.
#[derive(Clone, Copy)]
pub struct Layout {
    /// SCALAR, VEC2, ...
    pub dimensions: Dimensions,
    /// Component type.
    pub data_type: DataType,
    /// Whether the accessor must be `normalized: true`.
    pub normalized: bool,
}

const fn layout(dimensions: Dimensions, data_type: DataType, normalized: bool) -> Layout {
    Layout {
        dimensions,
        data_type,
        normalized,
    }
}

/// POSITION and NORMAL: float VEC3.
pub const VEC3_F32: &[Layout] = &[layout(Dimensions::Vec3, DataType::F32, false)];
/// TANGENT: float VEC4.
pub const VEC4_F32: &[Layout] = &[layout(Dimensions::Vec4, DataType::F32, false)];
/// TEXCOORD_n: float or normalized unsigned VEC2.
pub const TEXCOORD: &[Layout] = &[
    layout(Dimensions::Vec2, DataType::F32, false),
    layout(Dimensions::Vec2, DataType::U8, true),
    layout(Dimensions::Vec2, DataType::U16, true),
];
/// COLOR_0: float or normalized unsigned VEC3 / VEC4.
pub const COLOR: &[Layout] = &[
    layout(Dimensions::Vec3, DataType::F32, false),
    layout(Dimensions::Vec3, DataType::U8, true),
    layout(Dimensions::Vec3, DataType::U16, true),
    layout(Dimensions::Vec4, DataType::F32, false),
    layout(Dimensions::Vec4, DataType::U8, true),
    layout(Dimensions::Vec4, DataType::U16, true),
];
/// Indices: unsigned SCALAR.
pub const INDICES: &[Layout] = &[
    layout(Dimensions::Scalar, DataType::U8, false),
    layout(Dimensions::Scalar, DataType::U16, false),
    layout(Dimensions::Scalar, DataType::U32, false),
];

/// Names for messages.
fn dimensions_name(d: Dimensions) -> &'static str {
    match d {
        Dimensions::Scalar => "SCALAR",
        Dimensions::Vec2 => "VEC2",
        Dimensions::Vec3 => "VEC3",
        Dimensions::Vec4 => "VEC4",
        Dimensions::Mat2 => "MAT2",
        Dimensions::Mat3 => "MAT3",
        Dimensions::Mat4 => "MAT4",
    }
}

fn data_type_name(t: DataType) -> &'static str {
    match t {
        DataType::I8 => "BYTE",
        DataType::U8 => "UNSIGNED_BYTE",
        DataType::I16 => "SHORT",
        DataType::U16 => "UNSIGNED_SHORT",
        DataType::U32 => "UNSIGNED_INT",
        DataType::F32 => "FLOAT",
    }
}

fn describe(l: &Layout) -> String {
    let norm = if l.normalized { " normalized" } else { "" };
    format!(
        "{} {}{}",
        dimensions_name(l.dimensions),
        data_type_name(l.data_type),
        norm
    )
}

/// Checks that `accessor`, used as `semantic` by `primitive`, has an accepted layout and
/// that every byte the reader will touch lies inside its buffer view and buffer.
pub fn check(
    accessor: &Accessor<'_>,
    semantic: &str,
    allowed: &[Layout],
    primitive: &str,
    buffers: &[Vec<u8>],
    origin: Origin<'_>,
) -> Result<(), LoadError> {
    let fail = |problem: String| LoadError::Primitive {
        path: origin.file.to_path_buf(),
        primitive: primitive.to_string(),
        problem: format!("{semantic} accessor {}: {problem}", accessor.index()),
    };
    let matches = |l: &Layout| {
        l.dimensions == accessor.dimensions()
            && l.data_type == accessor.data_type()
            && (l.normalized == accessor.normalized() || l.data_type == DataType::F32)
    };
    if !allowed.iter().any(matches) {
        let found = layout(
            accessor.dimensions(),
            accessor.data_type(),
            accessor.normalized(),
        );
        let accepted: Vec<String> = allowed.iter().map(describe).collect();
        return Err(fail(format!(
            "has type {}, but glTF allows only {} here (re-export the mesh)",
            describe(&found),
            accepted.join(" or ")
        )));
    }
    let count = accessor.count();
    if count == 0 {
        return Err(fail(
            "has count 0; glTF requires at least 1 (re-export the mesh)".into(),
        ));
    }
    let element = accessor.size();
    if accessor.view().is_none() {
        check_viewless_budget(count, element, buffers).map_err(fail)?;
    }
    if let Some(view) = accessor.view() {
        let bytes = view_bytes(&view, buffers, &format!("{primitive}: {semantic}"), origin)?;
        let stride = view.stride().unwrap_or(element);
        if stride < element {
            return Err(fail(format!(
                "buffer view {} has byteStride {stride}, shorter than one {element}-byte element",
                view.index()
            )));
        }
        check_span(accessor.offset(), stride, count, element, bytes.len())
            .map_err(|needed| {
                fail(format!(
                    "needs {needed} bytes of buffer view {}, which has {} (the file is corrupt; re-export it)",
                    view.index(),
                    bytes.len()
                ))
            })?;
    }
    if let Some(sparse) = accessor.sparse() {
        let sparse_count = sparse.count();
        if sparse_count == 0 || sparse_count > count {
            return Err(fail(format!(
                "has a sparse count of {sparse_count}; it must be between 1 and the accessor's count {count}"
            )));
        }
        let indices = sparse.indices();
        let index_view = indices.view();
        let index_size = indices.index_type().size();
        let index_bytes = view_bytes(
            &index_view,
            buffers,
            &format!("{primitive}: {semantic} sparse indices"),
            origin,
        )?;
        let index_stride = index_view.stride().unwrap_or(index_size);
        if index_stride < index_size {
            return Err(fail(format!(
                "sparse indices: buffer view {} has a stride shorter than an index",
                index_view.index()
            )));
        }
        check_span(
            indices.offset(),
            index_stride,
            sparse_count,
            index_size,
            index_bytes.len(),
        )
        .map_err(|needed| {
            fail(format!(
                "sparse indices need {needed} bytes of buffer view {}",
                index_view.index()
            ))
        })?;
        let values = sparse.values();
        let value_view = values.view();
        let value_bytes = view_bytes(
            &value_view,
            buffers,
            &format!("{primitive}: {semantic} sparse values"),
            origin,
        )?;
        let value_stride = value_view.stride().unwrap_or(element);
        if value_stride < element {
            return Err(fail(format!(
                "sparse values: buffer view {} has a stride shorter than an element",
                value_view.index()
            )));
        }
        check_span(
            values.offset(),
            value_stride,
            sparse_count,
            element,
            value_bytes.len(),
        )
        .map_err(|needed| {
            fail(format!(
                "sparse values need {needed} bytes of buffer view {}",
                value_view.index()
            ))
        })?;
    }
    Ok(())
}

/// Refuses an accessor without a buffer view whose `count` elements (all zeros but for its
/// sparse substitutes) would take more than [`viewless_budget`] bytes: such an accessor
/// costs nothing in the file, so a 1 KB file could otherwise have glint allocate gigabytes.
fn check_viewless_budget(count: usize, element: usize, buffers: &[Vec<u8>]) -> Result<(), String> {
    let budget = viewless_budget(buffers);
    let bytes = count.saturating_mul(element);
    if bytes <= budget {
        return Ok(());
    }
    Err(format!(
        "has no bufferView but a count of {count} ({bytes} bytes of {element}-byte elements), \
         more than the {budget} bytes glint allows such an accessor in this file (the larger of \
         the file's buffer data and {} bytes); the count is corrupt, re-export the file",
        super::limits::VIEWLESS_ACCESSOR_FLOOR_BYTES
    ))
}

/// Most bytes one accessor without a buffer view may expand to: the file's buffer data (a
/// view-less accessor, such as a sparse morph target, mirrors an attribute whose data is in
/// the buffers), but at least [`VIEWLESS_ACCESSOR_FLOOR_BYTES`](super::limits::VIEWLESS_ACCESSOR_FLOOR_BYTES).
pub fn viewless_budget(buffers: &[Vec<u8>]) -> usize {
    let data: usize = buffers.iter().map(Vec::len).fold(0, usize::saturating_add);
    data.max(super::limits::VIEWLESS_ACCESSOR_FLOOR_BYTES)
}

/// Checks that `count` elements of `element` bytes, `stride` apart from `offset`, fit in
/// `available` bytes; on failure returns the bytes needed (saturated on overflow).
fn check_span(
    offset: usize,
    stride: usize,
    count: usize,
    element: usize,
    available: usize,
) -> Result<(), usize> {
    let needed = count
        .checked_sub(1)
        .and_then(|last| last.checked_mul(stride))
        .and_then(|span| span.checked_add(element))
        .and_then(|span| span.checked_add(offset))
        .unwrap_or(usize::MAX);
    if needed <= available {
        Ok(())
    } else {
        Err(needed)
    }
}

/// Collects a reader's values, or `count` defaults when the accessor has no buffer view
/// (glTF defines such an accessor as all zeros), and checks the count.
pub fn collect_or_zeros<T: Default + Clone>(
    values: Option<impl Iterator<Item = T>>,
    count: usize,
) -> Vec<T> {
    match values {
        Some(values) => {
            let mut out = Vec::with_capacity(count);
            out.extend(values.take(count));
            // A checked accessor yields exactly `count` items; pad defensively rather than
            // leave a short attribute array behind.
            out.resize(count, T::default());
            out
        }
        None => vec![T::default(); count],
    }
}
