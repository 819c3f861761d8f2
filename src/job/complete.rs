//! Completing a scene for one job, beyond what the scene alone decides
//! ([`crate::scene::defaults`]: the camera, the default lights): the environment, which depends
//! on the job's integrator and lights.

use super::studio::{STUDIO_NAME, studio_environment};
use crate::light::environment::{EnvironmentError, EnvironmentLight};
use crate::render::Integrator;
use crate::scene::defaults::{Completed, DEFAULT_ENVIRONMENT_RADIANCE};
use crate::scene::{Light, Scene};
use std::sync::Arc;

/// The environment to render `scene` with: `given` if there is one; else, for the path
/// tracer, when the scene and `extra` have no punctual light, the default environment (the
/// bundled studio HDRI, [`super::studio`]) instead of the default sun, announced; else none.
/// The former default, a uniform white of [`DEFAULT_ENVIRONMENT_RADIANCE`], is
/// `--background 1,1,1`. Emissive surfaces do not count as lights here: a scene lit only by
/// them (a Cornell box) renders them under the default environment unless the job gives a
/// black one (`--background 0,0,0`). The direct integrator keeps the default sun, so its
/// images of a scene without lights are what they were.
pub fn environment_for(
    scene: &Scene,
    extra: &[Light],
    given: Option<Arc<EnvironmentLight>>,
    integrator: Integrator,
) -> Result<Completed<Option<Arc<EnvironmentLight>>>, EnvironmentError> {
    if given.is_some() {
        return Ok(Completed {
            value: given,
            added: None,
        });
    }
    if integrator == Integrator::Path && scene.lights.is_empty() && extra.is_empty() {
        return Ok(Completed {
            value: Some(studio_environment()?),
            added: Some(format!(
                "the scene has no lights: rendering it under {STUDIO_NAME}; give --env, \
                 --background (--background {DEFAULT_ENVIRONMENT_RADIANCE},\
                 {DEFAULT_ENVIRONMENT_RADIANCE},{DEFAULT_ENVIRONMENT_RADIANCE}: a uniform white) \
                 or --light to light it otherwise"
            )),
        });
    }
    Ok(Completed {
        value: None,
        added: None,
    })
}
