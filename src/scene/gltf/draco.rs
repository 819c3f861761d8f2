//! KHR_draco_mesh_compression: primitives whose geometry is one Draco-compressed stream.
//!
//! A compressed primitive carries `{bufferView, attributes: {SEMANTIC: draco_id}}` in its
//! extension object: the view holds a Draco mesh, and each named attribute is the stream's
//! attribute with that unique id. The primitive's own accessors (with no buffer view) describe
//! the decoded data: their `type` says how many components to read.
//!
//! glint decodes every such primitive once, at load, with the pure-Rust `draco-core` decoder
//! (no `unsafe`, no C++ to abort the process), writes the decoded indices (u32) and
//! attributes (f32; JOINTS as u16) into a new in-memory buffer with one view and one new
//! accessor each, and points the primitive at them, so that everything downstream reads plain
//! accessors. Sizes are checked before allocating: the decoder is given the geometry budget
//! that is left as its ceiling on faces and decoded bytes, and what it decoded is charged to
//! that budget before glint copies it. A panic inside the decoder (it is young) becomes the
//! primitive's load error, as with the Basis Universal transcoder.

use super::LoadError;
use super::limits::GeometryBudget;
use super::source::Origin;
use ::gltf::json;
use ::gltf::json::validation::{Checked, USize64};
use std::collections::BTreeMap;

/// The extension's name.
pub const EXTENSION: &str = "KHR_draco_mesh_compression";

/// The extension object of one compressed primitive.
#[derive(serde::Deserialize)]
#[serde(rename_all = "camelCase")]
struct Compressed {
    buffer_view: usize,
    attributes: BTreeMap<String, u32>,
}

/// What one decoded attribute becomes.
struct Decoded {
    bytes: Vec<u8>,
    component_type: json::accessor::ComponentType,
}

/// Whether any primitive of `root` is Draco-compressed.
pub fn any_compressed(root: &json::Root) -> bool {
    root.meshes.iter().any(|m| {
        m.primitives.iter().any(|p| {
            p.extensions
                .as_ref()
                .is_some_and(|e| e.others.contains_key(EXTENSION))
        })
    })
}

/// Decodes every Draco primitive of `root` into new buffers, views and accessors, before the
/// document is validated (the `gltf` crate's validator refuses the accessors without a buffer
/// view that a compressed primitive has until then). `buffers` are the root's buffers.
pub fn decode_primitives(
    root: &mut json::Root,
    buffers: &mut Vec<Vec<u8>>,
    origin: Origin<'_>,
    geometry: &mut GeometryBudget,
) -> Result<(), LoadError> {
    let mut any = false;
    for mesh_index in 0..root.meshes.len() {
        for primitive_index in 0..root.meshes[mesh_index].primitives.len() {
            let primitive = &mut root.meshes[mesh_index].primitives[primitive_index];
            let Some(value) = primitive
                .extensions
                .as_mut()
                .and_then(|e| e.others.remove(EXTENSION))
            else {
                continue;
            };
            any = true;
            let what = format!("mesh {mesh_index} / primitive {primitive_index} ({EXTENSION})");
            decode_one(
                root,
                mesh_index,
                primitive_index,
                value,
                buffers,
                origin,
                geometry,
            )
            .map_err(|problem| LoadError::Primitive {
                path: origin.file.to_path_buf(),
                primitive: what.clone(),
                problem,
            })?;
        }
    }
    if any {
        root.extensions_used.retain(|e| e != EXTENSION);
        root.extensions_required.retain(|e| e != EXTENSION);
    }
    Ok(())
}

/// Decodes one primitive's stream and re-points it at the decoded data. The error is the
/// problem, for the caller to name the primitive.
fn decode_one(
    root: &mut json::Root,
    mesh_index: usize,
    primitive_index: usize,
    value: json::Value,
    buffers: &mut Vec<Vec<u8>>,
    origin: Origin<'_>,
    geometry: &mut GeometryBudget,
) -> Result<(), String> {
    let compressed: Compressed = serde_json::from_value(value)
        .map_err(|err| format!("has an invalid extension object: {err} (re-export the scene)"))?;
    let stream = stream_bytes(root, compressed.buffer_view, buffers)?;
    // The decoder's own ceilings: what is left of the geometry budget.
    let left = geometry.left();
    // Refused before the decoder allocates: the decoded bytes the stream's declared point
    // count and attribute layout imply, and its declared faces (three indices each). The
    // point ceiling is kept for streams the decoder checks it on (draco-core 2.3 reads it
    // only on its point-cloud path, which glint does not enable; the byte ceiling is what
    // bounds a mesh's declared points).
    let limits = draco_core::DecodeLimits::default()
        .with_max_points(left / 12)
        .with_max_faces(left / 12)
        .with_max_decoded_bytes(left);
    let mesh = crate::panics::catch(|| {
        let mut buffer = draco_core::DecoderBuffer::new(stream).with_limits(limits);
        let mut mesh = draco_core::Mesh::new();
        draco_core::MeshDecoder::new()
            .decode(&mut buffer, &mut mesh)
            .map(|()| mesh)
    })
    .map_err(|panic| {
        format!(
            "the Draco decoder failed on this stream (it panicked: {}); the data is corrupt, \
             re-export the scene",
            super::error::one_line(&panic.message)
        )
    })?
    .map_err(|err| {
        let over_budget = err.kind() == draco_core::ErrorKind::LimitExceeded;
        let err = super::error::one_line(&err.to_string());
        if over_budget {
            format!(
                "the Draco stream in buffer view {} decodes to more than the {left} bytes left of \
                 the scene's geometry budget ({err}); raise --max-geometry-bytes if the scene is real",
                compressed.buffer_view
            )
        } else {
            format!(
                "the Draco stream in buffer view {} does not decode ({err}); the data is corrupt, \
                 re-export the scene",
                compressed.buffer_view
            )
        }
    })?;
    let points = mesh.num_points();
    let faces = mesh.num_faces();
    let primitive = &root.meshes[mesh_index].primitives[primitive_index];
    // Each mapped attribute's accessor, with the component count its type gives.
    let mut mapped = Vec::new();
    for (semantic, &id) in &compressed.attributes {
        let accessor = primitive
            .attributes
            .iter()
            .find(|(s, _)| matches!(s, Checked::Valid(s) if s.to_string() == *semantic))
            .map(|(_, a)| a.value())
            .ok_or_else(|| {
                format!(
                    "the extension maps {semantic}, which the primitive's attributes do not list \
                     (the file is corrupt; re-export it)"
                )
            })?;
        let components = root
            .accessors
            .get(accessor)
            .and_then(|a| match a.type_ {
                Checked::Valid(t) => Some(t.multiplicity()),
                Checked::Invalid => None,
            })
            .ok_or_else(|| format!("{semantic} refers to accessor {accessor}, which is missing or has no valid type"))?;
        mapped.push((semantic.clone(), id, accessor, components));
    }
    let bytes = (faces as u64).saturating_mul(12).saturating_add(
        mapped
            .iter()
            .map(|m| (points as u64).saturating_mul(m.3 as u64 * 4))
            .fold(0, u64::saturating_add),
    );
    geometry
        .charge(bytes, &format!("the decoded {EXTENSION} primitive"), origin)
        .map_err(|err| match err {
            LoadError::Data { problem, .. } => problem,
            other => other.to_string(),
        })?;
    let mut decoded = Vec::new();
    for (semantic, id, accessor, components) in &mapped {
        let attribute = mesh.attribute_by_unique_id(*id).ok_or_else(|| {
            format!(
                "{semantic} refers to Draco attribute {id}, which the stream does not have \
                 (the file is corrupt; re-export it)"
            )
        })?;
        let values = attribute.read_f32s(points, *components);
        let data = if semantic.starts_with("JOINTS_") {
            Decoded {
                bytes: values
                    .iter()
                    .flat_map(|v| (v.clamp(0.0, f32::from(u16::MAX)) as u16).to_le_bytes())
                    .collect(),
                component_type: json::accessor::ComponentType::U16,
            }
        } else {
            Decoded {
                bytes: values.iter().flat_map(|v| v.to_le_bytes()).collect(),
                component_type: json::accessor::ComponentType::F32,
            }
        };
        decoded.push((semantic.clone(), *accessor, data));
    }
    let mut indices = Vec::with_capacity(faces * 12);
    for face in mesh.faces() {
        for point in face {
            if point.0 as usize >= points {
                return Err(format!(
                    "a face refers to point {}, past the stream's {points} points (the data is corrupt; re-export it)",
                    point.0
                ));
            }
            indices.extend_from_slice(&point.0.to_le_bytes());
        }
    }
    // One new buffer holding the indices, then each attribute (4-byte aligned).
    let buffer_index = root.buffers.len();
    let mut data = Vec::new();
    let new_accessor = |root: &mut json::Root,
                        data: &mut Vec<u8>,
                        template: Option<usize>,
                        bytes: &[u8],
                        count: usize,
                        component_type,
                        type_| {
        while !data.len().is_multiple_of(4) {
            data.push(0);
        }
        let offset = data.len();
        data.extend_from_slice(bytes);
        root.buffer_views.push(json::buffer::View {
            buffer: json::Index::new(buffer_index as u32),
            byte_length: USize64(bytes.len() as u64),
            byte_offset: Some(USize64(offset as u64)),
            byte_stride: None,
            name: None,
            target: None,
            extensions: None,
            extras: Default::default(),
        });
        let view = json::Index::new((root.buffer_views.len() - 1) as u32);
        // The primitive's own accessor is pointed at the decoded data in place (the
        // validator refuses an accessor left without a view); one is made when missing.
        let index = match template.filter(|&t| t < root.accessors.len()) {
            Some(t) => t,
            None => {
                root.accessors.push(json::Accessor {
                    buffer_view: None,
                    byte_offset: None,
                    count: USize64(0),
                    component_type: Checked::Valid(json::accessor::GenericComponentType(
                        component_type,
                    )),
                    extensions: None,
                    extras: Default::default(),
                    type_: Checked::Valid(type_),
                    min: None,
                    max: None,
                    name: None,
                    normalized: false,
                    sparse: None,
                });
                root.accessors.len() - 1
            }
        };
        let accessor = &mut root.accessors[index];
        accessor.buffer_view = Some(view);
        accessor.byte_offset = Some(USize64(0));
        accessor.count = USize64(count as u64);
        accessor.component_type =
            Checked::Valid(json::accessor::GenericComponentType(component_type));
        accessor.normalized = false;
        accessor.sparse = None;
        json::Index::new(index as u32)
    };
    let index_template = root.meshes[mesh_index].primitives[primitive_index]
        .indices
        .map(|i| i.value());
    let index_accessor = new_accessor(
        root,
        &mut data,
        index_template,
        &indices,
        faces * 3,
        json::accessor::ComponentType::U32,
        json::accessor::Type::Scalar,
    );
    let mut repointed = Vec::new();
    for (semantic, accessor, d) in decoded {
        let index = new_accessor(
            root,
            &mut data,
            Some(accessor),
            &d.bytes,
            points,
            d.component_type,
            json::accessor::Type::Scalar,
        );
        repointed.push((semantic, index));
    }
    root.buffers.push(json::Buffer {
        byte_length: USize64(data.len() as u64),
        name: None,
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    buffers.push(data);
    let primitive = &mut root.meshes[mesh_index].primitives[primitive_index];
    primitive.indices = Some(index_accessor);
    for (semantic, index) in repointed {
        for (s, a) in primitive.attributes.iter_mut() {
            if matches!(s, Checked::Valid(s) if s.to_string() == semantic) {
                *a = index;
            }
        }
    }
    // Draco streams hold triangle lists.
    primitive.mode = Checked::Valid(json::mesh::Mode::Triangles);
    Ok(())
}

/// The bytes of the compressed stream's buffer view, checked against its buffer.
fn stream_bytes<'b>(
    root: &json::Root,
    view_index: usize,
    buffers: &'b [Vec<u8>],
) -> Result<&'b [u8], String> {
    let view = root.buffer_views.get(view_index).ok_or_else(|| {
        format!(
            "its bufferView {view_index} does not exist (the file has {}); the file is corrupt, re-export it",
            root.buffer_views.len()
        )
    })?;
    let buffer = buffers
        .get(view.buffer.value())
        .map_or(&[][..], Vec::as_slice);
    let offset = view.byte_offset.map_or(0, |o| o.0) as usize;
    let length = view.byte_length.0 as usize;
    offset
        .checked_add(length)
        .and_then(|end| buffer.get(offset..end))
        .ok_or_else(|| {
            format!(
                "its Draco stream, bytes {offset}..+{length} of buffer {}, lies outside the buffer ({} bytes); \
                 the file is corrupt, re-export it",
                view.buffer.value(),
                buffer.len()
            )
        })
}
