//! A scene prepared once and shared by every job of it.

use super::{EnvironmentSource, JobError, SceneSource};
use crate::accel::{Accel, BackendKind, BuildOptions};
use crate::light::area::AreaLights;
use crate::light::environment::{EnvironmentError, EnvironmentLight};
use crate::render::{build_area_lights, build_mipmaps, prepare};
use crate::scene::Scene;
use crate::scene::gltf::{LoadOptions, SceneSelection};
use crate::texture::MipMap;
use std::sync::{Arc, Mutex};

/// A loaded scene and everything derived from it at load, shared by every job of the scene.
pub struct PreparedScene {
    /// The scene as loaded (its own lights; job lights are added per job).
    pub scene: Scene,
    /// The scene's name in messages.
    pub label: String,
    /// Its ray-query structure.
    pub accel: Box<dyn Accel>,
    /// Its MIP chains ([`build_mipmaps`]), index-aligned with `scene.textures`.
    pub mipmaps: Vec<MipMap>,
    /// Its emissive triangles as lights ([`build_area_lights`]; empty when nothing
    /// emits).
    pub area_lights: AreaLights,
    /// The environment the last job asked for, kept for the next one: the jobs of a batch
    /// (or a Python loop) over one scene usually share their environment, whose decode and
    /// sampling tables cost more than many small renders.
    environment_cache: Mutex<Option<(EnvironmentSource, Arc<EnvironmentLight>)>>,
}

impl PreparedScene {
    /// Loads `source` (the scene and time `selection` names) and prepares it for `backend`.
    pub fn load(
        source: &SceneSource,
        selection: &SceneSelection,
        options: &LoadOptions,
        backend: BackendKind,
    ) -> Result<Self, JobError> {
        let scene = source.load_with(selection, options)?;
        Self::new(scene, source.label(), backend)
    }

    /// Prepares a scene already in memory.
    pub fn new(scene: Scene, label: String, backend: BackendKind) -> Result<Self, JobError> {
        let accel = prepare(&scene, backend, BuildOptions::default())
            .map_err(|e| JobError::from(e).in_scene(&label))?;
        let mipmaps = build_mipmaps(&scene);
        let area_lights = build_area_lights(&scene, Some(&mipmaps))
            .map_err(|e| JobError::from(e).in_scene(&label))?;
        Ok(Self {
            scene,
            label,
            accel,
            mipmaps,
            area_lights,
            environment_cache: Mutex::new(None),
        })
    }

    /// The environment light of `source`: the one the previous job of this scene loaded if
    /// it asked for the same, else loaded now (and kept in its place).
    pub fn environment(
        &self,
        source: &EnvironmentSource,
    ) -> Result<Arc<EnvironmentLight>, EnvironmentError> {
        // A poisoned lock only means another job panicked while loading: the slot holds
        // either nothing or a complete entry, so it is still safe to use.
        let mut slot = self
            .environment_cache
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some((cached, light)) = slot.as_ref()
            && cached == source
        {
            return Ok(Arc::clone(light));
        }
        let light = Arc::new(source.light()?);
        *slot = Some((source.clone(), Arc::clone(&light)));
        Ok(light)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_prepared_scene_keeps_the_last_environment_for_the_next_job() {
        let scene = crate::scene::demo::demo_scene().unwrap();
        let prepared =
            PreparedScene::new(scene, "demo".into(), crate::accel::BackendKind::Bvh).unwrap();
        let studio = EnvironmentSource::File {
            path: std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                .join("../shared/env/studio.hdr"),
            strength: 1.0,
            rotation_deg: 0.0,
        };
        let first = prepared.environment(&studio).unwrap();
        let again = prepared.environment(&studio).unwrap();
        assert!(
            Arc::ptr_eq(&first, &again),
            "the same source was loaded twice"
        );
        let turned = EnvironmentSource::File {
            path: match &studio {
                EnvironmentSource::File { path, .. } => path.clone(),
                EnvironmentSource::Constant(_) => unreachable!(),
            },
            strength: 1.0,
            rotation_deg: 90.0,
        };
        let other = prepared.environment(&turned).unwrap();
        assert!(
            !Arc::ptr_eq(&first, &other),
            "a different rotation reused the cache"
        );
        let missing = EnvironmentSource::File {
            path: "no/such/env.hdr".into(),
            strength: 1.0,
            rotation_deg: 0.0,
        };
        assert!(prepared.environment(&missing).is_err());
    }
}
