//! Cameras and KHR_lights_punctual lights attached to nodes, placed in world space.

use super::LoadError;
use super::nodes::{PlacedNode, node_label};
use super::source::Origin;
use crate::scene::{Camera, Light, Projection};
use glam::{Mat4, Vec3};

/// The node's camera in world space, if it has one.
///
/// glTF cameras look down their −Z with +Y up. The world matrix's scale is removed by
/// Gram–Schmidt: the viewing direction is kept exactly, up is made orthogonal to it, and
/// right completes a right-handed frame (so a mirroring node does not mirror the image).
pub fn camera(placed: &PlacedNode<'_>, origin: Origin<'_>) -> Result<Option<Camera>, LoadError> {
    let Some(camera) = placed.node.camera() else {
        return Ok(None);
    };
    let what = match camera.name() {
        Some(name) => format!(
            "{} / camera {} \"{name}\"",
            node_label(&placed.node),
            camera.index()
        ),
        None => format!("{} / camera {}", node_label(&placed.node), camera.index()),
    };
    let fail = |problem: String| LoadError::Node {
        path: origin.file.to_path_buf(),
        what: what.clone(),
        problem,
    };
    let world = placed.world_from_node;
    let back = world.transform_vector3(Vec3::Z).normalize_or_zero();
    let up_hint = world.transform_vector3(Vec3::Y);
    let up = (up_hint - back * up_hint.dot(back)).normalize_or_zero();
    if back == Vec3::ZERO || up == Vec3::ZERO {
        return Err(fail(
            "the node's transform collapses the camera's axes (zero or degenerate scale)".into(),
        ));
    }
    let right = up.cross(back);
    let world_from_camera = Mat4::from_cols(
        right.extend(0.0),
        up.extend(0.0),
        back.extend(0.0),
        world.w_axis.truncate().extend(1.0),
    );
    let (znear, zfar) = match camera.projection() {
        ::gltf::camera::Projection::Perspective(p) => (p.znear(), p.zfar()),
        ::gltf::camera::Projection::Orthographic(o) => (o.znear(), Some(o.zfar())),
    };
    if !(znear.is_finite() && znear >= 0.0 && zfar.is_none_or(|f| f.is_finite() && f > znear)) {
        return Err(fail(format!(
            "znear {znear} and zfar {zfar:?} must be finite with 0 ≤ znear < zfar"
        )));
    }
    let projection = match camera.projection() {
        ::gltf::camera::Projection::Perspective(p) => {
            let yfov = p.yfov();
            if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
                return Err(fail(format!("yfov is {yfov} rad; it must lie in (0, π)")));
            }
            let aspect_ratio = p.aspect_ratio();
            if let Some(aspect) = aspect_ratio
                && !(aspect > 0.0 && aspect.is_finite())
            {
                return Err(fail(format!(
                    "aspectRatio is {aspect}; it must be positive"
                )));
            }
            Projection::Perspective { yfov, aspect_ratio }
        }
        ::gltf::camera::Projection::Orthographic(o) => {
            let (xmag, ymag) = (o.xmag(), o.ymag());
            if !(xmag != 0.0 && ymag != 0.0 && xmag.is_finite() && ymag.is_finite()) {
                return Err(fail(format!(
                    "xmag {xmag} and ymag {ymag} must be finite and non-zero"
                )));
            }
            // glTF says xmag/ymag SHOULD NOT be negative; a negative one means its
            // magnitude (the half-extent), so the image is never mirrored and K's fx, fy are
            // positive (docs/ground-truth.md).
            Projection::Orthographic {
                xmag: xmag.abs(),
                ymag: ymag.abs(),
            }
        }
    };
    Ok(Some(Camera {
        name: camera.name().map_or(what.clone(), str::to_string),
        node: u32::try_from(placed.node.index()).ok(),
        znear: Some(znear),
        zfar,
        world_from_camera,
        projection,
    }))
}

/// The node's KHR_lights_punctual light in world space, if it has one.
///
/// Position is the node's world translation and direction its world −Z, normalised. The
/// stored intensity is `intensity × color`: W/sr for point and spot lights, W/m² for
/// directional ones (see [`Light`]). Spot cone angles default to 0 and π/4 as the extension
/// specifies.
pub fn light(placed: &PlacedNode<'_>, origin: Origin<'_>) -> Result<Option<Light>, LoadError> {
    let Some(light) = placed.node.light() else {
        return Ok(None);
    };
    let what = match light.name() {
        Some(name) => format!(
            "{} / light {} \"{name}\"",
            node_label(&placed.node),
            light.index()
        ),
        None => format!("{} / light {}", node_label(&placed.node), light.index()),
    };
    let fail = |problem: String| LoadError::Node {
        path: origin.file.to_path_buf(),
        what: what.clone(),
        problem,
    };
    let intensity = light.intensity();
    if !(intensity >= 0.0 && intensity.is_finite()) {
        return Err(fail(format!(
            "intensity is {intensity}; it must be finite and non-negative"
        )));
    }
    let color = Vec3::from(light.color());
    if !(color.is_finite() && color.min_element() >= 0.0) {
        return Err(fail(format!(
            "color is {color}; its components must be finite and non-negative"
        )));
    }
    let range = light.range();
    if let Some(r) = range
        && (r.is_nan() || r <= 0.0)
    {
        return Err(fail(format!(
            "range is {r}; it must be positive (or absent for no limit)"
        )));
    }
    let world = placed.world_from_node;
    let position = world.w_axis.truncate();
    let direction = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
    let needs_direction = !matches!(light.kind(), ::gltf::khr_lights_punctual::Kind::Point);
    if needs_direction && direction == Vec3::ZERO {
        return Err(fail(
            "the node's transform collapses the light's −Z axis (zero scale)".into(),
        ));
    }
    let radiometric = color * intensity;
    Ok(Some(match light.kind() {
        ::gltf::khr_lights_punctual::Kind::Point => Light::Point {
            position,
            intensity: radiometric,
            range,
        },
        ::gltf::khr_lights_punctual::Kind::Directional => Light::Directional {
            direction,
            irradiance: radiometric,
        },
        ::gltf::khr_lights_punctual::Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => {
            let right_angle = std::f32::consts::FRAC_PI_2;
            if !(0.0 <= inner_cone_angle
                && inner_cone_angle < outer_cone_angle
                && outer_cone_angle <= right_angle)
            {
                return Err(fail(format!(
                    "cone angles inner {inner_cone_angle} and outer {outer_cone_angle} rad must satisfy \
                     0 ≤ inner < outer ≤ π/2"
                )));
            }
            Light::Spot {
                position,
                direction,
                intensity: radiometric,
                range,
                cos_inner: inner_cone_angle.cos(),
                cos_outer: outer_cone_angle.cos(),
            }
        }
    }))
}
