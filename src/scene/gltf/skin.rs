//! Skins: vertices posed by a weighted blend of their joints' transforms.
//!
//! glTF's linear blend skinning puts a vertex in world space directly:
//!
//! ```text
//! p' = Σₖ wₖ · Jⱼₖ · p,   Jⱼ = world_from_joint(j) · inverseBindMatrix(j)
//! ```
//!
//! with joints `jₖ` and weights `wₖ` from JOINTS_n / WEIGHTS_n (n = 0, 1, …), the joint
//! transforms from the current pose (the file's node transforms at rest, or as animated at
//! `--time`). The skinned node's own transform is not applied (the spec says so: the joints
//! place the mesh). Normals go through the blended matrix's inverse transpose, tangents
//! through its linear part. A vertex whose weights are all zero keeps its bind position
//! (identity) rather than collapsing to the origin.

use super::LoadError;
use super::accessors::{self, Layout};
use super::animation::Pose;
use super::nodes::{self, node_label};
use super::primitives::normal_transform;
use super::quantization;
use super::source::Origin;
use ::gltf::accessor::{DataType, Dimensions};
use glam::{Mat3, Mat4, Vec3};

const MAT4_F32: &[Layout] = &[Layout {
    dimensions: Dimensions::Mat4,
    data_type: DataType::F32,
    normalized: false,
}];
const JOINTS: &[Layout] = &[
    Layout {
        dimensions: Dimensions::Vec4,
        data_type: DataType::U8,
        normalized: false,
    },
    Layout {
        dimensions: Dimensions::Vec4,
        data_type: DataType::U16,
        normalized: false,
    },
];
const WEIGHTS: &[Layout] = &[
    Layout {
        dimensions: Dimensions::Vec4,
        data_type: DataType::F32,
        normalized: false,
    },
    Layout {
        dimensions: Dimensions::Vec4,
        data_type: DataType::U8,
        normalized: true,
    },
    Layout {
        dimensions: Dimensions::Vec4,
        data_type: DataType::U16,
        normalized: true,
    },
];

/// World-from-node transforms of every node of the file (not only the rendered scene's:
/// a skin's joints may sit anywhere), under `pose`. Nodes reached twice or through a cycle
/// keep the first transform found; `nodes::flatten` reports such files for the scene itself.
pub fn world_matrices(
    document: &::gltf::Document,
    pose: &Pose,
    origin: Origin<'_>,
) -> Result<Vec<Mat4>, LoadError> {
    let count = document.nodes().len();
    let mut has_parent = vec![false; count];
    for child in document.nodes().flat_map(|n| n.children()) {
        has_parent[child.index()] = true;
    }
    let mut world = vec![Mat4::IDENTITY; count];
    let mut done = vec![false; count];
    let mut stack: Vec<(::gltf::Node<'_>, Mat4)> = document
        .nodes()
        .filter(|n| !has_parent[n.index()])
        .map(|n| (n, Mat4::IDENTITY))
        .collect();
    while let Some((node, parent)) = stack.pop() {
        if std::mem::replace(&mut done[node.index()], true) {
            continue;
        }
        let matrix = parent * nodes::local_transform(&node, pose, origin)?;
        world[node.index()] = matrix;
        stack.extend(node.children().map(|c| (c, matrix)));
    }
    Ok(world)
}

/// The joint matrices `Jⱼ` of `node`'s skin, from the world transforms of every node.
pub fn joint_matrices(
    node: &::gltf::Node<'_>,
    skin: &::gltf::Skin<'_>,
    world: &[Mat4],
    buffers: &[Vec<u8>],
    origin: Origin<'_>,
) -> Result<Vec<Mat4>, LoadError> {
    let label = format!("{} / skin {}", node_label(node), skin.index());
    let joint_count = skin.joints().len();
    let inverse_bind: Vec<Mat4> = match skin.inverse_bind_matrices() {
        Some(accessor) => {
            accessors::check(
                &accessor,
                "inverseBindMatrices",
                MAT4_F32,
                &label,
                buffers,
                origin,
            )?;
            if accessor.count() < joint_count {
                return Err(LoadError::Primitive {
                    path: origin.file.to_path_buf(),
                    primitive: label,
                    problem: format!(
                        "inverseBindMatrices accessor {} has {} matrices for {joint_count} joints (re-export the skin)",
                        accessor.index(),
                        accessor.count()
                    ),
                });
            }
            quantization::read::<16>(&accessor, buffers)
                .iter()
                .map(Mat4::from_cols_array)
                .collect()
        }
        None => vec![Mat4::IDENTITY; joint_count],
    };
    Ok(skin
        .joints()
        .zip(inverse_bind)
        .map(|(joint, ibm)| world.get(joint.index()).copied().unwrap_or(Mat4::IDENTITY) * ibm)
        .collect())
}

/// Skins the primitive's object-space attributes into world space, in place.
#[allow(clippy::too_many_arguments)]
pub fn apply(
    primitive: &::gltf::Primitive<'_>,
    joints: &[Mat4],
    label: &str,
    buffers: &[Vec<u8>],
    origin: Origin<'_>,
    positions: &mut [[f32; 3]],
    normals: Option<&mut [[f32; 3]]>,
    tangents: Option<&mut [[f32; 4]]>,
) -> Result<(), LoadError> {
    let fail = |problem: String| LoadError::Primitive {
        path: origin.file.to_path_buf(),
        primitive: label.to_string(),
        problem,
    };
    let vertex_count = positions.len();
    let mut blended = vec![Mat4::ZERO; vertex_count];
    let mut total = vec![0.0f32; vertex_count];
    for set in 0u32.. {
        let (Some(joint_accessor), Some(weight_accessor)) = (
            primitive.get(&::gltf::Semantic::Joints(set)),
            primitive.get(&::gltf::Semantic::Weights(set)),
        ) else {
            if set == 0 {
                return Err(fail(
                    "belongs to a skinned node but has no JOINTS_0 / WEIGHTS_0 (re-export the skin)".into(),
                ));
            }
            break;
        };
        let joints_name = format!("JOINTS_{set}");
        let weights_name = format!("WEIGHTS_{set}");
        accessors::check(
            &joint_accessor,
            &joints_name,
            JOINTS,
            label,
            buffers,
            origin,
        )?;
        accessors::check(
            &weight_accessor,
            &weights_name,
            WEIGHTS,
            label,
            buffers,
            origin,
        )?;
        for (name, accessor) in [
            (&joints_name, &joint_accessor),
            (&weights_name, &weight_accessor),
        ] {
            if accessor.count() != vertex_count {
                return Err(fail(format!(
                    "{name} accessor {} has {} elements but POSITION has {vertex_count} (re-export the mesh)",
                    accessor.index(),
                    accessor.count()
                )));
            }
        }
        let joint_ids = quantization::read::<4>(&joint_accessor, buffers);
        let weights = quantization::read::<4>(&weight_accessor, buffers);
        for (v, (ids, ws)) in joint_ids.iter().zip(&weights).enumerate() {
            for (&id, &w) in ids.iter().zip(ws) {
                if w == 0.0 {
                    continue;
                }
                let Some(joint) = joints.get(id as usize) else {
                    return Err(fail(format!(
                        "{joints_name} accessor {}: vertex {v} names joint {id}, but the skin has {} joints \
                         (the file is corrupt; re-export it)",
                        joint_accessor.index(),
                        joints.len()
                    )));
                };
                blended[v] += *joint * w;
                total[v] += w;
            }
        }
    }
    for (m, &t) in blended.iter_mut().zip(&total) {
        if t == 0.0 {
            *m = Mat4::IDENTITY;
        }
    }
    for (p, m) in positions.iter_mut().zip(&blended) {
        *p = m.transform_point3(Vec3::from(*p)).to_array();
    }
    if let Some(normals) = normals {
        for (n, m) in normals.iter_mut().zip(&blended) {
            *n = (normal_transform(Mat3::from_mat4(*m)) * Vec3::from(*n)).to_array();
        }
    }
    if let Some(tangents) = tangents {
        for (t, m) in tangents.iter_mut().zip(&blended) {
            let xyz = Mat3::from_mat4(*m) * Vec3::new(t[0], t[1], t[2]);
            *t = [xyz.x, xyz.y, xyz.z, t[3]];
        }
    }
    Ok(())
}
