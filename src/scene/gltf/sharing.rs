//! Which meshes are stored once and drawn as placements: a glTF mesh that is drawn more than
//! once with the same shape.
//!
//! Two draws of a mesh share its shape when neither is skinned (joints deform each copy on its
//! own) and their morph weights are equal bit for bit (the node's, else the mesh's, else
//! none, animated at `--time`). Every draw of such a group (each node, and each of an
//! EXT_mesh_gpu_instancing node's instances) becomes one [`Placement`] of one object-space
//! mesh per primitive, built at the group's first node; a mesh drawn once stays baked into
//! world space, exactly as before.

use super::nodes::PlacedNode;
use crate::scene::Placement;
use glam::{Affine3A, Mat4};
use std::collections::HashMap;

/// What a placed node draws.
pub struct NodeMesh<'a> {
    /// The glTF mesh.
    pub mesh: ::gltf::Mesh<'a>,
    /// Its morph weights at the rendered time.
    pub weights: Vec<f32>,
    /// Joint matrices, for a skinned node.
    pub joints: Option<Vec<Mat4>>,
    /// Node-local transforms of its copies (one identity copy without instancing).
    pub copies: Vec<Mat4>,
    /// Whether the node has EXT_mesh_gpu_instancing (for labels).
    pub instanced: bool,
}

/// A node's part in a shared mesh.
pub struct Share {
    /// Whether this node builds the group's meshes (the group's first node in traversal
    /// order); the others only contribute placements.
    pub first: bool,
    /// Every placement of the group, for its first node (empty for the others). Copies whose
    /// transform is singular or not finite are left out: they cover nothing.
    pub placements: Vec<Placement>,
}

/// The shares of every placed node.
pub struct Plan {
    by_node: Vec<Option<Share>>,
}

impl Plan {
    /// The share of placed node `index`, or `None` when its mesh is baked into world space.
    pub fn of(&self, index: usize) -> Option<&Share> {
        self.by_node.get(index).and_then(Option::as_ref)
    }
}

/// Groups the draws of `placed` (with `drawn[i]` what node `i` draws) into shared meshes.
pub fn plan(placed: &[PlacedNode<'_>], drawn: &[Option<NodeMesh<'_>>]) -> Plan {
    let mut groups: HashMap<(usize, Vec<u32>), Vec<usize>> = HashMap::new();
    for (index, draw) in drawn.iter().enumerate() {
        let Some(draw) = draw else { continue };
        if draw.joints.is_some() {
            continue;
        }
        let key = (
            draw.mesh.index(),
            draw.weights.iter().map(|w| w.to_bits()).collect(),
        );
        // Members are pushed in traversal order, so a group's first is its first node.
        groups.entry(key).or_default().push(index);
    }
    let mut by_node: Vec<Option<Share>> = (0..drawn.len()).map(|_| None).collect();
    for (_, members) in groups {
        let copies: usize = members
            .iter()
            .filter_map(|&i| drawn.get(i).and_then(Option::as_ref))
            .map(|d| d.copies.len())
            .sum();
        if copies < 2 {
            continue;
        }
        let mut placements = Vec::with_capacity(copies);
        for &i in &members {
            let (Some(Some(draw)), Some(node)) = (drawn.get(i), placed.get(i)) else {
                continue;
            };
            let id = u32::try_from(node.node.index()).ok();
            placements.extend(draw.copies.iter().filter_map(|local| {
                Placement::new(Affine3A::from_mat4(node.world_from_node * *local), id)
            }));
        }
        for (k, &i) in members.iter().enumerate() {
            by_node[i] = Some(Share {
                first: k == 0,
                placements: if k == 0 {
                    std::mem::take(&mut placements)
                } else {
                    Vec::new()
                },
            });
        }
    }
    Plan { by_node }
}
