//! `glint.load` and the `Scene` and `Camera` classes.

use crate::{arrays, glint_error, interrupt, options};
use glint::accel::BackendKind;
use glint::job::{self, Job, JobError, PreparedScene, RunOptions, SceneSource};
use glint::scene::Projection;
use glint::scene::gltf::{
    DEFAULT_MAX_GEOMETRY_BYTES, DEFAULT_MAX_TEXTURE_PIXELS, LoadOptions, SceneSelection,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

/// A loaded scene, prepared for rendering: its ray-query structure, MIP chains and area lights
/// are built once, by `glint.load`, and shared by every render of the scene. Renders of one
/// scene may run from several Python threads at once.
#[pyclass(frozen, module = "glint")]
pub struct Scene {
    pub(crate) prepared: Arc<PreparedScene>,
    pub(crate) source: SceneSource,
    pub(crate) backend: BackendKind,
    /// The scene index and animation time it was loaded at, and how: a render's jobs carry
    /// them (the flow AOVs load the scene again at neighbouring times; the sidecar records
    /// the time).
    pub(crate) selection: SceneSelection,
    pub(crate) load_options: LoadOptions,
    /// The render pool, kept between renders so that a loop of renders does not start
    /// threads each time: (threads asked for, pool).
    pool: Mutex<Option<(usize, Arc<rayon::ThreadPool>)>>,
}

/// A camera of the scene, as loaded (world space).
#[pyclass(frozen, get_all, module = "glint")]
pub struct Camera {
    /// Name (the glTF camera's, else its node's).
    pub name: String,
    /// "perspective" or "orthographic".
    pub projection: String,
    /// World-from-camera transform, 4×4 row-major (the camera looks down its −Z).
    pub world_from_camera: [[f32; 4]; 4],
    /// Position in world space.
    pub position: [f32; 3],
    /// Vertical field of view in radians (perspective), else None.
    pub yfov: Option<f32>,
    /// Width / height the camera fixes, if any.
    pub aspect_ratio: Option<f32>,
    /// Orthographic half-extents (x, y), else None.
    pub xmag: Option<f32>,
    /// See `xmag`.
    pub ymag: Option<f32>,
}

#[pymethods]
impl Camera {
    fn __repr__(&self) -> String {
        format!(
            "Camera(name={:?}, projection={:?})",
            self.name, self.projection
        )
    }
}

impl Camera {
    fn of(camera: &glint::scene::Camera) -> Self {
        let m = camera.world_from_camera.transpose().to_cols_array_2d();
        let (yfov, aspect_ratio, xmag, ymag, projection) = match camera.projection {
            Projection::Perspective { yfov, aspect_ratio } => {
                (Some(yfov), aspect_ratio, None, None, "perspective")
            }
            Projection::Orthographic { xmag, ymag } => (
                None,
                job::fixed_aspect(camera),
                Some(xmag),
                Some(ymag),
                "orthographic",
            ),
        };
        Self {
            name: camera.name.clone(),
            projection: projection.into(),
            world_from_camera: m,
            position: camera.world_from_camera.w_axis.truncate().to_array(),
            yfov,
            aspect_ratio,
            xmag,
            ymag,
        }
    }
}

/// Loads a glTF 2.0 scene (.gltf or .glb), or glint's demo scene when `path` is None, and
/// prepares it for rendering (ray-query structure, MIP chains, area lights).
///
/// backend: "embree" (default when compiled in) or "bvh". scene: which of the file's scenes
/// (glTF `scenes` index). time: sample animations at this many seconds. variant: render the
/// materials of this KHR_materials_variants variant (default: the default materials; an
/// unknown name raises GlintError listing the file's variants). asset_root: every
/// file the glTF refers to must resolve inside this folder. max_texture_pixels: the most
/// texels one texture may have. max_geometry_bytes: the most bytes of geometry the scene may
/// decode and build (Draco and meshopt streams, vertices and indices), checked before
/// allocating.
///
/// Raises glint.GlintError with glint's message when the file cannot be loaded.
// Python keyword arguments, one parameter each: pyo3 maps them to this signature.
#[allow(clippy::too_many_arguments)]
#[pyfunction]
#[pyo3(signature = (path=None, *, backend=None, scene=None, time=None, variant=None, asset_root=None, max_texture_pixels=DEFAULT_MAX_TEXTURE_PIXELS, max_geometry_bytes=DEFAULT_MAX_GEOMETRY_BYTES))]
pub fn load(
    py: Python<'_>,
    path: Option<PathBuf>,
    backend: Option<String>,
    scene: Option<usize>,
    time: Option<f32>,
    variant: Option<String>,
    asset_root: Option<PathBuf>,
    max_texture_pixels: u64,
    max_geometry_bytes: u64,
) -> PyResult<Scene> {
    let backend = match backend {
        Some(name) => name
            .parse::<BackendKind>()
            .map_err(|e| PyValueError::new_err(format!("backend={name:?}: {e}")))?,
        None => BackendKind::default(),
    };
    let source = match path {
        Some(path) => SceneSource::File(path),
        None => SceneSource::Demo,
    };
    let selection = SceneSelection {
        scene,
        time,
        variant,
    };
    let options = LoadOptions {
        asset_root,
        max_texture_pixels,
        max_geometry_bytes,
    };
    let doing = format!("loading {}", source.label());
    let prepared = interrupt::run_detached(py, &doing, |_| {
        PreparedScene::load(&source, &selection, &options, backend)
    })?
    .map_err(glint_error)?;
    Ok(Scene {
        prepared: Arc::new(prepared),
        source,
        backend,
        selection,
        load_options: options,
        pool: Mutex::new(None),
    })
}

#[pymethods]
impl Scene {
    /// The scene's cameras, in the order of the file's camera nodes.
    #[getter]
    fn cameras(&self) -> Vec<Camera> {
        self.prepared.scene.cameras.iter().map(Camera::of).collect()
    }

    /// Axis-aligned world-space bounds ((min x, y, z), (max x, y, z)), or None if the scene
    /// has no triangles.
    #[getter]
    #[allow(clippy::type_complexity)]
    fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        self.prepared
            .scene
            .bounds()
            .map(|(lo, hi)| (lo.to_array(), hi.to_array()))
    }

    /// The scene's meshes (one per glTF primitive and instance): dicts with `name`, `node`
    /// (the instance_id of its pixels), `material` (their material_id) and `triangles`.
    #[getter]
    fn meshes<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let scene = &self.prepared.scene;
        (0..scene.meshes.len())
            .map(|i| {
                let mesh = &scene.meshes[i];
                let dict = PyDict::new(py);
                dict.set_item("name", &mesh.name)?;
                let geom = u32::try_from(i).unwrap_or(u32::MAX);
                dict.set_item(
                    "node",
                    glint::render::ids::instance_id(&self.prepared.scene, geom, 0),
                )?;
                dict.set_item("copies", mesh.copies())?;
                dict.set_item("material", mesh.material)?;
                dict.set_item("triangles", mesh.indices.len())?;
                Ok(dict)
            })
            .collect()
    }

    /// The names of the scene's materials, indexed by material_id.
    #[getter]
    fn materials(&self) -> Vec<String> {
        let scene = &self.prepared.scene;
        scene.materials.iter().map(|m| m.name.clone()).collect()
    }

    /// The scene's punctual lights (not counting emissive surfaces).
    #[getter]
    fn light_count(&self) -> usize {
        self.prepared.scene.lights.len()
    }

    /// Triangles in the scene.
    #[getter]
    fn triangles(&self) -> usize {
        self.prepared.scene.triangle_count()
    }

    /// The ray-query backend the scene was prepared for ("embree" or "bvh").
    #[getter]
    fn backend(&self) -> String {
        self.backend.to_string()
    }

    /// The scene's name in messages (its path, or "demo scene").
    #[getter]
    fn label(&self) -> String {
        self.prepared.label.clone()
    }

    fn __repr__(&self) -> String {
        format!(
            "glint.Scene({:?}, {} triangles, {} cameras, backend={})",
            self.prepared.label,
            self.prepared.scene.triangle_count(),
            self.prepared.scene.cameras.len(),
            self.backend
        )
    }

    /// Renders the scene and returns a dict of numpy arrays: "radiance" (float32 H×W×3,
    /// W/(m²·sr)) and one entry per AOV asked for (see glint.AOVS and docs/python.md).
    /// The keyword arguments and their defaults are `glint render`'s; see the type stub.
    /// The GIL is released while rendering; Ctrl-C stops the render (KeyboardInterrupt).
    #[pyo3(signature = (**kwargs))]
    fn render<'py>(
        &self,
        py: Python<'py>,
        kwargs: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let mut job = options::job_from_kwargs(kwargs, self.source.clone(), self.backend, &[])?;
        job.selection = self.selection.clone();
        job.load_options = self.load_options.clone();
        let pool = self.pool_for(job.settings.threads)?;
        let prepared = &*self.prepared;
        let doing = format!("rendering {}", self.source.label());
        let images =
            interrupt::run_detached(py, &doing, |cancel| run_job(&job, prepared, &pool, cancel))??;
        arrays::images_to_dict(py, &images)
    }
}

/// Runs `job` on `prepared`, returning its images.
pub(crate) fn run_job(
    job: &Job,
    prepared: &PreparedScene,
    pool: &rayon::ThreadPool,
    cancel: &std::sync::atomic::AtomicBool,
) -> PyResult<job::JobImages> {
    // Notes (a default camera or lights added) are for a person at a terminal; a program
    // calling glint asks for what it gets, so they are not printed.
    let options = RunOptions {
        pool: Some(pool),
        cancel: Some(cancel),
        ..RunOptions::default()
    };
    let done = job::run(job, prepared, options).map_err(|e| match e {
        JobError::InScene { source, .. }
            if matches!(
                *source,
                JobError::Render(glint::render::RenderError::Cancelled)
            ) =>
        {
            pyo3::exceptions::PyKeyboardInterrupt::new_err("render cancelled")
        }
        e => glint_error(e),
    })?;
    done.images
        .ok_or_else(|| glint_error("a partial render has no image"))
}

impl Scene {
    /// The pool for `threads` workers, started on first use and kept.
    pub(crate) fn pool_for(&self, threads: usize) -> PyResult<Arc<rayon::ThreadPool>> {
        let mut kept = self
            .pool
            .lock()
            .map_err(|_| glint_error("a render thread panicked while holding the pool"))?;
        if let Some((n, pool)) = kept.as_ref()
            && *n == threads
        {
            return Ok(pool.clone());
        }
        let pool =
            Arc::new(glint::render::thread_pool(threads, self.backend).map_err(glint_error)?);
        *kept = Some((threads, pool.clone()));
        Ok(pool)
    }
}
