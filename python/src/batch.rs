//! `glint.render_batch`: many jobs, rendered side by side on one thread pool whose workers
//! also share each job's tiles (as `glint batch` does), so small jobs do not leave cores idle.

use crate::scene::{Scene, run_job};
use crate::{arrays, glint_error, interrupt, options};
use glint::job::{Job, PreparedScene};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

/// Renders a list of jobs and returns their results (dicts of numpy arrays, as
/// `Scene.render`) in the jobs' order.
///
/// Each job is a dict of `Scene.render`'s keyword arguments plus "scene": a `glint.Scene`, or
/// a path, loaded once per distinct path (with the default backend; load it yourself for
/// other load options). `threads`: worker threads shared by all jobs (0: every core); a job's
/// own "threads" is ignored. Results do not depend on the thread count. The first failing job
/// (in job order) raises glint.GlintError naming its index, after every job has run.
#[pyfunction]
#[pyo3(signature = (jobs, *, threads=0))]
pub fn render_batch<'py>(
    py: Python<'py>,
    jobs: Vec<Bound<'py, PyDict>>,
    threads: usize,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let mut scenes: Vec<Arc<PreparedScene>> = Vec::new();
    let mut by_path: HashMap<PathBuf, usize> = HashMap::new();
    let mut work: Vec<(Job, usize)> = Vec::with_capacity(jobs.len());
    let mut backend = glint::accel::BackendKind::Bvh;
    for (index, spec) in jobs.iter().enumerate() {
        let Some(scene) = spec.get_item("scene")? else {
            return Err(PyTypeError::new_err(format!(
                "job {index}: no \"scene\" (a glint.Scene or a path)"
            )));
        };
        let (slot, source, kind) = if let Ok(loaded) = scene.cast::<Scene>() {
            let loaded = loaded.get();
            scenes.push(loaded.prepared.clone());
            (scenes.len() - 1, loaded.source.clone(), loaded.backend)
        } else {
            let path: PathBuf = scene.extract().map_err(|_| {
                PyTypeError::new_err(format!(
                    "job {index}: \"scene\" must be a glint.Scene or a path"
                ))
            })?;
            let slot = match by_path.get(&path) {
                Some(&slot) => slot,
                None => {
                    let loaded = crate::scene::load(
                        py,
                        Some(path.clone()),
                        None,
                        None,
                        None,
                        None,
                        None,
                        glint::scene::gltf::DEFAULT_MAX_TEXTURE_PIXELS,
                        glint::scene::gltf::DEFAULT_MAX_GEOMETRY_BYTES,
                    )
                    .map_err(|e| glint_error(format!("job {index}: {e}")))?;
                    scenes.push(loaded.prepared.clone());
                    by_path.insert(path.clone(), scenes.len() - 1);
                    scenes.len() - 1
                }
            };
            (
                slot,
                glint::scene::SceneSource::File(path),
                glint::accel::BackendKind::default(),
            )
        };
        if kind == glint::accel::BackendKind::Embree {
            backend = kind;
        }
        let job = options::job_from_kwargs(Some(spec), source, kind, &["scene"]).map_err(|e| {
            let message = format!("job {index}: {}", e.value(py));
            if e.is_instance_of::<pyo3::exceptions::PyValueError>(py) {
                pyo3::exceptions::PyValueError::new_err(message)
            } else {
                PyTypeError::new_err(message)
            }
        })?;
        work.push((job, slot));
    }
    // One pool for all, set up for Embree if any job uses it.
    let pool = glint::render::thread_pool(threads, backend).map_err(glint_error)?;
    let results = interrupt::run_detached(py, "rendering a batch", |cancel| {
        pool.install(|| {
            work.par_iter()
                .map(|(job, slot)| run_job(job, &scenes[*slot], &pool, cancel))
                .collect::<Vec<_>>()
        })
    })?;
    let mut out = Vec::with_capacity(results.len());
    for (index, result) in results.into_iter().enumerate() {
        let images = result.map_err(|e| {
            if e.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) {
                e
            } else {
                glint_error(format!("job {index}: {}", e.value(py)))
            }
        })?;
        out.push(arrays::images_to_dict(py, &images)?);
    }
    Ok(out)
}
