//! Flattening the node hierarchy: each node's world matrix, composed down the tree.

use super::LoadError;
use super::animation::Pose;
use super::source::Origin;
use glam::{Mat4, Quat, Vec3};

/// A node reached from the rendered scene, with its world transform.
pub struct PlacedNode<'a> {
    /// The node.
    pub node: ::gltf::Node<'a>,
    /// World-from-node transform (parent transforms composed with the node's own).
    pub world_from_node: Mat4,
}

/// How a node is named in messages: `node "Wheel"` or, without a name, `node 7`.
pub fn node_label(node: &::gltf::Node<'_>) -> String {
    match node.name() {
        Some(name) => format!("node \"{name}\""),
        None => format!("node {}", node.index()),
    }
}

/// Every node of the scene to render, parents before children (depth-first, in the file's
/// child order), posed by `pose`. The scene is `scene` if given, else the file's default
/// scene, else scene 0; a file without scenes gets its root nodes rendered, with a warning.
pub fn flatten<'a>(
    document: &'a ::gltf::Document,
    scene: Option<usize>,
    pose: &Pose,
    origin: Origin<'_>,
    warnings: &mut Vec<String>,
) -> Result<Vec<PlacedNode<'a>>, LoadError> {
    let chosen =
        match scene {
            Some(index) => Some(document.scenes().nth(index).ok_or_else(|| {
                LoadError::Invalid {
                    path: origin.file.to_path_buf(),
                    message: format!(
                        "scene {index} was asked for, but the file has {} scenes (pick 0..{})",
                        document.scenes().len(),
                        document.scenes().len().saturating_sub(1)
                    ),
                }
            })?),
            None => document
                .default_scene()
                .or_else(|| document.scenes().next()),
        };
    let roots: Vec<::gltf::Node<'a>> = match chosen {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut has_parent = vec![false; document.nodes().len()];
            for child in document.nodes().flat_map(|n| n.children()) {
                has_parent[child.index()] = true;
            }
            let roots: Vec<_> = document
                .nodes()
                .filter(|n| !has_parent[n.index()])
                .collect();
            if !roots.is_empty() {
                warnings.push(format!(
                    "{}: the file defines no scene; rendering its {} root nodes",
                    origin.file.display(),
                    roots.len()
                ));
            }
            roots
        }
    };

    let mut visited = vec![false; document.nodes().len()];
    let mut placed = Vec::new();
    // An explicit stack: a deep hierarchy must not overflow the call stack.
    let mut stack: Vec<(::gltf::Node<'a>, Mat4)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, Mat4::IDENTITY))
        .collect();
    while let Some((node, world_from_parent)) = stack.pop() {
        if std::mem::replace(&mut visited[node.index()], true) {
            return Err(LoadError::Node {
                path: origin.file.to_path_buf(),
                what: node_label(&node),
                problem: "is reached twice from the scene (a cycle or a node with two parents); glTF nodes must form trees"
                    .into(),
            });
        }
        let world_from_node = world_from_parent * local_transform(&node, pose, origin)?;
        stack.extend(
            node.children()
                .collect::<Vec<_>>()
                .into_iter()
                .rev()
                .map(|c| (c, world_from_node)),
        );
        placed.push(PlacedNode {
            node,
            world_from_node,
        });
    }
    Ok(placed)
}

/// The node's own transform, from its matrix or its translation · rotation · scale, with
/// the properties `pose` animates replacing the file's (glTF forbids animating a node that
/// has a matrix; such a node keeps its matrix).
pub fn local_transform(
    node: &::gltf::Node<'_>,
    pose: &Pose,
    origin: Origin<'_>,
) -> Result<Mat4, LoadError> {
    let fail = |problem: &str| LoadError::Node {
        path: origin.file.to_path_buf(),
        what: node_label(node),
        problem: problem.to_string(),
    };
    let matrix = match node.transform() {
        ::gltf::scene::Transform::Matrix { matrix } => Mat4::from_cols_array_2d(&matrix),
        ::gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let animated = pose.node(node.index());
            let translation = animated
                .and_then(|p| p.translation)
                .map_or(translation, |v| v.to_array());
            let scale = animated
                .and_then(|p| p.scale)
                .map_or(scale, |v| v.to_array());
            let rotation = animated
                .and_then(|p| p.rotation)
                .unwrap_or(Quat::from_array(rotation));
            // Exporters write quaternions a few ulps off unit length; a zero one is an error.
            if rotation.length_squared().is_nan() || rotation.length_squared() <= 0.0 {
                return Err(fail(
                    "has a zero or NaN rotation quaternion (fix the node's rotation)",
                ));
            }
            Mat4::from_scale_rotation_translation(
                Vec3::from(scale),
                rotation.normalize(),
                Vec3::from(translation),
            )
        }
    };
    if !matrix.is_finite() {
        return Err(fail(
            "has a NaN or infinite transform (fix the node's matrix or TRS)",
        ));
    }
    Ok(matrix)
}
