//! Draco seeds for the `draco` target: a grid encoded by draco-core (edgebreaker and
//! sequential connectivity, quantised and not), and the stream of `tests/draco/Box-draco.glb`
//! (Google's encoder). The first byte is the target's attribute selector.

use draco_core::{
    DataType, EncoderBuffer, EncoderOptions, FaceIndex, GeometryAttributeType, Mesh, MeshEncoder,
    PointAttribute,
};

const SIDE: usize = 4;

fn attribute(kind: GeometryAttributeType, components: u8, values: &[f32]) -> PointAttribute {
    let mut attribute = PointAttribute::new();
    let points = values.len() / usize::from(components);
    attribute.init(kind, components, DataType::Float32, false, points);
    for (i, v) in values.iter().enumerate() {
        attribute.buffer_mut().write(i * 4, &v.to_le_bytes());
    }
    attribute
}

/// A SIDE × SIDE grid with positions (id 0), normals (id 1) and texture coordinates (id 2).
fn grid() -> Mesh {
    let (mut positions, mut normals, mut uvs) = (Vec::new(), Vec::new(), Vec::new());
    for y in 0..SIDE {
        for x in 0..SIDE {
            let (u, v) = (x as f32 / (SIDE - 1) as f32, y as f32 / (SIDE - 1) as f32);
            positions.extend_from_slice(&[u, v, (u * 3.0).sin() * 0.2]);
            normals.extend_from_slice(&[0.0, 0.0, 1.0]);
            uvs.extend_from_slice(&[u, 1.0 - v]);
        }
    }
    let mut mesh = Mesh::new();
    mesh.add_attribute(attribute(GeometryAttributeType::Position, 3, &positions));
    mesh.add_attribute(attribute(GeometryAttributeType::Normal, 3, &normals));
    mesh.add_attribute(attribute(GeometryAttributeType::TexCoord, 2, &uvs));
    mesh.set_num_faces((SIDE - 1) * (SIDE - 1) * 2);
    let mut face = 0;
    for y in 0..SIDE - 1 {
        for x in 0..SIDE - 1 {
            let a = (y * SIDE + x) as u32;
            let (b, c, d) = (a + 1, a + SIDE as u32, a + SIDE as u32 + 1);
            mesh.set_face(FaceIndex(face), [a.into(), c.into(), b.into()]);
            mesh.set_face(FaceIndex(face + 1), [b.into(), c.into(), d.into()]);
            face += 2;
        }
    }
    mesh
}

fn encode(speed: i32, quantise: bool) -> Option<Vec<u8>> {
    let mut options = EncoderOptions::new();
    options.set_global_int("encoding_speed", speed);
    options.set_global_int("decoding_speed", speed);
    if quantise {
        options.set_attribute_int(0, "quantization_bits", 11);
        options.set_attribute_int(1, "quantization_bits", 8);
        options.set_attribute_int(2, "quantization_bits", 10);
    }
    let mut encoder = MeshEncoder::new();
    encoder.set_mesh(grid());
    let mut buffer = EncoderBuffer::new();
    encoder.encode(&options, &mut buffer).ok()?;
    Some(buffer.data().to_vec())
}

/// The seeds: (file name, selector byte + stream).
pub fn seeds() -> Vec<(String, Vec<u8>)> {
    let mut seeds = Vec::new();
    for (name, speed, quantise) in [
        ("grid-edgebreaker.drc", 5, true),
        ("grid-sequential.drc", 10, true),
        ("grid-float.drc", 10, false),
    ] {
        if let Some(stream) = encode(speed, quantise) {
            let mut input = vec![0b011];
            input.extend_from_slice(&stream);
            seeds.push((name.to_string(), input));
        }
    }
    // Google's encoder: NORMAL is attribute 0, POSITION 1 (selector bit 2 swaps them).
    let box_glb =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/draco/Box-draco.glb");
    if let Ok(glb) = std::fs::read(box_glb) {
        let word =
            |i: usize| u32::from_le_bytes([glb[i], glb[i + 1], glb[i + 2], glb[i + 3]]) as usize;
        let json_len = word(12);
        let bin = &glb[28 + json_len..];
        // The stream is the whole of buffer view 0 (130 bytes at offset 0, see the JSON).
        let mut input = vec![0b101];
        input.extend_from_slice(&bin[..130.min(bin.len())]);
        seeds.push(("box-google.drc".to_string(), input));
    }
    seeds
}
