//! The demo scene, embedded in the binary so `glint render` works from any directory.

use super::Scene;
use super::gltf::LoadError;

/// Loads the embedded demo scene.
pub fn demo_scene() -> Result<Scene, LoadError> {
    super::gltf::load_slice(&[], "scenes/demo.glb (embedded)", None)
}
