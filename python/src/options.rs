//! A render's keyword arguments, as `Scene.render` and the jobs of `glint.render_batch` take
//! them, turned into a library [`Job`]. Defaults are [`Job::default`]'s, which are `glint
//! render`'s, so a render from Python and the same render from the command line are the same
//! job (and the same pixels); the tests below and `tests/render/job_defaults.rs` check it.

use glam::Vec3;
use glint::job::{
    CameraChoice, EnvironmentSource, Job, LightSource, OutputSpec, Samples, SceneSource,
};
use glint::render::{
    AovSelection, BrdfModel, FilterSpec, Integrator, PixelSampling, RenderSettings, StopRule,
    progressive::DEFAULT_MAX_SPP,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use std::path::PathBuf;
use std::time::Duration;

/// The AOV names `aovs=` accepts, as the command line's `--aov` spells them.
pub const AOV_NAMES: [&str; 11] = AovSelection::NAMES;

/// The keyword arguments `Scene.render` accepts (`render_batch` jobs also take `scene`).
pub const RENDER_KEYS: [&str; 33] = [
    "sidecar",
    "annotations",
    "categories",
    "flow_dt",
    "width",
    "height",
    "spp",
    "camera",
    "lights",
    "lights_file",
    "photometric",
    "env",
    "env_strength",
    "env_rotation",
    "env_hidden",
    "seed",
    "integrator",
    "brdf",
    "max_depth",
    "max_transmission_depth",
    "aovs",
    "threads",
    "filter",
    "sampler",
    "time_budget",
    "target_error",
    "max_spp",
    "adaptive",
    "clamp_indirect",
    "mis_compensation",
    "guiding",
    "output",
    "denoise",
];

/// Reads one keyword argument, `None` when absent or `None`.
fn get<'py, T>(kwargs: Option<&Bound<'py, PyDict>>, key: &str) -> PyResult<Option<T>>
where
    T: for<'a> FromPyObject<'a, 'py>,
{
    let Some(kwargs) = kwargs else {
        return Ok(None);
    };
    match kwargs.get_item(key)? {
        Some(value) if !value.is_none() => value.extract::<T>().map(Some).map_err(|e| {
            let err: PyErr = e.into();
            PyTypeError::new_err(format!("{key}: {err}"))
        }),
        _ => Ok(None),
    }
}

/// `name` parsed by `parse`, as a `ValueError` naming the argument on failure.
fn parsed<T, E: std::fmt::Display>(
    key: &str,
    text: &str,
    parse: impl Fn(&str) -> Result<T, E>,
) -> PyResult<T> {
    parse(text).map_err(|e| PyValueError::new_err(format!("{key}={text:?}: {e}")))
}

/// The job the keyword arguments describe, for the scene `source` (used for messages and
/// the output's default; the render itself uses the prepared scene). Unknown keys are a
/// `TypeError`, as for a Python function; `allowed_extra` names keys the caller handles.
pub fn job_from_kwargs(
    kwargs: Option<&Bound<'_, PyDict>>,
    source: SceneSource,
    backend: glint::accel::BackendKind,
    allowed_extra: &[&str],
) -> PyResult<Job> {
    if let Some(kwargs) = kwargs {
        for key in kwargs.keys() {
            let key: String = key.extract()?;
            if !RENDER_KEYS.contains(&key.as_str()) && !allowed_extra.contains(&key.as_str()) {
                return Err(PyTypeError::new_err(format!(
                    "render() got an unexpected keyword argument '{key}'; the arguments are: {}",
                    RENDER_KEYS.join(", ")
                )));
            }
        }
    }
    let defaults = Job::default();
    let integrator = match get::<String>(kwargs, "integrator")? {
        Some(name) => parsed("integrator", &name, str::parse::<Integrator>)?,
        None => defaults.settings.integrator,
    };
    let brdf = match get::<String>(kwargs, "brdf")? {
        Some(name) => parsed("brdf", &name, str::parse::<BrdfModel>)?,
        None => defaults.settings.brdf,
    };
    let filter = match get::<String>(kwargs, "filter")? {
        Some(text) => parsed("filter", &text, str::parse::<FilterSpec>)?,
        None => defaults.settings.filter,
    };
    let sampling = match get::<String>(kwargs, "sampler")? {
        Some(text) => parsed("sampler", &text, str::parse::<PixelSampling>)?,
        None => defaults.settings.sampling,
    };
    let mut aovs = aov_selection(&get::<Vec<String>>(kwargs, "aovs")?.unwrap_or_default())?;
    aovs.annotations = get::<bool>(kwargs, "annotations")?.unwrap_or(false);
    // `categories={"NodeOrMeshName": "category"}`, as `--category NAME=CATEGORY` (sorted by
    // name, so the order of a dict never matters).
    let categories: Vec<(String, String)> =
        get::<std::collections::BTreeMap<String, String>>(kwargs, "categories")?
            .unwrap_or_default()
            .into_iter()
            .collect();
    let mut lights: Vec<LightSource> = get::<Vec<String>>(kwargs, "lights")?
        .unwrap_or_default()
        .into_iter()
        .map(LightSource::Spec)
        .collect();
    lights.extend(get::<PathBuf>(kwargs, "lights_file")?.map(LightSource::File));
    let environment = environment(kwargs)?;
    let time_budget = get::<f64>(kwargs, "time_budget")?;
    let target_error = get::<f64>(kwargs, "target_error")?;
    let samples = if time_budget.is_some() || target_error.is_some() {
        let time_budget = match time_budget {
            Some(t) if t > 0.0 && t.is_finite() && t < 1e9 => Some(Duration::from_secs_f64(t)),
            Some(t) => {
                return Err(PyValueError::new_err(format!(
                    "time_budget={t}: give a positive number of seconds"
                )));
            }
            None => None,
        };
        Samples::Progressive(StopRule {
            time_budget,
            target_error,
            max_spp: get(kwargs, "max_spp")?.unwrap_or(DEFAULT_MAX_SPP),
        })
    } else {
        Samples::All
    };
    let sidecar = get::<bool>(kwargs, "sidecar")?.unwrap_or(false);
    Ok(Job {
        scene: source,
        backend,
        camera: camera(kwargs)?,
        lights,
        environment,
        light_units: if get::<bool>(kwargs, "photometric")?.unwrap_or(false) {
            glint::light::LightUnits::Photometric
        } else {
            glint::light::LightUnits::Radiometric
        },
        width: get(kwargs, "width")?,
        height: get(kwargs, "height")?,
        settings: RenderSettings {
            spp: get(kwargs, "spp")?.unwrap_or(defaults.settings.spp),
            seed: get(kwargs, "seed")?.unwrap_or(defaults.settings.seed),
            max_depth: get(kwargs, "max_depth")?.unwrap_or(defaults.settings.max_depth),
            max_transmission_depth: get(kwargs, "max_transmission_depth")?
                .unwrap_or(defaults.settings.max_transmission_depth),
            threads: get(kwargs, "threads")?.unwrap_or(defaults.settings.threads),
            aovs,
            filter,
            sampling,
            integrator,
            brdf,
            environment_visible: !get::<bool>(kwargs, "env_hidden")?.unwrap_or(false),
            adaptive: glint::render::adaptive::threshold_for(
                get::<f32>(kwargs, "adaptive")?,
                target_error,
            )
            .map_err(PyValueError::new_err)?,
            clamp_indirect: match get::<f32>(kwargs, "clamp_indirect")? {
                Some(x) if !(x > 0.0 && x.is_finite()) => {
                    return Err(PyValueError::new_err(format!(
                        "clamp_indirect={x}: give a positive radiance, e.g. 10"
                    )));
                }
                x => x,
            },
            mis_compensation: get::<bool>(kwargs, "mis_compensation")?
                .unwrap_or(defaults.settings.mis_compensation),
            guiding: get::<bool>(kwargs, "guiding")?.unwrap_or(defaults.settings.guiding),
            ..defaults.settings
        },
        samples,
        output: get::<PathBuf>(kwargs, "output")?.map(|path| OutputSpec {
            path,
            sidecar,
            ..OutputSpec::default()
        }),
        flow_dt: get(kwargs, "flow_dt")?,
        categories,
        denoise: get::<bool>(kwargs, "denoise")?.unwrap_or(false),
        ..defaults
    })
}

/// `aovs=[...]` as an [`AovSelection`].
fn aov_selection(names: &[String]) -> PyResult<AovSelection> {
    AovSelection::from_names(names.iter().map(String::as_str)).map_err(|other| {
        PyValueError::new_err(format!(
            "aovs: unknown AOV {other:?}; the AOVs are {}",
            AOV_NAMES.join(", ")
        ))
    })
}

/// `camera=`: `None` (the scene's first), an index, or a dict placing a perspective camera.
fn camera(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<CameraChoice> {
    let Some(value) = kwargs.map(|k| k.get_item("camera")).transpose()?.flatten() else {
        return Ok(CameraChoice::First);
    };
    if value.is_none() {
        return Ok(CameraChoice::First);
    }
    if let Ok(index) = value.extract::<usize>() {
        return Ok(CameraChoice::Index(index));
    }
    let Ok(dict) = value.cast::<PyDict>() else {
        return Err(PyTypeError::new_err(
            "camera: give an index into scene.cameras, or a dict with position, target and \
             optionally up and yfov_degrees",
        ));
    };
    let vec3 = |key: &str| -> PyResult<Option<Vec3>> {
        Ok(get::<[f32; 3]>(Some(dict), key)?.map(Vec3::from))
    };
    let (Some(position), Some(target)) = (vec3("position")?, vec3("target")?) else {
        return Err(PyValueError::new_err(
            "camera: a camera dict needs 'position' and 'target' (3 numbers each)",
        ));
    };
    for key in dict.keys() {
        let key: String = key.extract()?;
        if !["position", "target", "up", "yfov_degrees", "name"].contains(&key.as_str()) {
            return Err(PyValueError::new_err(format!(
                "camera: unknown key '{key}'; use position, target, up, yfov_degrees, name"
            )));
        }
    }
    let yfov = get::<f32>(Some(dict), "yfov_degrees")?;
    if let Some(y) = yfov
        && !(y > 0.0 && y < 180.0)
    {
        return Err(PyValueError::new_err(format!(
            "camera: yfov_degrees={y} must be between 0 and 180"
        )));
    }
    Ok(CameraChoice::LookAt {
        name: get::<String>(Some(dict), "name")?.unwrap_or_else(|| "look-at".into()),
        position,
        target,
        up: vec3("up")?.unwrap_or(Vec3::Y),
        yfov: yfov.map(f32::to_radians),
    })
}

/// `env=`: a path to an equirectangular `.hdr`/`.exr`, or a uniform radiance `(r, g, b)`.
fn environment(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Option<EnvironmentSource>> {
    let Some(value) = kwargs.map(|k| k.get_item("env")).transpose()?.flatten() else {
        return Ok(None);
    };
    if value.is_none() {
        return Ok(None);
    }
    let strength = get::<f32>(kwargs, "env_strength")?.unwrap_or(1.0);
    let rotation = get::<f32>(kwargs, "env_rotation")?.unwrap_or(0.0);
    if !(strength.is_finite() && strength >= 0.0 && rotation.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "env_strength={strength} / env_rotation={rotation}: give finite numbers (strength ≥ 0)"
        )));
    }
    if value.is_instance_of::<PyString>() || value.hasattr("__fspath__")? {
        return Ok(Some(EnvironmentSource::File {
            path: value.extract::<PathBuf>()?,
            strength,
            rotation_deg: rotation,
        }));
    }
    match value.extract::<[f32; 3]>() {
        Ok(rgb) if rgb.iter().all(|c| c.is_finite() && *c >= 0.0) => {
            Ok(Some(EnvironmentSource::Constant(Vec3::from(rgb))))
        }
        _ => Err(PyValueError::new_err(
            "env: give a path to an .hdr/.exr image or three non-negative numbers (r, g, b)",
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_keyword_arguments_give_the_default_job() {
        // Python's defaults are `Job::default()`'s, which tests/render/job_defaults.rs proves are
        // `glint render`'s.
        let job = job_from_kwargs(None, SceneSource::Demo, Default::default(), &[]).unwrap();
        assert_eq!(job, Job::default());
        assert_eq!(job.settings.integrator, Integrator::Path);
    }
}
