//! MikkTSpace tangents for meshes whose material has a normal map but whose file supplies no
//! `TANGENT` attribute, as the glTF specification asks ("client implementations SHOULD
//! calculate tangents using default MikkTSpace algorithms with the specified vertex
//! positions, normals, and texture coordinates associated with the normal texture").
//!
//! The algorithm is the `bevy_mikktspace` crate's (a safe port of Mikkelsen's reference
//! implementation, the one Blender uses, with its default, byte-compatible features). It
//! runs on the world-space mesh the loader built, so a skinned, morphed, instanced or mirrored
//! mesh gets tangents that fit the geometry it renders with; for a rigid node transform this
//! is the object-space result rotated, for a non-uniform scale it differs slightly from
//! tangents generated in object space and then transformed.
//!
//! MikkTSpace writes one tangent per triangle corner: a vertex shared by triangles of
//! different tangent groups (a UV mirror seam, a hard edge) gets different tangents from
//! them. [`generate`] keeps one tangent per vertex by giving such corners copies of the vertex
//! (same position, normal, texture coordinates, colour), so the geometry the ray backends see
//! is unchanged.
//!
//! Texture coordinates are handed to MikkTSpace with v flipped (`1 − v`), as tools with
//! MikkTSpace's v-up convention (Blender) read glTF: without the flip every generated
//! handedness would be negated and normal maps' green channel inverted (the Khronos
//! NormalTangentTest shows its normal-mapped hemispheres as dents then).
//!
//! Only meshes that need tangents get them: [`generate`] is called by the loader for meshes
//! whose material has a normal texture and no supplied tangents, and nowhere else.

use super::Mesh;
use glam::{Vec2, Vec3, Vec4};
use std::collections::HashMap;

/// Why tangents could not be generated for a mesh.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TangentError {
    /// The normal texture reads a texture-coordinate set the mesh does not have.
    #[error(
        "its normal texture (or anisotropy) reads TEXCOORD_{0}, which the mesh lacks, so no \
         tangents can be generated and the normal map (or anisotropy) is ignored (add the UV \
         set, or TANGENTs, to the mesh)"
    )]
    MissingTexcoords(usize),
    /// Splitting vertices at tangent seams would pass 32-bit vertex indices.
    #[error(
        "splitting vertices at tangent seams would need more than 2³² vertices; the normal map \
         is ignored (split the mesh)"
    )]
    TooManyVertices,
}

/// What [`generate`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Generated {
    /// Vertices added where a vertex had different tangents in different triangles.
    pub split_vertices: usize,
}

/// The mesh as MikkTSpace reads it, and the per-corner results it writes.
struct Input<'a> {
    positions: &'a [Vec3],
    /// Vertex normals, or `None` for flat shading (then each face's own normal).
    normals: Option<&'a [Vec3]>,
    uvs: &'a [Vec2],
    indices: &'a [[u32; 3]],
    /// One result per triangle corner, `3 · triangle + corner`.
    corners: Vec<Option<Vec4>>,
}

impl Input<'_> {
    fn vertex(&self, face: usize, vert: usize) -> usize {
        // The loader checked every index against the vertex count; a bad one reads vertex 0
        // (its attributes are then only wrong, never out of bounds).
        self.indices
            .get(face)
            .and_then(|t| t.get(vert))
            .map_or(0, |&i| i as usize)
    }

    fn position_of(&self, index: usize) -> Vec3 {
        self.positions.get(index).copied().unwrap_or(Vec3::ZERO)
    }
}

impl bevy_mikktspace::Geometry for Input<'_> {
    fn num_faces(&self) -> usize {
        self.indices.len()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.position_of(self.vertex(face, vert)).to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        match self.normals {
            Some(normals) => normals
                .get(self.vertex(face, vert))
                .copied()
                .unwrap_or(Vec3::ZERO)
                .to_array(),
            None => {
                // glTF's flat normals: the face's own (counter-clockwise front faces).
                let [a, b, c] = [0, 1, 2].map(|v| self.position_of(self.vertex(face, v)));
                (b - a).cross(c - a).normalize_or_zero().to_array()
            }
        }
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let uv = self
            .uvs
            .get(self.vertex(face, vert))
            .copied()
            .unwrap_or(Vec2::ZERO);
        // glTF's v axis points down the image, MikkTSpace's (like OpenGL's) up: flipped, the
        // bitangent w·(n × t) points toward decreasing glTF v, the image's up, which is where
        // glTF normal maps put +green. (Blender flips v on import for the same reason.)
        [uv.x, 1.0 - uv.y]
    }

    fn set_tangent(
        &mut self,
        tangent_space: Option<bevy_mikktspace::TangentSpace>,
        face: usize,
        vert: usize,
    ) {
        if let Some(slot) = self.corners.get_mut(3 * face + vert) {
            *slot = tangent_space.map(|t| Vec4::from(t.tangent_encoded()));
        }
    }
}

/// Generates MikkTSpace tangents (xyz unit, w = ±1 handedness) for `mesh` from its positions,
/// normals (flat ones if it has none) and texture-coordinate set `texcoord`, splitting
/// vertices where neighbouring triangles disagree. Supplied tangents are replaced.
///
/// A corner MikkTSpace leaves without a tangent (a degenerate triangle with no usable
/// neighbour) gets an arbitrary tangent perpendicular to its normal, so the mesh always has a
/// complete tangent array.
pub fn generate(mesh: &mut Mesh, texcoord: usize) -> Result<Generated, TangentError> {
    let Some(uvs) = mesh.texcoords.get(texcoord).and_then(|s| s.as_deref()) else {
        return Err(TangentError::MissingTexcoords(texcoord));
    };
    let mut input = Input {
        positions: &mesh.positions,
        normals: mesh.normals.as_deref(),
        uvs,
        indices: &mesh.indices,
        corners: vec![None; 3 * mesh.indices.len()],
    };
    // The crate's error type has no variants: generation cannot fail.
    if bevy_mikktspace::generate_tangents(&mut input).is_err() {
        return Err(TangentError::MissingTexcoords(texcoord));
    }
    let corners = std::mem::take(&mut input.corners);

    let vertex_count = mesh.positions.len();
    // Distinct fields, borrowed apart: the indices are rewritten while the normals are read.
    let normals = mesh.normals.as_deref();
    let fallback = |vertex: usize| -> Vec4 {
        let n = normals
            .and_then(|n| n.get(vertex))
            .copied()
            .unwrap_or(Vec3::Z)
            .normalize_or(Vec3::Z);
        n.any_orthonormal_vector().extend(1.0)
    };
    let mut tangents: Vec<Option<Vec4>> = vec![None; vertex_count];
    // Copies made so far: (original vertex, tangent bits) → new vertex index.
    let mut copies: HashMap<(u32, [u32; 4]), u32> = HashMap::new();
    let mut sources: Vec<u32> = Vec::new();
    let mut extra: Vec<Vec4> = Vec::new();
    for (face, triangle) in mesh.indices.iter_mut().enumerate() {
        for (corner, index) in triangle.iter_mut().enumerate() {
            let vertex = *index as usize;
            let tangent = corners
                .get(3 * face + corner)
                .copied()
                .flatten()
                .unwrap_or_else(|| fallback(vertex));
            match tangents.get_mut(vertex) {
                Some(slot @ None) => *slot = Some(tangent),
                Some(Some(existing)) if *existing == tangent => {}
                Some(Some(_)) => {
                    let key = (*index, tangent.to_array().map(f32::to_bits));
                    let copy = match copies.get(&key) {
                        Some(&copy) => copy,
                        None => {
                            let Ok(copy) = u32::try_from(vertex_count + extra.len()) else {
                                return Err(TangentError::TooManyVertices);
                            };
                            copies.insert(key, copy);
                            sources.push(*index);
                            extra.push(tangent);
                            copy
                        }
                    };
                    *index = copy;
                }
                // Out-of-range index (the loader prevents it): leave the corner alone.
                None => {}
            }
        }
    }
    let mut all: Vec<Vec4> = tangents
        .into_iter()
        .enumerate()
        .map(|(vertex, t)| t.unwrap_or_else(|| fallback(vertex)))
        .collect();
    all.extend(extra);
    duplicate_vertices(mesh, &sources);
    mesh.tangents = Some(all);
    Ok(Generated {
        split_vertices: sources.len(),
    })
}

/// Appends a copy of every vertex in `sources` to each per-vertex attribute (tangents are
/// set by the caller).
fn duplicate_vertices(mesh: &mut Mesh, sources: &[u32]) {
    fn extend<T: Copy + Default>(values: &mut Vec<T>, sources: &[u32]) {
        values.reserve(sources.len());
        for &s in sources {
            let value = values.get(s as usize).copied().unwrap_or_default();
            values.push(value);
        }
    }
    extend(&mut mesh.positions, sources);
    if let Some(normals) = &mut mesh.normals {
        extend(normals, sources);
    }
    for set in mesh.texcoords.iter_mut().flatten() {
        extend(set, sources);
    }
    if let Some(colors) = &mut mesh.colors {
        extend(colors, sources);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two quads side by side in the z = 0 plane, facing +Z, sharing the middle edge; the right
    /// one's u runs backwards (a UV mirror seam at the shared edge) when `mirrored`.
    fn two_quads(mirrored: bool) -> Mesh {
        let positions = vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        ];
        let right_u = if mirrored { 0.0 } else { 2.0 };
        // glTF v points down the image: v = 1 at the bottom (y = −1).
        let uvs = vec![
            Vec2::new(0.0, 1.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(0.0, 0.0),
            Vec2::new(right_u, 1.0),
            Vec2::new(right_u, 0.0),
        ];
        Mesh {
            positions,
            indices: vec![[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]],
            normals: Some(vec![Vec3::Z; 6]),
            texcoords: [Some(uvs), None],
            ..Mesh::default()
        }
    }

    #[test]
    fn an_unmirrored_mapping_gets_the_u_direction_and_positive_handedness() {
        let mut mesh = two_quads(false);
        let result = generate(&mut mesh, 0).unwrap();
        assert_eq!(result.split_vertices, 0);
        for t in mesh.tangents.as_ref().unwrap() {
            // Tangent along +u = +x; bitangent w·(n × t) = +y, toward decreasing v.
            assert!((t.truncate() - Vec3::X).length() < 1e-5, "{t}");
            assert_eq!(t.w, 1.0);
        }
    }

    #[test]
    fn a_uv_mirror_seam_splits_the_shared_vertices() {
        let mut mesh = two_quads(true);
        let result = generate(&mut mesh, 0).unwrap();
        // The two vertices on the seam get one copy each; every attribute array grows with them.
        assert_eq!(result.split_vertices, 2);
        assert_eq!(mesh.positions.len(), 8);
        assert_eq!(mesh.normals.as_ref().unwrap().len(), 8);
        assert_eq!(mesh.texcoords[0].as_ref().unwrap().len(), 8);
        let tangents = mesh.tangents.as_ref().unwrap();
        assert_eq!(tangents.len(), 8);
        for (face, triangle) in mesh.indices.iter().enumerate() {
            let (dir, w) = if face < 2 {
                (Vec3::X, 1.0)
            } else {
                (-Vec3::X, -1.0)
            };
            for &v in triangle {
                let t = tangents[v as usize];
                assert!(
                    (t.truncate() - dir).length() < 1e-5 && t.w == w,
                    "face {face}: {t}"
                );
            }
        }
        // The copies sit where the originals do.
        assert_eq!(mesh.positions[6], mesh.positions[1]);
        assert_eq!(mesh.positions[7], mesh.positions[2]);
    }

    #[test]
    fn a_missing_uv_set_is_an_error_and_leaves_the_mesh_alone() {
        let mut mesh = two_quads(false);
        assert_eq!(
            generate(&mut mesh, 1),
            Err(TangentError::MissingTexcoords(1))
        );
        assert!(mesh.tangents.is_none());
        assert_eq!(mesh.positions.len(), 6);
    }

    #[test]
    fn flat_meshes_use_their_face_normals() {
        let mut mesh = two_quads(false);
        mesh.normals = None;
        generate(&mut mesh, 0).unwrap();
        assert!(
            mesh.tangents
                .unwrap()
                .iter()
                .all(|t| (t.truncate() - Vec3::X).length() < 1e-5)
        );
    }
}
