//! EXT_mesh_gpu_instancing, flattened: one world-space copy of the node's mesh per instance.
//!
//! The extension gives a node per-instance TRANSLATION, ROTATION and SCALE accessors (any
//! subset; missing ones are identity); instance `i` is drawn at
//! `world_from_node · T(tᵢ) · R(rᵢ) · S(sᵢ)`. glint copies the mesh once per instance,
//! so memory grows with the instance count; a two-level acceleration structure (one
//! geometry, many instances) is the accel layer's business and not done here yet.

use super::LoadError;
use super::accessors;
use super::nodes::node_label;
use super::quantization::{self, INSTANCE_ROTATION, INSTANCE_VEC3};
use super::source::Origin;
use glam::{Mat4, Quat, Vec3};

const EXTENSION: &str = "EXT_mesh_gpu_instancing";

/// The most vertices one instanced node may flatten into (2²⁸: about 10 GiB of positions,
/// normals and texture coordinates). Flattening multiplies the mesh by the instance count,
/// so a small file could otherwise ask for more memory than any machine has.
const MAX_FLATTENED_VERTICES: u64 = 1 << 28;

/// Refuses, before anything is copied, an instanced node whose flattened copies would
/// exceed [`MAX_FLATTENED_VERTICES`].
fn check_flattened_size(
    node: &::gltf::Node<'_>,
    mesh: &::gltf::Mesh<'_>,
    instances: usize,
    origin: Origin<'_>,
) -> Result<(), LoadError> {
    let per_copy: u64 = mesh
        .primitives()
        .filter_map(|p| p.get(&::gltf::Semantic::Positions))
        .map(|a| a.count() as u64)
        .sum();
    let total = per_copy.saturating_mul(instances as u64);
    if total > MAX_FLATTENED_VERTICES {
        return Err(LoadError::Node {
            path: origin.file.to_path_buf(),
            what: format!("{} / {EXTENSION}", node_label(node)),
            problem: format!(
                "{instances} instances × {per_copy} vertices would flatten to {total} vertices, more than \
                 glint's limit of {MAX_FLATTENED_VERTICES}: glint copies each instance for now (reduce the \
                 instance count or the mesh)"
            ),
        });
    }
    Ok(())
}

/// The node-local transforms of the node's instances, or `None` if it is not instanced.
pub fn transforms(
    node: &::gltf::Node<'_>,
    document: &::gltf::Document,
    buffers: &[Vec<u8>],
    origin: Origin<'_>,
) -> Result<Option<Vec<Mat4>>, LoadError> {
    let Some(extension) = node.extension_value(EXTENSION) else {
        return Ok(None);
    };
    let label = format!("{} / {EXTENSION}", node_label(node));
    let fail = |problem: String| LoadError::Node {
        path: origin.file.to_path_buf(),
        what: label.clone(),
        problem,
    };
    let attributes = extension
        .get("attributes")
        .and_then(serde_json::Value::as_object)
        .ok_or_else(|| fail("has no `attributes` object (re-export the scene)".into()))?;
    let accessor = |name: &str| -> Result<Option<::gltf::Accessor<'_>>, LoadError> {
        let Some(value) = attributes.get(name) else {
            return Ok(None);
        };
        let index = value
            .as_u64()
            .and_then(|i| usize::try_from(i).ok())
            .ok_or_else(|| fail(format!("{name} is not an accessor index")))?;
        document.accessors().nth(index).map(Some).ok_or_else(|| {
            fail(format!(
                "{name} refers to accessor {index}, but the file has only {} accessors",
                document.accessors().len()
            ))
        })
    };
    let translation = accessor("TRANSLATION")?;
    let rotation = accessor("ROTATION")?;
    let scale = accessor("SCALE")?;
    let mut count = None;
    for (name, a, allowed) in [
        ("TRANSLATION", &translation, INSTANCE_VEC3),
        ("ROTATION", &rotation, INSTANCE_ROTATION),
        ("SCALE", &scale, INSTANCE_VEC3),
    ] {
        let Some(a) = a else { continue };
        accessors::check(a, name, allowed, &label, buffers, origin)?;
        match count {
            None => count = Some(a.count()),
            Some(c) if c != a.count() => {
                return Err(fail(format!(
                    "{name} accessor {} has {} instances, others have {c} (re-export the scene)",
                    a.index(),
                    a.count()
                )));
            }
            Some(_) => {}
        }
    }
    let Some(count) = count else {
        return Err(fail(
            "has none of TRANSLATION, ROTATION, SCALE (re-export the scene)".into(),
        ));
    };
    if let Some(mesh) = node.mesh() {
        check_flattened_size(node, &mesh, count, origin)?;
    }
    let read3 =
        |a: &Option<::gltf::Accessor<'_>>| a.as_ref().map(|a| quantization::read::<3>(a, buffers));
    let translations = read3(&translation);
    let scales = read3(&scale);
    let rotations = rotation
        .as_ref()
        .map(|a| quantization::read::<4>(a, buffers));
    let mut out = Vec::with_capacity(count);
    for i in 0..count {
        let t = translations
            .as_ref()
            .map_or(Vec3::ZERO, |v| Vec3::from(v[i]));
        let s = scales.as_ref().map_or(Vec3::ONE, |v| Vec3::from(v[i]));
        let r = match &rotations {
            Some(v) => {
                let q = Quat::from_array(v[i]);
                if q.length_squared().is_nan() || q.length_squared() <= 0.0 {
                    return Err(fail(format!("instance {i} has a zero or NaN rotation")));
                }
                q.normalize()
            }
            None => Quat::IDENTITY,
        };
        let m = Mat4::from_scale_rotation_translation(s, r, t);
        if !m.is_finite() {
            return Err(fail(format!(
                "instance {i} has a NaN or infinite transform"
            )));
        }
        out.push(m);
    }
    Ok(Some(out))
}
