//! Completing a scene for one job, beyond what the scene alone decides
//! ([`crate::scene::defaults`]: the camera, the default lights): the environment, which depends
//! on the job's integrator and lights.

use crate::light::environment::EnvironmentLight;
use crate::render::Integrator;
use crate::scene::defaults::{Completed, DEFAULT_ENVIRONMENT_RADIANCE};
use crate::scene::{Light, Scene};
use glam::Vec3;
use std::sync::Arc;

/// The environment to render `scene` with: `given` if there is one; else, for the path
/// tracer, when the scene and `extra` have no punctual light, the default environment (a
/// uniform white of [`DEFAULT_ENVIRONMENT_RADIANCE`]) instead of the default sun, announced;
/// else none. Emissive surfaces do not count as lights here: a scene lit only by them (a
/// Cornell box) renders them under the default environment unless the job gives a black one
/// (`--background 0,0,0`). The direct integrator keeps the default sun, so its images of a
/// scene without lights are what they were.
pub fn environment_for(
    scene: &Scene,
    extra: &[Light],
    given: Option<Arc<EnvironmentLight>>,
    integrator: Integrator,
) -> Completed<Option<Arc<EnvironmentLight>>> {
    if given.is_some() {
        return Completed {
            value: given,
            added: None,
        };
    }
    if integrator == Integrator::Path && scene.lights.is_empty() && extra.is_empty() {
        return Completed {
            value: Some(Arc::new(EnvironmentLight::constant(Vec3::splat(
                DEFAULT_ENVIRONMENT_RADIANCE,
            )))),
            added: Some(format!(
                "the scene has no lights: rendering it under the default environment (uniform \
                 white, radiance {DEFAULT_ENVIRONMENT_RADIANCE} W/(m²·sr)); give --env, \
                 --background or --light to light it otherwise"
            )),
        };
    }
    Completed {
        value: None,
        added: None,
    }
}
