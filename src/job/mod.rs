//! One render job, from a scene source to files on disk: the library's single entry point for
//! `glint render`, each job of `glint batch`, each render of the Python package, and anything
//! else that renders a whole image. This layer sits above the engine ([`crate::render`]) and
//! the writers ([`crate::output`]); nothing below it knows about jobs.
//!
//! - [`Job`]: plain data saying what to render: the scene, the backend, the camera, extra
//!   lights and their units, the image size, the [`RenderSettings`], which samples, and where
//!   the image goes ([`sources`]: the parts it is made of). `Default` is `glint render`'s
//!   defaults (and the Python package's) on the demo scene.
//! - [`Job::check`] ([`check`]): refuses impossible combinations before any work.
//! - [`PreparedScene`] ([`prepared`]): everything derived from a scene at load — the scene
//!   itself, its ray-query structure, its MIP chains and area lights — built once and shared
//!   by every job of the scene.
//! - [`run()`]: completes the scene ([`complete`]: camera, lights, environment), sizes the
//!   image ([`size`]), renders the samples (all, a partial range, or progressive passes) and
//!   writes the output; [`RunOptions`] says on which pool, with which progress report and
//!   notes, and whether it can be cancelled.
//!
//! Light units are converted in one place: [`crate::light::LightSet::new`] scales the job's
//! lights by [`RenderSettings::light_units`]. Default lights are radiometric, so a job whose
//! lights are all defaults renders them in radiometric units whatever the job's units.

pub mod check;
pub mod complete;
pub mod prepared;
mod run;
pub mod size;
pub mod sources;
pub mod studio;

pub use crate::scene::SceneSource;
pub use check::MAX_SPP;
pub use prepared::PreparedScene;
pub use run::{JobImages, JobOutput, RunOptions, run};
pub use size::{DEFAULT_ASPECT, DEFAULT_WIDTH, fixed_aspect, image_size};
pub use sources::{CameraChoice, EnvironmentSource, LightSource, OutputSpec, Samples};

use crate::accel::BackendKind;
use crate::light::LightUnits;
use crate::light::environment::EnvironmentError;
use crate::output::OutputError;
use crate::render::{RenderError, RenderSettings};
use crate::scene::defaults::NoSuchCamera;
use crate::scene::gltf::{LoadError, LoadOptions, SceneSelection};
use crate::scene::light_spec::LightSpecError;

/// One render: what to render, how, and where it goes. Plain data: every field is public and
/// [`Default`] is the demo scene at `glint render`'s defaults, which the Python package's
/// defaults are too (`tests/render/job_defaults.rs` and the Python crate's tests check both).
#[derive(Clone, Debug, PartialEq)]
pub struct Job {
    /// The scene.
    pub scene: SceneSource,
    /// Which of the file's scenes, and the animation time (`--scene`, `--time`).
    pub selection: SceneSelection,
    /// How the file is loaded: asset root and texture budget (`--asset-root`,
    /// `--max-texture-pixels`).
    pub load_options: LoadOptions,
    /// The ray-query backend.
    pub backend: BackendKind,
    /// The camera.
    pub camera: CameraChoice,
    /// Lights added to the scene's own.
    pub lights: Vec<LightSource>,
    /// The environment; `None` leaves it to [`complete::environment_for`] (the default
    /// environment for a path-traced scene without punctual lights, else none).
    pub environment: Option<EnvironmentSource>,
    /// Units of the scene's and the added lights' intensities.
    pub light_units: LightUnits,
    /// Image width; `None` derives it from the height and the camera (see [`image_size`]).
    pub width: Option<u32>,
    /// Image height; `None` derives it from the width and the camera.
    pub height: Option<u32>,
    /// Everything else about the render (its width, height and light units are set from the
    /// fields above when the job runs). The AOVs to produce are `settings.aovs`.
    pub settings: RenderSettings,
    /// Which samples.
    pub samples: Samples,
    /// Where the image goes; `None` renders without writing.
    pub output: Option<OutputSpec>,
    /// The flow AOVs' time step Δ in seconds (`--flow-dt`; `glint batch` sets it to the
    /// frame interval of an animation sweep): `flow` goes to `time + Δ`, `flow_backward` to
    /// `time − Δ`. `None`: [`DEFAULT_FLOW_DT`].
    pub flow_dt: Option<f32>,
    /// Categories for per-instance annotations (`--category NAME=CATEGORY`): a node's or
    /// mesh's name and the category its instances get
    /// ([`crate::output::instances::annotate`]).
    pub categories: Vec<(String, String)>,
    /// Denoise the finished image with Open Image Denoise ([`crate::denoise`]; `--denoise`):
    /// the albedo and normal AOVs are rendered for it, PNG gets the denoised image, EXR the
    /// denoised one with the noisy radiance as its `noisy.R/G/B` layer.
    pub denoise: bool,
    /// Most bytes the render's own buffers (film, AOVs, resolved images, the denoiser's and the
    /// encoder's copies) may take, estimated before they are allocated ([`Job::memory_estimate`];
    /// `--max-memory`). `None`: [`crate::output::budget::memory_budget`] (half of physical
    /// memory, or `GLINT_MAX_MEMORY`).
    pub max_memory: Option<u64>,
}

/// The flow AOVs' time step when none is given: one frame at 24 frames per second.
pub const DEFAULT_FLOW_DT: f32 = 1.0 / 24.0;

impl Default for Job {
    fn default() -> Self {
        Self {
            scene: SceneSource::Demo,
            selection: SceneSelection::default(),
            load_options: LoadOptions::default(),
            backend: BackendKind::default(),
            camera: CameraChoice::First,
            lights: Vec::new(),
            environment: None,
            light_units: LightUnits::Radiometric,
            width: None,
            height: None,
            settings: RenderSettings::default(),
            samples: Samples::All,
            output: None,
            flow_dt: None,
            categories: Vec::new(),
            denoise: false,
            max_memory: None,
        }
    }
}

/// Why a job could not run. Messages name the scene (through [`JobError::InScene`]), the
/// option or file at fault, and the fix.
#[derive(Debug, thiserror::Error)]
pub enum JobError {
    /// Options that cannot be honoured together, or out of range.
    #[error("{0}")]
    Options(String),
    /// The output cannot be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The scene cannot be loaded.
    #[error(transparent)]
    Load(#[from] LoadError),
    /// The camera asked for does not exist.
    #[error(transparent)]
    Camera(#[from] NoSuchCamera),
    /// A light spec cannot be parsed.
    #[error("--light '{spec}': {source}")]
    LightSpec {
        /// The spec.
        spec: String,
        /// Why.
        source: LightSpecError,
    },
    /// A lights file cannot be used.
    #[error(transparent)]
    LightsFile(LightSpecError),
    /// The environment cannot be loaded.
    #[error(transparent)]
    Environment(#[from] EnvironmentError),
    /// The render failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The image could not be denoised (or this build cannot denoise).
    #[error(transparent)]
    Denoise(#[from] crate::denoise::DenoiseError),
    /// One of the above, in the named scene.
    #[error("{scene}: {source}")]
    InScene {
        /// The scene's label ([`SceneSource::label`]).
        scene: String,
        /// The error.
        source: Box<JobError>,
    },
}

impl JobError {
    fn in_scene(self, scene: &str) -> Self {
        JobError::InScene {
            scene: scene.to_string(),
            source: Box::new(self),
        }
    }
}
