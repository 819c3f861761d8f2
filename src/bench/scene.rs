//! The scenes a benchmark traces: the built-in procedural scenes or a glTF file's triangles.

use crate::accel::TriangleMesh;
use crate::procedural::{self, Builtin, OwnedMesh};
use crate::scene::Camera;
use crate::scene::gltf::{self, LoadError};
use std::path::Path;

/// Seed of the built-in scenes: fixed, so every machine benchmarks the same triangles.
pub const BUILTIN_SEED: u64 = 2024;

/// How large to make the built-in scenes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneSize {
    /// The benchmark size, about a million triangles each ([`Builtin::generate`]).
    Full,
    /// About five thousand triangles each, for smoke tests that must finish in seconds.
    Quick,
}

/// Why a benchmark scene could not be had.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The argument is neither a built-in name nor a glTF file name.
    #[error(
        "'{0}' is neither a built-in scene (sphere, terrain, soup) nor a .gltf/.glb file; \
         pass one of those"
    )]
    Unknown(String),
    /// The glTF file could not be loaded (the error names the file and what is wrong).
    #[error(transparent)]
    Load(#[from] LoadError),
}

/// A scene to benchmark: triangles, and the camera to trace coherent rays from, if it has one.
#[derive(Clone, Debug)]
pub struct BenchScene {
    /// Name in reports: the built-in's name or the file path.
    pub name: String,
    /// Triangle meshes in world space.
    pub meshes: Vec<OwnedMesh>,
    /// The scene's own camera (a glTF's first), else `None` to frame the scene's bounds.
    pub camera: Option<Camera>,
}

impl BenchScene {
    /// A built-in procedural scene, generated from [`BUILTIN_SEED`].
    pub fn builtin(builtin: Builtin, size: SceneSize) -> Self {
        let mesh = match size {
            SceneSize::Full => builtin.generate(BUILTIN_SEED),
            // Parameters giving about 5k triangles: 20·4⁴ = 5120, 2·50² = 5000, 5000.
            SceneSize::Quick => match builtin {
                Builtin::DisplacedSphere => procedural::displaced_sphere(4, 0.05, BUILTIN_SEED),
                Builtin::Terrain => procedural::terrain(50, 0.1, BUILTIN_SEED),
                Builtin::TriangleSoup => procedural::triangle_soup(5000, 0.05, BUILTIN_SEED),
            },
        };
        Self {
            name: builtin.name().to_string(),
            meshes: vec![mesh],
            camera: None,
        }
    }

    /// Every built-in scene at `size`.
    pub fn all_builtins(size: SceneSize) -> Vec<Self> {
        Builtin::ALL
            .iter()
            .map(|&builtin| Self::builtin(builtin, size))
            .collect()
    }

    /// The triangles and first camera of a `.gltf` or `.glb` file.
    pub fn from_gltf(path: &Path) -> Result<Self, SceneError> {
        Self::from_gltf_with(path, &gltf::LoadOptions::default())
    }

    /// Like [`from_gltf`](Self::from_gltf), under `options` (asset root, texture budget).
    pub fn from_gltf_with(path: &Path, options: &gltf::LoadOptions) -> Result<Self, SceneError> {
        let scene = gltf::load_full(path, &gltf::SceneSelection::default(), options)
            .map(gltf::print_warnings)?;
        Ok(Self {
            name: path.display().to_string(),
            camera: scene.cameras.first().cloned(),
            meshes: scene
                .meshes
                .into_iter()
                .map(|mesh| OwnedMesh {
                    positions: mesh.positions,
                    indices: mesh.indices,
                    instances: mesh.instances,
                })
                .collect(),
        })
    }

    /// A scene named on the command line: a built-in name (`sphere`, `terrain`, `soup`,
    /// generated at `size`) or the path of a `.gltf` / `.glb` file.
    pub fn from_arg(arg: &str, size: SceneSize) -> Result<Self, SceneError> {
        Self::from_arg_with(arg, size, &gltf::LoadOptions::default())
    }

    /// Like [`from_arg`](Self::from_arg), loading files under `options`.
    pub fn from_arg_with(
        arg: &str,
        size: SceneSize,
        options: &gltf::LoadOptions,
    ) -> Result<Self, SceneError> {
        if let Some(&builtin) = Builtin::ALL.iter().find(|b| b.name() == arg) {
            return Ok(Self::builtin(builtin, size));
        }
        let path = Path::new(arg);
        let is_gltf = path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"));
        if is_gltf {
            Self::from_gltf_with(path, options)
        } else {
            Err(SceneError::Unknown(arg.to_string()))
        }
    }

    /// The meshes as the ray backends take them.
    pub fn triangle_meshes(&self) -> Vec<TriangleMesh<'_>> {
        self.meshes
            .iter()
            .map(OwnedMesh::as_triangle_mesh)
            .collect()
    }

    /// Total number of triangles drawn (each placed copy counted).
    pub fn triangle_count(&self) -> usize {
        self.meshes
            .iter()
            .map(|m| m.as_triangle_mesh().drawn_triangles())
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_names_resolve_and_others_do_not() {
        for builtin in Builtin::ALL {
            let scene = BenchScene::from_arg(builtin.name(), SceneSize::Quick).unwrap();
            assert_eq!(scene.name, builtin.name());
            assert!((4000..6000).contains(&scene.triangle_count()));
        }
        let err = BenchScene::from_arg("spheer", SceneSize::Quick).unwrap_err();
        assert!(matches!(err, SceneError::Unknown(_)));
        assert!(err.to_string().contains("spheer"));
    }

    #[test]
    fn a_missing_gltf_is_a_load_error_naming_the_file() {
        let err = BenchScene::from_arg("no/such/scene.glb", SceneSize::Quick).unwrap_err();
        assert!(matches!(err, SceneError::Load(_)));
        assert!(err.to_string().contains("no/such/scene.glb"), "{err}");
    }
}
