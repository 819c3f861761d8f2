//! Loading glTF 2.0 (`.gltf` and `.glb`) into a [`Scene`](super::Scene).

use super::Scene;
use std::path::{Path, PathBuf};

/// Why a scene could not be loaded. Every variant names the file and the thing in it.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// Catch-all while the loader is being written.
    #[error("{path}: {message}")]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// What is wrong, naming the node / mesh / accessor.
        message: String,
    },
}

/// Loads a `.gltf` or `.glb` file, resolving external buffers and images next to it.
pub fn load(path: &Path) -> Result<Scene, LoadError> {
    Err(LoadError::Invalid {
        path: path.to_path_buf(),
        message: "glTF loading is not implemented yet".into(),
    })
}

/// Loads a glTF or GLB held in memory (the embedded demo scene); `label` names it in errors and
/// `base_dir` resolves relative URIs (None: only embedded data is allowed).
pub fn load_slice(bytes: &[u8], label: &str, base_dir: Option<&Path>) -> Result<Scene, LoadError> {
    let _ = (bytes, base_dir);
    Err(LoadError::Invalid {
        path: PathBuf::from(label),
        message: "glTF loading is not implemented yet".into(),
    })
}
