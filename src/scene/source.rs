//! Where a scene comes from: glint's embedded demo scene or a glTF file, and loading it.

use super::Scene;
use super::gltf::{LoadError, LoadOptions, SceneSelection};
use std::path::PathBuf;

/// Where a render's scene comes from.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum SceneSource {
    /// glint's embedded demo scene.
    #[default]
    Demo,
    /// A .gltf or .glb file.
    File(PathBuf),
}

impl SceneSource {
    /// The name of the scene in messages: the file's path, or "demo scene".
    pub fn label(&self) -> String {
        match self {
            SceneSource::Demo => "demo scene".to_string(),
            SceneSource::File(path) => path.display().to_string(),
        }
    }

    /// Loads the scene (the file's default scene, at rest).
    pub fn load(&self) -> Result<Scene, LoadError> {
        self.load_selected(&SceneSelection::default())
    }

    /// Loads the scene and animation time `selection` names; the demo scene has one scene and
    /// no animation, so it ignores them.
    pub fn load_selected(&self, selection: &SceneSelection) -> Result<Scene, LoadError> {
        self.load_with(selection, &LoadOptions::default())
    }

    /// Like [`load_selected`](Self::load_selected), under `options` (asset root, texture
    /// budget).
    pub fn load_with(
        &self,
        selection: &SceneSelection,
        options: &LoadOptions,
    ) -> Result<Scene, LoadError> {
        match self {
            SceneSource::Demo => super::demo::demo_scene(),
            SceneSource::File(path) => {
                super::gltf::load_full(path, selection, options).map(super::gltf::print_warnings)
            }
        }
    }

    /// Like [`load_with`](Self::load_with), without printing the loader's warnings: for a
    /// second load of a scene already loaded (and warned about) once, e.g. its rest pose.
    pub fn load_quietly(
        &self,
        selection: &SceneSelection,
        options: &LoadOptions,
    ) -> Result<Scene, LoadError> {
        match self {
            SceneSource::File(path) => {
                super::gltf::load_full(path, selection, options).map(|loaded| loaded.scene)
            }
            // The demo scene has no warnings to print.
            SceneSource::Demo => self.load_with(selection, options),
        }
    }
}
