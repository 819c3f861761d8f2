//! EXT_meshopt_compression: buffer views stored compressed by meshoptimizer's codecs.
//!
//! A compressed view carries `{buffer, byteOffset, byteLength, byteStride, count, mode,
//! filter}` in its extension object: `byteLength` bytes of `buffer` decode, with the codec
//! `mode` names (ATTRIBUTES: the vertex codec; TRIANGLES: the index codec; INDICES: the
//! index-sequence codec), into `count × byteStride` bytes, to which the `filter` is then
//! applied in place (NONE; OCTAHEDRAL unit vectors; QUATERNION rotations; EXPONENTIAL
//! floats; COLOR YCoCg). The view's own `buffer` is then usually a *fallback* buffer with no
//! data at all.
//!
//! glint decodes every such view once, at load, through the `meshopt` crate (the
//! meshoptimizer library's own decoders and filters), appends the decoded bytes as a new
//! in-memory buffer and points the view at it, so that everything downstream reads plain
//! buffer views. The decoders are documented as safe on untrusted input (they may produce
//! garbage, which the accessor checks then catch).

use super::LoadError;
use super::source::Origin;
use ::gltf::json::validation::USize64;

const EXTENSION: &str = "EXT_meshopt_compression";

/// Decoded data larger than this is refused before allocating: no mesh glint can render
/// needs a 2 GiB buffer view, and a hostile count must not exhaust memory.
const MAX_DECODED_BYTES: u64 = 2 << 30;

/// Whether `buffer` is an EXT_meshopt_compression fallback buffer (no data of its own;
/// only compressed views refer to it).
pub fn is_fallback(buffer: &::gltf::Buffer<'_>) -> bool {
    buffer
        .extension_value(EXTENSION)
        .and_then(|v| v.get("fallback"))
        .and_then(serde_json::Value::as_bool)
        .unwrap_or(false)
}

/// The extension object of one compressed view.
#[derive(serde::Deserialize)]
#[serde(rename_all = "camelCase")]
struct Compressed {
    buffer: usize,
    #[serde(default)]
    byte_offset: usize,
    byte_length: usize,
    byte_stride: usize,
    count: usize,
    mode: String,
    #[serde(default = "no_filter")]
    filter: String,
}

fn no_filter() -> String {
    "NONE".to_string()
}

/// Decodes every compressed buffer view of `document`, appending the decoded bytes to
/// `buffers` and re-pointing the views; a document without compressed views is returned
/// unchanged.
pub fn decode_views(
    document: ::gltf::Document,
    buffers: &mut Vec<Vec<u8>>,
    origin: Origin<'_>,
    geometry: &mut super::limits::GeometryBudget,
) -> Result<::gltf::Document, LoadError> {
    if document
        .views()
        .all(|view| view.extension_value(EXTENSION).is_none())
    {
        return Ok(document);
    }
    let mut root = document.into_json();
    for (index, view) in root.buffer_views.iter_mut().enumerate() {
        let Some(value) = view
            .extensions
            .as_mut()
            .and_then(|e| e.others.remove(EXTENSION))
        else {
            continue;
        };
        let what = format!("buffer view {index} ({EXTENSION})");
        let fail = |problem: String| LoadError::Data {
            path: origin.file.to_path_buf(),
            what: what.clone(),
            problem,
        };
        let compressed: Compressed = serde_json::from_value(value).map_err(|err| {
            fail(format!(
                "has an invalid extension object: {err} (re-run gltfpack)"
            ))
        })?;
        let source = buffers
            .get(compressed.buffer)
            .and_then(|b| {
                b.get(
                    compressed.byte_offset
                        ..compressed.byte_offset.checked_add(compressed.byte_length)?,
                )
            })
            .ok_or_else(|| {
                fail(format!(
                    "its compressed bytes {}..+{} lie outside buffer {} (the file is corrupt; re-export it)",
                    compressed.byte_offset, compressed.byte_length, compressed.buffer
                ))
            })?;
        let expected = (compressed.count as u64).saturating_mul(compressed.byte_stride as u64);
        if expected != view.byte_length.0 {
            return Err(fail(format!(
                "count {} × byteStride {} is {expected} bytes, but the view declares byteLength {} \
                 (the file is corrupt; re-export it)",
                compressed.count, compressed.byte_stride, view.byte_length.0
            )));
        }
        geometry.charge(expected, &what, origin)?;
        let decoded = decode(source, &compressed).map_err(fail)?;
        let length = decoded.len();
        view.buffer = ::gltf::json::Index::new(root.buffers.len() as u32);
        view.byte_offset = Some(USize64(0));
        root.buffers.push(::gltf::json::Buffer {
            byte_length: USize64(length as u64),
            name: None,
            uri: None,
            extensions: None,
            extras: Default::default(),
        });
        buffers.push(decoded);
    }
    ::gltf::Document::from_json(root).map_err(|err| LoadError::Syntax {
        path: origin.file.to_path_buf(),
        message: format!("after decoding {EXTENSION}: {err} (re-run gltfpack)"),
    })
}

/// One element of `S` bytes, so that the vertex decoder's element size is the view's stride.
#[derive(Clone, Copy)]
struct Element<const S: usize>([u8; S]);

impl<const S: usize> Default for Element<S> {
    fn default() -> Self {
        Element([0; S])
    }
}

fn decode_vertices<const S: usize>(source: &[u8], count: usize) -> Result<Vec<u8>, String> {
    meshopt::encoding::decode_vertex_buffer::<Element<S>>(source, count)
        .map(|elements| elements.into_iter().flat_map(|e| e.0).collect())
        .map_err(|err| format!("the vertex data does not decode ({err}); the file is corrupt"))
}

/// The vertex codec for a stride known only at run time: one monomorphised decoder per
/// stride the extension allows (multiples of 4 up to 256).
macro_rules! vertex_strides {
    ($source:expr, $count:expr, $stride:expr, [$($s:literal)*]) => {
        match $stride {
            $($s => decode_vertices::<$s>($source, $count),)*
            other => Err(format!(
                "byteStride {other} is not a multiple of 4 between 4 and 256, as ATTRIBUTES mode requires"
            )),
        }
    };
}

/// Most bytes one vertex of the ATTRIBUTES codec may have (meshoptimizer asserts it).
const MAX_VERTEX_STRIDE: usize = 256;

/// Checks what meshoptimizer's decoders and filters assert (an assertion aborts the process,
/// which no Rust code can catch) and what the extension requires, before any is called:
///
/// - ATTRIBUTES: `byteStride` a multiple of 4 from 4 to 256 (`meshopt_decodeVertexBuffer`);
/// - TRIANGLES: `byteStride` 2 or 4 and `count` a multiple of 3 (`meshopt_decodeIndexBuffer`);
/// - INDICES: `byteStride` 2 or 4 (`meshopt_decodeIndexSequence`);
/// - a filter other than NONE only in ATTRIBUTES mode (the extension's rule; the filters'
///   own stride rules are checked by [`apply_filter`]);
/// - at most [`MAX_DECODED_BYTES`] of output.
fn check_preconditions(c: &Compressed) -> Result<(), String> {
    match c.mode.as_str() {
        "ATTRIBUTES" => {
            if c.byte_stride == 0
                || c.byte_stride > MAX_VERTEX_STRIDE
                || !c.byte_stride.is_multiple_of(4)
            {
                return Err(format!(
                    "byteStride {} is not a multiple of 4 between 4 and {MAX_VERTEX_STRIDE}, as ATTRIBUTES mode requires",
                    c.byte_stride
                ));
            }
        }
        "TRIANGLES" | "INDICES" => {
            if c.byte_stride != 2 && c.byte_stride != 4 {
                return Err(format!(
                    "byteStride {} is not 2 or 4, as {} mode requires",
                    c.byte_stride, c.mode
                ));
            }
            if c.mode == "TRIANGLES" && !c.count.is_multiple_of(3) {
                return Err(format!(
                    "count {} is not a multiple of 3, as TRIANGLES mode requires (the file is corrupt; re-run gltfpack)",
                    c.count
                ));
            }
            if c.filter != "NONE" {
                return Err(format!(
                    "filter {} is only allowed in ATTRIBUTES mode, not {} (the file is corrupt; re-run gltfpack)",
                    c.filter, c.mode
                ));
            }
        }
        other => {
            return Err(format!(
                "mode {other} is not ATTRIBUTES, TRIANGLES or INDICES"
            ));
        }
    }
    let size = (c.count as u64).saturating_mul(c.byte_stride as u64);
    if size > MAX_DECODED_BYTES {
        return Err(format!(
            "would decode to {size} bytes ({} × {}), more than glint accepts for one view",
            c.count, c.byte_stride
        ));
    }
    Ok(())
}

fn decode(source: &[u8], c: &Compressed) -> Result<Vec<u8>, String> {
    check_preconditions(c)?;
    let mut bytes = match c.mode.as_str() {
        "ATTRIBUTES" => vertex_strides!(source, c.count, c.byte_stride, [
            4 8 12 16 20 24 28 32 36 40 44 48 52 56 60 64 68 72 76 80 84 88 92 96 100 104 108
            112 116 120 124 128 132 136 140 144 148 152 156 160 164 168 172 176 180 184 188 192
            196 200 204 208 212 216 220 224 228 232 236 240 244 248 252 256
        ])?,
        "TRIANGLES" | "INDICES" => {
            let triangles = c.mode == "TRIANGLES";
            let bad = |err| format!("the index data does not decode ({err}); the file is corrupt");
            match (c.byte_stride, triangles) {
                (2, true) => meshopt::encoding::decode_index_buffer::<u16>(source, c.count)
                    .map(|v| v.into_iter().flat_map(u16::to_le_bytes).collect())
                    .map_err(bad)?,
                (4, true) => meshopt::encoding::decode_index_buffer::<u32>(source, c.count)
                    .map(|v| v.into_iter().flat_map(u32::to_le_bytes).collect())
                    .map_err(bad)?,
                (2, false) => meshopt::encoding::decode_index_sequence::<u16>(source, c.count)
                    .map(|v| v.into_iter().flat_map(u16::to_le_bytes).collect())
                    .map_err(bad)?,
                (4, false) => meshopt::encoding::decode_index_sequence::<u32>(source, c.count)
                    .map(|v| v.into_iter().flat_map(u32::to_le_bytes).collect())
                    .map_err(bad)?,
                (stride, _) => {
                    return Err(format!(
                        "byteStride {stride} is not 2 or 4, as {} mode requires",
                        c.mode
                    ));
                }
            }
        }
        other => {
            return Err(format!(
                "mode {other} is not ATTRIBUTES, TRIANGLES or INDICES"
            ));
        }
    };
    apply_filter(&mut bytes, c)?;
    Ok(bytes)
}

/// Reinterprets little-endian bytes as `N`-component words, runs `filter` on them and writes
/// them back (the filters work on typed arrays; the buffers are plain bytes).
fn filter_words<const W: usize, const N: usize, T: Copy>(
    bytes: &mut [u8],
    from: fn([u8; W]) -> T,
    to: fn(T) -> [u8; W],
    filter: impl FnOnce(&mut [[T; N]]),
) {
    let mut words: Vec<[T; N]> = bytes
        .chunks_exact(W * N)
        .map(|chunk| {
            std::array::from_fn(|i| {
                let mut word = [0u8; W];
                word.copy_from_slice(&chunk[i * W..(i + 1) * W]);
                from(word)
            })
        })
        .collect();
    filter(&mut words);
    for (chunk, word) in bytes.chunks_exact_mut(W * N).zip(words) {
        for (i, value) in word.into_iter().enumerate() {
            chunk[i * W..(i + 1) * W].copy_from_slice(&to(value));
        }
    }
}

fn apply_filter(bytes: &mut [u8], c: &Compressed) -> Result<(), String> {
    use meshopt::encoding::{
        decode_filter_color, decode_filter_exp, decode_filter_oct, decode_filter_quat,
    };
    let wrong_stride = |allowed: &str| {
        Err(format!(
            "filter {} needs byteStride {allowed}, not {}",
            c.filter, c.byte_stride
        ))
    };
    match (c.filter.as_str(), c.byte_stride) {
        ("NONE", _) => {}
        ("OCTAHEDRAL", 4) => {
            filter_words::<1, 4, i8>(bytes, i8::from_le_bytes, i8::to_le_bytes, decode_filter_oct)
        }
        ("OCTAHEDRAL", 8) => filter_words::<2, 4, i16>(
            bytes,
            i16::from_le_bytes,
            i16::to_le_bytes,
            decode_filter_oct,
        ),
        ("OCTAHEDRAL", _) => return wrong_stride("4 or 8"),
        ("QUATERNION", 8) => filter_words::<2, 4, i16>(
            bytes,
            i16::from_le_bytes,
            i16::to_le_bytes,
            decode_filter_quat,
        ),
        ("QUATERNION", _) => return wrong_stride("8"),
        // Each 32-bit word decodes on its own, so one word per "vector" is equivalent.
        ("EXPONENTIAL", stride) if stride % 4 == 0 => filter_words::<4, 1, u32>(
            bytes,
            u32::from_le_bytes,
            u32::to_le_bytes,
            decode_filter_exp::<1>,
        ),
        ("EXPONENTIAL", _) => return wrong_stride("a multiple of 4"),
        ("COLOR", 4) => filter_words::<1, 4, u8>(
            bytes,
            u8::from_le_bytes,
            u8::to_le_bytes,
            decode_filter_color,
        ),
        ("COLOR", 8) => filter_words::<2, 4, u16>(
            bytes,
            u16::from_le_bytes,
            u16::to_le_bytes,
            decode_filter_color,
        ),
        ("COLOR", _) => return wrong_stride("4 or 8"),
        (other, _) => {
            return Err(format!(
                "filter {other} is not NONE, OCTAHEDRAL, QUATERNION, EXPONENTIAL or COLOR"
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn compressed(mode: &str, filter: &str, stride: usize, count: usize) -> Compressed {
        Compressed {
            buffer: 0,
            byte_offset: 0,
            byte_length: 0,
            byte_stride: stride,
            count,
            mode: mode.into(),
            filter: filter.into(),
        }
    }

    #[test]
    fn vertex_and_index_codecs_round_trip() {
        let vertices: Vec<[u8; 12]> = (0..100u8)
            .map(|i| std::array::from_fn(|j| i.wrapping_mul(7).wrapping_add(j as u8)))
            .collect();
        let encoded = meshopt::encoding::encode_vertex_buffer(&vertices).unwrap();
        let decoded = decode(&encoded, &compressed("ATTRIBUTES", "NONE", 12, 100)).unwrap();
        assert_eq!(decoded, vertices.concat());

        let indices: Vec<u32> = vec![0, 1, 2, 2, 1, 3, 3, 1, 4];
        let encoded = meshopt::encoding::encode_index_buffer(&indices, 5).unwrap();
        let decoded = decode(&encoded, &compressed("TRIANGLES", "NONE", 2, 9)).unwrap();
        let back: Vec<u32> = decoded
            .chunks_exact(2)
            .map(|c| u32::from(u16::from_le_bytes([c[0], c[1]])))
            .collect();
        assert_eq!(back, indices);
    }

    #[test]
    fn exponential_filter_gives_mantissa_times_power_of_two() {
        // Exponent −2 in the top byte, mantissa 6: 6 · 2⁻² = 1.5.
        let word: u32 = ((-2i8 as u8 as u32) << 24) | 6;
        let mut bytes = word.to_le_bytes().to_vec();
        apply_filter(&mut bytes, &compressed("ATTRIBUTES", "EXPONENTIAL", 4, 1)).unwrap();
        assert_eq!(
            f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]),
            1.5
        );
    }

    #[test]
    fn octahedral_and_quaternion_filters_invert_their_encoders() {
        let normals = [
            [0.0f32, 0.0, 1.0, 0.0],
            [0.6, -0.8, 0.0, 0.0],
            [-0.48, 0.6, -0.64, 0.0],
        ];
        let encoded = meshopt::encoding::encode_filter_oct::<i16>(&normals, 16);
        let mut bytes: Vec<u8> = encoded
            .iter()
            .flatten()
            .flat_map(|c| c.to_le_bytes())
            .collect();
        apply_filter(&mut bytes, &compressed("ATTRIBUTES", "OCTAHEDRAL", 8, 3)).unwrap();
        for (n, chunk) in normals.iter().zip(bytes.chunks_exact(8)) {
            let c = |i: usize| {
                f32::from(i16::from_le_bytes([chunk[2 * i], chunk[2 * i + 1]])) / 32767.0
            };
            for i in 0..3 {
                assert!((c(i) - n[i]).abs() < 1e-3, "{n:?}");
            }
        }
        let q = glam::Quat::from_rotation_y(0.7) * glam::Quat::from_rotation_x(-0.3);
        let encoded = meshopt::encoding::encode_filter_quat(&[q.to_array()], 16);
        let mut bytes: Vec<u8> = encoded
            .iter()
            .flatten()
            .flat_map(|c| c.to_le_bytes())
            .collect();
        apply_filter(&mut bytes, &compressed("ATTRIBUTES", "QUATERNION", 8, 1)).unwrap();
        let c =
            |i: usize| f32::from(i16::from_le_bytes([bytes[2 * i], bytes[2 * i + 1]])) / 32767.0;
        let back = glam::Quat::from_xyzw(c(0), c(1), c(2), c(3));
        assert!(back.dot(q).abs() > 0.9999, "{back} vs {q}");
    }

    #[test]
    fn bad_strides_and_modes_are_errors() {
        assert!(decode(&[0; 16], &compressed("ATTRIBUTES", "NONE", 6, 1)).is_err());
        assert!(decode(&[0; 16], &compressed("TRIANGLES", "NONE", 3, 3)).is_err());
        assert!(decode(&[0; 16], &compressed("LINES", "NONE", 4, 1)).is_err());
        assert!(decode(&[0; 16], &compressed("ATTRIBUTES", "NONE", 4, usize::MAX)).is_err());
        assert!(decode(&[0; 16], &compressed("ATTRIBUTES", "NONE", 260, 1)).is_err());
        // meshoptimizer asserts (aborts) on these; they must be refused before the call.
        let err = decode(&[0xe1; 32], &compressed("TRIANGLES", "NONE", 2, 4)).unwrap_err();
        assert!(err.contains("multiple of 3"), "{err}");
        assert!(decode(&[0xe1; 32], &compressed("INDICES", "NONE", 8, 4)).is_err());
        let err = decode(&[0xe1; 32], &compressed("TRIANGLES", "OCTAHEDRAL", 4, 3)).unwrap_err();
        assert!(err.contains("only allowed in ATTRIBUTES"), "{err}");
        let mut bytes = vec![0; 12];
        assert!(apply_filter(&mut bytes, &compressed("ATTRIBUTES", "QUATERNION", 12, 1)).is_err());
    }
}
