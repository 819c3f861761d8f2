//! One glTF primitive instanced by one node → one world-space [`Mesh`].

use super::LoadError;
use super::accessors::{self, COLOR, INDICES, TEXCOORD, VEC3_F32, VEC4_F32};
use super::source::Origin;
use super::{morph, quantization, skin};
use crate::scene::Mesh;
use ::gltf::mesh::Mode;
use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};

/// What a primitive needs besides itself.
pub struct PrimitiveContext<'a> {
    /// File and base folder, for messages.
    pub origin: Origin<'a>,
    /// Buffer bytes, index-aligned with the document's buffers.
    pub buffers: &'a [Vec<u8>],
    /// `node "X" / mesh 3 / primitive 0`.
    pub label: String,
    /// The instancing node's world transform.
    pub world_from_object: Mat4,
    /// Index into `Scene::materials`.
    pub material: usize,
    /// Whether the file uses KHR_mesh_quantization (integer vertex attributes allowed).
    pub quantized: bool,
    /// Morph-target weights (the node's, else the mesh's, else zeros; animated at `--time`).
    pub morph_weights: &'a [f32],
    /// The skin's joint matrices (joint world transform × inverse bind matrix), if the node
    /// is skinned; then `world_from_object` is ignored, as glTF specifies.
    pub skin: Option<&'a [Mat4]>,
}

/// Builds the world-space mesh of `primitive`, or `None` (with a warning) for a primitive
/// glint does not render: points, lines, or no triangles at all.
pub fn build(
    primitive: &::gltf::Primitive<'_>,
    ctx: &PrimitiveContext<'_>,
    warnings: &mut Vec<String>,
) -> Result<Option<Mesh>, LoadError> {
    let mode = primitive.mode();
    if matches!(
        mode,
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip
    ) {
        warnings.push(format!(
            "{}: {}: skipped: mode {mode:?} is not a surface; glint renders triangles only",
            ctx.origin.file.display(),
            ctx.label
        ));
        return Ok(None);
    }
    let fail = |problem: String| LoadError::Primitive {
        path: ctx.origin.file.to_path_buf(),
        primitive: ctx.label.clone(),
        problem,
    };
    let check = |accessor: &::gltf::Accessor<'_>, semantic: &str, allowed| {
        accessors::check(
            accessor,
            semantic,
            allowed,
            &ctx.label,
            ctx.buffers,
            ctx.origin,
        )
    };
    let reader = primitive.reader(|buffer| ctx.buffers.get(buffer.index()).map(Vec::as_slice));

    // POSITION is required by the schema, which the document passed.
    let Some(position_accessor) = primitive.get(&::gltf::Semantic::Positions) else {
        return Err(fail(
            "has no POSITION attribute (re-export the mesh)".into(),
        ));
    };
    let quantized = |core, extended| if ctx.quantized { extended } else { core };
    check(
        &position_accessor,
        "POSITION",
        quantized(VEC3_F32, quantization::POSITION),
    )?;
    let vertex_count = position_accessor.count();
    let mut object_positions: Vec<[f32; 3]> = quantization::read(&position_accessor, ctx.buffers);
    if let Some(vertex) = object_positions
        .iter()
        .position(|p| !p.iter().all(|c| c.is_finite()))
    {
        return Err(fail(format!(
            "POSITION accessor {}: vertex {vertex} is {:?}, not finite (fix the exporter's output)",
            position_accessor.index(),
            object_positions[vertex]
        )));
    }

    let vertex_indices: Vec<u32> = match primitive.indices() {
        Some(accessor) => {
            check(&accessor, "indices", INDICES)?;
            let count = accessor.count();
            let indices =
                accessors::collect_or_zeros(reader.read_indices().map(|i| i.into_u32()), count);
            if let Some(bad) = indices.iter().position(|&i| i as usize >= vertex_count) {
                return Err(fail(format!(
                    "indices accessor {}: index {bad} is {}, past the {vertex_count} vertices of POSITION accessor {} \
                     (the file is corrupt; re-export it)",
                    accessor.index(),
                    indices[bad],
                    position_accessor.index()
                )));
            }
            indices
        }
        None => {
            let Ok(count) = u32::try_from(vertex_count) else {
                return Err(fail(format!(
                    "has {vertex_count} vertices, more than 32-bit indices can address"
                )));
            };
            (0..count).collect()
        }
    };
    let mut triangles = assemble_triangles(mode, &vertex_indices);
    if mode == Mode::Triangles && !vertex_indices.len().is_multiple_of(3) {
        warnings.push(format!(
            "{}: {}: {} indices are not a multiple of 3; the last {} are ignored",
            ctx.origin.file.display(),
            ctx.label,
            vertex_indices.len(),
            vertex_indices.len() % 3
        ));
    }
    if triangles.is_empty() {
        warnings.push(format!(
            "{}: {}: skipped: it has no triangles",
            ctx.origin.file.display(),
            ctx.label
        ));
        return Ok(None);
    }

    // Optional attributes, each checked and required to match the vertex count.
    let same_count = |accessor: &::gltf::Accessor<'_>, semantic: &str| {
        if accessor.count() == vertex_count {
            Ok(())
        } else {
            Err(fail(format!(
                "{semantic} accessor {} has {} elements but POSITION has {vertex_count} (re-export the mesh)",
                accessor.index(),
                accessor.count()
            )))
        }
    };
    let mut object_normals: Option<Vec<[f32; 3]>> = match primitive.get(&::gltf::Semantic::Normals)
    {
        Some(accessor) => {
            check(
                &accessor,
                "NORMAL",
                quantized(VEC3_F32, quantization::NORMAL),
            )?;
            same_count(&accessor, "NORMAL")?;
            Some(quantization::read(&accessor, ctx.buffers))
        }
        None => None,
    };
    let mut object_tangents: Option<Vec<[f32; 4]>> =
        match primitive.get(&::gltf::Semantic::Tangents) {
            Some(accessor) => {
                check(
                    &accessor,
                    "TANGENT",
                    quantized(VEC4_F32, quantization::TANGENT),
                )?;
                same_count(&accessor, "TANGENT")?;
                Some(quantization::read(&accessor, ctx.buffers))
            }
            None => None,
        };
    let mut texcoords: [Option<Vec<Vec2>>; 2] = [None, None];
    for (set, slot) in texcoords.iter_mut().enumerate() {
        if let Some(accessor) = primitive.get(&::gltf::Semantic::TexCoords(set as u32)) {
            let semantic = format!("TEXCOORD_{set}");
            check(
                &accessor,
                &semantic,
                quantized(TEXCOORD, quantization::TEXCOORD),
            )?;
            same_count(&accessor, &semantic)?;
            let values: Vec<[f32; 2]> = quantization::read(&accessor, ctx.buffers);
            *slot = Some(values.into_iter().map(Vec2::from).collect());
        }
    }
    let colors = match primitive.get(&::gltf::Semantic::Colors(0)) {
        Some(accessor) => {
            check(&accessor, "COLOR_0", COLOR)?;
            same_count(&accessor, "COLOR_0")?;
            let values = reader.read_colors(0).map(|c| c.into_rgba_f32());
            let values: Vec<[f32; 4]> = accessors::collect_or_zeros(values, vertex_count);
            Some(values.into_iter().map(Vec4::from).collect())
        }
        None => None,
    };

    // Morph targets, then skinning (which lands in world space itself).
    let deform = morph::Targets {
        primitive,
        weights: ctx.morph_weights,
        label: &ctx.label,
        buffers: ctx.buffers,
        origin: ctx.origin,
    };
    deform.apply(
        &mut object_positions,
        object_normals.as_deref_mut(),
        object_tangents.as_deref_mut(),
    )?;
    let world = match ctx.skin {
        Some(joints) => {
            skin::apply(
                primitive,
                joints,
                &ctx.label,
                ctx.buffers,
                ctx.origin,
                &mut object_positions,
                object_normals.as_deref_mut(),
                object_tangents.as_deref_mut(),
            )?;
            Mat4::IDENTITY
        }
        None => ctx.world_from_object,
    };

    // To world space.
    let positions: Vec<Vec3> = object_positions
        .into_iter()
        .map(|p| world.transform_point3(Vec3::from(p)))
        .collect();
    if positions.iter().any(|p| !p.is_finite()) {
        return Err(fail(
            "positions overflow to infinity in world space (the node transforms scale them too far)".into(),
        ));
    }
    let linear = Mat3::from_mat4(world);
    let mirrored = linear.determinant() < 0.0;
    let normal_matrix = normal_transform(linear);
    let normals = object_normals.map(|normals| {
        normals
            .into_iter()
            .map(|n| (normal_matrix * Vec3::from(n)).normalize_or_zero())
            .collect()
    });
    // A mirroring transform flips the tangent frame's handedness: n' × t' = −M(n × t) for a
    // reflection M, so the bitangent sign w must flip to keep b' = M b.
    let handedness = if mirrored { -1.0 } else { 1.0 };
    let tangents = object_tangents.map(|tangents| {
        tangents
            .into_iter()
            .map(|[x, y, z, w]| {
                (linear * Vec3::new(x, y, z))
                    .normalize_or_zero()
                    .extend(w * handedness)
            })
            .collect()
    });
    // A mirroring transform turns counter-clockwise triangles clockwise: swap two corners so
    // that front faces (and the geometric normal) still face outwards.
    if mirrored {
        for triangle in &mut triangles {
            triangle.swap(1, 2);
        }
    }

    Ok(Some(Mesh {
        name: ctx.label.clone(),
        positions,
        indices: triangles,
        normals,
        tangents,
        texcoords,
        colors,
        material: ctx.material,
        // The caller knows the node.
        node: None,
        instances: Vec::new(),
    }))
}

/// The matrix that maps object-space normals to world space for the node transform's linear
/// part (see [`crate::accel::instance::normal_matrix`], which placements use too).
pub fn normal_transform(linear: Mat3) -> Mat3 {
    Mat3::from(crate::accel::instance::normal_matrix(glam::Mat3A::from(
        linear,
    )))
}

/// Triangles (counter-clockwise in the file's winding) from a primitive's vertex indices.
///
/// Strips and fans follow glTF's definitions: strip triangle i is (v_i, v_{i+1+i%2},
/// v_{i+2−i%2}), which alternates the order so that every triangle keeps the strip's
/// orientation; fan triangle i is (v_{i+1}, v_{i+2}, v_0).
pub fn assemble_triangles(mode: Mode, indices: &[u32]) -> Vec<[u32; 3]> {
    match mode {
        Mode::Triangles => indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect(),
        Mode::TriangleStrip => (0..indices.len().saturating_sub(2))
            .map(|i| {
                let odd = i % 2;
                [indices[i], indices[i + 1 + odd], indices[i + 2 - odd]]
            })
            .collect(),
        Mode::TriangleFan => (0..indices.len().saturating_sub(2))
            .map(|i| [indices[i + 1], indices[i + 2], indices[0]])
            .collect(),
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip => Vec::new(),
    }
}
