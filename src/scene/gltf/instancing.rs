//! EXT_mesh_gpu_instancing: the node-local transforms of a node's instances.
//!
//! The extension gives a node per-instance TRANSLATION, ROTATION and SCALE accessors (any
//! subset; missing ones are identity); instance `i` is drawn at
//! `world_from_node · T(tᵢ) · R(rᵢ) · S(sᵢ)`. The loader stores the mesh once and each
//! instance as a placement of it (`sharing`), so memory grows with the unique geometry.

use super::LoadError;
use super::accessors::{self, Layout};
use super::nodes::node_label;
use super::quantization::{self, INSTANCE_ROTATION, INSTANCE_VEC3};
use super::source::Origin;
use glam::{Mat4, Quat, Vec3};

const EXTENSION: &str = "EXT_mesh_gpu_instancing";

/// The most instances one node may have (2²⁴): each costs a placement (about 160 bytes) and an
/// instance in each backend's top level.
const MAX_INSTANCES: usize = 1 << 24;

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
    // The counts first: the instance limit is the one to name when a count is hostile.
    let present: Vec<(&str, &::gltf::Accessor<'_>, &[Layout])> = [
        ("TRANSLATION", &translation, INSTANCE_VEC3),
        ("ROTATION", &rotation, INSTANCE_ROTATION),
        ("SCALE", &scale, INSTANCE_VEC3),
    ]
    .into_iter()
    .filter_map(|(name, a, allowed)| a.as_ref().map(|a| (name, a, allowed)))
    .collect();
    let Some(count) = present.first().map(|(_, a, _)| a.count()) else {
        return Err(fail(
            "has none of TRANSLATION, ROTATION, SCALE (re-export the scene)".into(),
        ));
    };
    if let Some((name, a, _)) = present.iter().find(|(_, a, _)| a.count() != count) {
        return Err(fail(format!(
            "{name} accessor {} has {} instances, others have {count} (re-export the scene)",
            a.index(),
            a.count()
        )));
    }
    if count > MAX_INSTANCES {
        return Err(fail(format!(
            "has {count} instances, more than glint's limit of {MAX_INSTANCES} (split the node)"
        )));
    }
    for (name, a, allowed) in &present {
        accessors::check(a, name, allowed, &label, buffers, origin)?;
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
