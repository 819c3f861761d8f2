//! Morph targets: a primitive's attributes displaced by weighted per-target deltas.
//!
//! glTF defines the morphed attribute as
//!
//! ```text
//! A(v) = A₀(v) + Σᵢ wᵢ · Δᵢ(v)
//! ```
//!
//! for POSITION, NORMAL and TANGENT (xyz; the handedness w is never morphed), with the
//! weights `wᵢ` from the node's `weights`, else the mesh's `weights`, else zero, and, at
//! `--time`, from an animation's `weights` channel. Normals and tangents are renormalised
//! later, when they go to world space. Morphing happens in object space, before skinning and
//! the node transform, as the spec orders it.

use super::LoadError;
use super::accessors;
use super::quantization::{self, MORPH_DIRECTION, MORPH_POSITION};
use super::source::Origin;

/// A primitive's morph targets and the weights to apply.
pub struct Targets<'a, 'p> {
    /// The primitive whose targets are applied.
    pub primitive: &'a ::gltf::Primitive<'p>,
    /// One weight per target; missing weights count as zero.
    pub weights: &'a [f32],
    /// `node "X" / mesh 3 / primitive 0`, for messages.
    pub label: &'a str,
    /// Buffer bytes.
    pub buffers: &'a [Vec<u8>],
    /// The file, for messages.
    pub origin: Origin<'a>,
}

impl Targets<'_, '_> {
    /// Adds every target with a non-zero weight to the attributes (in place). A target
    /// attribute whose base attribute is absent is ignored, as glTF allows.
    pub fn apply(
        &self,
        positions: &mut [[f32; 3]],
        mut normals: Option<&mut [[f32; 3]]>,
        mut tangents: Option<&mut [[f32; 4]]>,
    ) -> Result<(), LoadError> {
        for (index, target) in self.primitive.morph_targets().enumerate() {
            let weight = self.weights.get(index).copied().unwrap_or(0.0);
            if !weight.is_finite() {
                return Err(LoadError::Primitive {
                    path: self.origin.file.to_path_buf(),
                    primitive: self.label.to_string(),
                    problem: format!(
                        "morph target {index} has weight {weight}; weights must be finite"
                    ),
                });
            }
            // Zero weight: no work, and the target's data need not even be read.
            if weight == 0.0 {
                continue;
            }
            if let Some(accessor) = target.positions() {
                let deltas = self.deltas(
                    &accessor,
                    index,
                    "POSITION",
                    MORPH_POSITION,
                    positions.len(),
                )?;
                add(positions, &deltas, weight);
            }
            if let (Some(accessor), Some(normals)) = (target.normals(), normals.as_deref_mut()) {
                let deltas =
                    self.deltas(&accessor, index, "NORMAL", MORPH_DIRECTION, normals.len())?;
                add(normals, &deltas, weight);
            }
            if let (Some(accessor), Some(tangents)) = (target.tangents(), tangents.as_deref_mut()) {
                let deltas =
                    self.deltas(&accessor, index, "TANGENT", MORPH_DIRECTION, tangents.len())?;
                for (t, d) in tangents.iter_mut().zip(&deltas) {
                    for c in 0..3 {
                        t[c] += weight * d[c];
                    }
                }
            }
        }
        Ok(())
    }

    /// One target attribute's deltas, checked (layout, bounds, count).
    fn deltas(
        &self,
        accessor: &::gltf::Accessor<'_>,
        target: usize,
        attribute: &str,
        allowed: &[accessors::Layout],
        vertex_count: usize,
    ) -> Result<Vec<[f32; 3]>, LoadError> {
        let semantic = format!("morph target {target} {attribute}");
        accessors::check(
            accessor,
            &semantic,
            allowed,
            self.label,
            self.buffers,
            self.origin,
        )?;
        if accessor.count() != vertex_count {
            return Err(LoadError::Primitive {
                path: self.origin.file.to_path_buf(),
                primitive: self.label.to_string(),
                problem: format!(
                    "{semantic} accessor {} has {} elements but the primitive has {vertex_count} vertices \
                     (re-export the mesh)",
                    accessor.index(),
                    accessor.count()
                ),
            });
        }
        Ok(quantization::read(accessor, self.buffers))
    }
}

fn add(values: &mut [[f32; 3]], deltas: &[[f32; 3]], weight: f32) {
    for (v, d) in values.iter_mut().zip(deltas) {
        for c in 0..3 {
            v[c] += weight * d[c];
        }
    }
}

/// The weights a node's mesh is drawn with at rest: the node's `weights`, else the mesh's,
/// else none (all zero).
pub fn default_weights(node: &::gltf::Node<'_>) -> Vec<f32> {
    node.weights()
        .or_else(|| node.mesh().and_then(|m| m.weights()))
        .map(<[f32]>::to_vec)
        .unwrap_or_default()
}
