//! One render job, from a scene source to files on disk: the library's single entry point for
//! `glint render`, each job of `glint batch`, and anything else that renders a whole image.
//!
//! - [`PreparedScene`]: everything derived from a scene at load — the scene itself, its
//!   ray-query structure and its MIP chains — built once and shared by every job of the scene.
//! - [`Job`]: plain data saying what to render: the scene, the backend, the camera, extra
//!   lights and their units, the image size, the [`RenderSettings`], which samples, and where
//!   the image goes. `Default` gives the demo scene at `glint render`'s defaults.
//! - [`run`]: completes the scene ([`crate::scene::defaults`]: camera, lights), sizes the
//!   image, renders the samples (all, a partial range, or progressive passes) and writes the
//!   output.
//!
//! Light units are converted in one place: [`crate::light::LightSet::new`] scales the job's
//! lights by [`RenderSettings::light_units`]. Default lights are radiometric, so a job whose
//! lights are all defaults renders them in radiometric units whatever the job's units.

use super::{Progress, RenderError, RenderSettings, RenderStats, StopRule};
use crate::accel::{Accel, BackendKind, BuildOptions};
use crate::light::LightUnits;
use crate::light::area::AreaLights;
use crate::light::environment::{EnvironmentError, EnvironmentLight};
use crate::output::{OutputError, OutputFormat, PngDepth, PngOptions, write_exr, write_png};
use crate::scene::defaults::{self, NoSuchCamera};
use crate::scene::gltf::{LoadError, LoadOptions, SceneSelection};
use crate::scene::light_spec::{self, LightSpecError};
use crate::scene::{Camera, Light, Projection, Scene};
use crate::texture::MipMap;
use glam::Vec3;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// Most samples per pixel a job accepts (2^24): beyond it f32 sample sums stop resolving a
/// single sample's contribution.
pub const MAX_SPP: u32 = 1 << 24;

/// Image width when the job gives neither width nor height.
pub const DEFAULT_WIDTH: u32 = 1280;
/// Aspect ratio (width / height) for cameras that do not fix one: 16:9.
pub const DEFAULT_ASPECT: f32 = 16.0 / 9.0;

/// Where a job's scene comes from.
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
            SceneSource::Demo => crate::scene::demo::demo_scene(),
            SceneSource::File(path) => crate::scene::gltf::load_full(path, selection, options)
                .map(crate::scene::gltf::print_warnings),
        }
    }
}

/// Which camera a job renders through.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum CameraChoice {
    /// The scene's first camera, or the default camera if it has none.
    #[default]
    First,
    /// The scene's camera with this index (from 0).
    Index(usize),
    /// A perspective camera placed by position ([`Camera::look_at`]).
    LookAt {
        /// Name in messages.
        name: String,
        /// Camera position, world space.
        position: Vec3,
        /// The point looked at.
        target: Vec3,
        /// The world direction that appears up.
        up: Vec3,
        /// Vertical field of view in radians; `None` keeps the field of view of the camera
        /// [`CameraChoice::First`] picks, or of the default camera if that one is orthographic.
        yfov: Option<f32>,
    },
    /// This camera, as given.
    Given(Camera),
}

/// Lights a job adds to the scene's own, in the job's [`Job::light_units`].
#[derive(Clone, Debug, PartialEq)]
pub enum LightSource {
    /// A light, as given.
    Light(Light),
    /// A light spec (format in docs/render.md, "Scenes without a camera or lights"), parsed
    /// when the job runs.
    Spec(String),
    /// A lights file, read when the job runs.
    File(PathBuf),
}

/// The environment a job renders under: a light at infinity seen by rays that leave the scene.
#[derive(Clone, Debug, PartialEq)]
pub enum EnvironmentSource {
    /// An equirectangular `.hdr` or `.exr` (mapping in [`crate::light::environment`]).
    File {
        /// The image.
        path: PathBuf,
        /// Radiance multiplier.
        strength: f32,
        /// Right-handed turn about +Y, degrees.
        rotation_deg: f32,
    },
    /// A uniform environment of this radiance, W/(m²·sr).
    Constant(Vec3),
}

impl EnvironmentSource {
    /// Loads (or builds) the environment light.
    pub fn light(&self) -> Result<EnvironmentLight, EnvironmentError> {
        match self {
            EnvironmentSource::File {
                path,
                strength,
                rotation_deg,
            } => EnvironmentLight::from_file(path, *strength, *rotation_deg),
            EnvironmentSource::Constant(radiance) => Ok(EnvironmentLight::constant(*radiance)),
        }
    }
}

/// Which samples of [`RenderSettings::spp`] a job renders.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Samples {
    /// All of `0..spp`, resolved into an image.
    #[default]
    All,
    /// Only these sample indices, written as a partial EXR of sums for `glint merge`.
    Range(Range<u32>),
    /// Shard `index` of `count` of `0..spp` (a balanced split), as a partial EXR.
    Shard {
        /// Which shard, from 0.
        index: u32,
        /// How many shards.
        count: u32,
    },
    /// Passes of samples until the rule says stop (`spp` is then ignored).
    Progressive(StopRule),
}

/// Where and how a job's image is written.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OutputSpec {
    /// The file; its extension (.png or .exr) picks the format.
    pub path: PathBuf,
    /// Exposure in stops for PNG output (radiance × 2^EV).
    pub exposure_ev: f32,
    /// 16 bits per channel in PNG output.
    pub png16: bool,
}

/// One render: what to render, how, and where it goes. Plain data: every field is public and
/// [`Default`] is the demo scene at `glint render`'s defaults.
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
    /// The environment; `None` leaves it to [`defaults::environment_for`] (the default
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
}

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

/// A loaded scene and everything derived from it at load, shared by every job of the scene.
pub struct PreparedScene {
    /// The scene as loaded (its own lights; job lights are added per job).
    pub scene: Scene,
    /// The scene's name in messages.
    pub label: String,
    /// Its ray-query structure.
    pub accel: Box<dyn Accel>,
    /// Its MIP chains ([`super::build_mipmaps`]), index-aligned with `scene.textures`.
    pub mipmaps: Vec<MipMap>,
    /// Its emissive triangles as lights ([`super::build_area_lights`]; empty when nothing
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
        let accel = super::prepare(&scene, backend, BuildOptions::default())
            .map_err(|e| JobError::from(e).in_scene(&label))?;
        let mipmaps = super::build_mipmaps(&scene);
        let area_lights = super::build_area_lights(&scene, Some(&mipmaps))
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

/// What [`run`] rendered (and wrote, if the job has an output).
#[derive(Clone, Debug)]
pub struct JobOutput {
    /// The file written, if any.
    pub output: Option<PathBuf>,
    /// Image size in pixels.
    pub width: u32,
    /// Image size in pixels.
    pub height: u32,
    /// The samples rendered (all of 0..spp unless partial or progressive).
    pub samples: Range<u32>,
    /// What the render traced.
    pub stats: RenderStats,
    /// How the samples were chosen, for a summary line: a partial range, or why a
    /// progressive render stopped ("" for a plain render).
    pub note: String,
}

impl Job {
    /// Rejects option combinations that cannot be honoured, before any work is done. Returns
    /// notes for the user (options that have no effect).
    pub fn check(&self) -> Result<Vec<String>, JobError> {
        let mut notes = Vec::new();
        let bad = |m: String| Err(JobError::Options(m));
        if self.settings.spp == 0 {
            return bad("--spp must be at least 1".into());
        }
        if self.settings.spp > MAX_SPP {
            return bad(format!(
                "--spp {} is above the limit of {MAX_SPP}; render shards (--shard) and merge \
                 them for more",
                self.settings.spp
            ));
        }
        let partial = matches!(self.samples, Samples::Range(_) | Samples::Shard { .. });
        if partial && self.settings.aovs.any_ids() {
            return bad(
                "--aov instance_id, material_id and coverage are whole-image results, not \
                 sums that merge: render them without --sample-range/--shard"
                    .into(),
            );
        }
        if self.width == Some(0) || self.height == Some(0) {
            return bad("--width and --height must be at least 1".into());
        }
        let side = self.width.max(self.height).unwrap_or(0);
        let pixels = u64::from(self.width.unwrap_or(1)) * u64::from(self.height.unwrap_or(1));
        if side > super::MAX_IMAGE_SIDE || pixels > super::MAX_PIXELS {
            return bad(format!(
                "--width/--height {}×{} exceed the limits of {} per side and {} pixels",
                self.width.map_or("auto".to_string(), |w| w.to_string()),
                self.height.map_or("auto".to_string(), |h| h.to_string()),
                super::MAX_IMAGE_SIDE,
                super::MAX_PIXELS
            ));
        }
        let Some(out) = &self.output else {
            return Ok(notes);
        };
        let format = OutputFormat::from_path(&out.path)?;
        let path = out.path.display();
        if format == OutputFormat::Png && self.settings.aovs.any() {
            return bad(format!(
                "{path}: --aov needs an EXR output (AOVs are linear data); use -o NAME.exr"
            ));
        }
        if format == OutputFormat::Png && partial {
            return bad(format!(
                "{path}: a partial render (--sample-range, --shard) writes sample sums to EXR; \
                 use -o NAME.exr and combine the parts with glint merge"
            ));
        }
        if format == OutputFormat::Exr && out.png16 {
            return bad(format!(
                "{path}: --png16 applies to PNG output; EXR is always 32-bit float"
            ));
        }
        if format == OutputFormat::Exr && out.exposure_ev != 0.0 {
            notes
                .push("note: --exposure applies to PNG only; the EXR holds linear radiance".into());
        }
        if !out.exposure_ev.is_finite() {
            return bad(format!("--exposure {} is not a number", out.exposure_ev));
        }
        let folder = match out.path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        if !folder.is_dir() {
            return bad(format!(
                "cannot write {path}: the folder {} does not exist; create it first",
                folder.display()
            ));
        }
        Ok(notes)
    }

    /// The camera the job renders through in `scene`, with the announcement of a default one.
    pub fn camera(&self, scene: &Scene) -> Result<defaults::Completed<Camera>, JobError> {
        Ok(match &self.camera {
            CameraChoice::First => defaults::camera_for(scene, None)?,
            CameraChoice::Index(i) => defaults::camera_for(scene, Some(*i))?,
            CameraChoice::Given(camera) => defaults::Completed {
                value: camera.clone(),
                added: None,
            },
            CameraChoice::LookAt {
                name,
                position,
                target,
                up,
                yfov,
            } => {
                let yfov = match yfov {
                    Some(y) => *y,
                    None => match defaults::camera_for(scene, None)?.value.projection {
                        Projection::Perspective { yfov, .. } => yfov,
                        Projection::Orthographic { .. } => {
                            match defaults::default_camera(scene).projection {
                                Projection::Perspective { yfov, .. } => yfov,
                                Projection::Orthographic { .. } => {
                                    defaults::DEFAULT_YFOV_DEGREES.to_radians()
                                }
                            }
                        }
                    },
                };
                let projection = Projection::Perspective {
                    yfov,
                    aspect_ratio: None,
                };
                defaults::Completed {
                    value: Camera::look_at(name, *position, *target, *up, projection),
                    added: None,
                }
            }
        })
    }

    /// The lights the job adds, parsed and read.
    fn extra_lights(&self) -> Result<Vec<Light>, JobError> {
        let mut lights = Vec::new();
        for source in &self.lights {
            match source {
                LightSource::Light(light) => lights.push(light.clone()),
                LightSource::Spec(spec) => {
                    lights.push(light_spec::parse_light(spec).map_err(|source| {
                        JobError::LightSpec {
                            spec: spec.clone(),
                            source,
                        }
                    })?)
                }
                LightSource::File(path) => {
                    lights.extend(light_spec::load_lights_file(path).map_err(JobError::LightsFile)?)
                }
            }
        }
        Ok(lights)
    }

    /// The samples of a partial job, checked against `spp`; `None` for a full one.
    fn partial_samples(&self) -> Result<Option<Range<u32>>, JobError> {
        let spp = self.settings.spp;
        let samples = match self.samples {
            Samples::Range(ref r) => r.clone(),
            Samples::Shard { index, count } => super::partial::shard_samples(spp, index, count),
            Samples::All | Samples::Progressive(_) => return Ok(None),
        };
        if samples.is_empty() || samples.end > spp {
            return Err(JobError::Options(format!(
                "samples {}..{} are not a non-empty part of the {spp} samples per pixel; pick a \
                 range within 0..{spp} (or fewer shards than samples)",
                samples.start, samples.end
            )));
        }
        Ok(Some(samples))
    }
}

/// Runs `job` on `prepared` (which must come from the job's scene and backend): completes the
/// camera and lights, renders and writes the output. `pool`: a pool shared with other jobs
/// (`None` starts one); `say` receives notes for the user (default camera or lights added,
/// stretched aspect ratio).
pub fn run(
    job: &Job,
    prepared: &PreparedScene,
    pool: Option<&rayon::ThreadPool>,
    progress: Option<Progress<'_>>,
    say: &dyn Fn(String),
) -> Result<JobOutput, JobError> {
    run_in_scene(job, prepared, pool, progress, say, None).map_err(|e| e.in_scene(&prepared.label))
}

/// [`run`], stoppable: setting `cancel` makes the render stop at the next tile and the job fail
/// with [`RenderError::Cancelled`] (nothing is written). The Python package's Ctrl-C.
pub fn run_cancellable(
    job: &Job,
    prepared: &PreparedScene,
    pool: Option<&rayon::ThreadPool>,
    progress: Option<Progress<'_>>,
    say: &dyn Fn(String),
    cancel: &std::sync::atomic::AtomicBool,
) -> Result<JobOutput, JobError> {
    run_in_scene(job, prepared, pool, progress, say, Some(cancel))
        .map_err(|e| e.in_scene(&prepared.label))
}

/// Resolved images of a job, for callers that keep them in memory (the Python package):
/// what [`run_images`] returns besides the [`JobOutput`].
#[derive(Clone, Debug)]
pub struct JobImages {
    /// Radiance, W/(m²·sr).
    pub image: super::Image<Vec3>,
    /// The selected AOVs.
    pub aovs: super::Aovs,
}

fn run_in_scene(
    job: &Job,
    prepared: &PreparedScene,
    pool: Option<&rayon::ThreadPool>,
    progress: Option<Progress<'_>>,
    say: &dyn Fn(String),
    cancel: Option<&std::sync::atomic::AtomicBool>,
) -> Result<JobOutput, JobError> {
    run_keeping(job, prepared, pool, progress, say, cancel).map(|(output, _)| output)
}

/// [`run_cancellable`] that also returns the resolved images (`None` for a partial job,
/// whose output is sums, not an image).
pub fn run_images(
    job: &Job,
    prepared: &PreparedScene,
    pool: Option<&rayon::ThreadPool>,
    progress: Option<Progress<'_>>,
    say: &dyn Fn(String),
    cancel: Option<&std::sync::atomic::AtomicBool>,
) -> Result<(JobOutput, Option<JobImages>), JobError> {
    run_keeping(job, prepared, pool, progress, say, cancel).map_err(|e| e.in_scene(&prepared.label))
}

fn run_keeping(
    job: &Job,
    prepared: &PreparedScene,
    pool: Option<&rayon::ThreadPool>,
    progress: Option<Progress<'_>>,
    say: &dyn Fn(String),
    cancel: Option<&std::sync::atomic::AtomicBool>,
) -> Result<(JobOutput, Option<JobImages>), JobError> {
    job.check()?;
    let scene = &prepared.scene;
    let camera = job.camera(scene)?;
    if let Some(note) = camera.added {
        say(note);
    }
    let camera = camera.value;
    let given = job
        .environment
        .as_ref()
        .map(|e| prepared.environment(e))
        .transpose()?;
    let extra = job.extra_lights()?;
    let environment = defaults::environment_for(scene, &extra, given, job.settings.integrator);
    if let Some(note) = environment.added {
        say(note);
    }
    let environment = environment.value;
    let lights = if environment.is_some() {
        // An environment lights the scene: no default sun on top of it.
        defaults::Completed {
            value: scene.lights.iter().cloned().chain(extra).collect(),
            added: None,
        }
    } else {
        defaults::lights_for(scene, extra, &camera)
    };
    // Default lights are radiometric: only lights from the scene or the job are in the job's
    // units.
    let light_units = match lights.added {
        Some(note) => {
            say(note);
            LightUnits::Radiometric
        }
        None => job.light_units,
    };
    let (width, height) = image_size(job.width, job.height, &camera);
    if let (Some(_), Some(_), Some(fixed)) = (job.width, job.height, fixed_aspect(&camera))
        && ((width as f32 / height as f32) / fixed - 1.0).abs() > 0.01
    {
        say(format!(
            "note: {width}×{height} differs from camera \"{}\"'s aspect ratio {fixed:.4}: the \
             image is stretched (give only --width or --height to keep it)",
            camera.name
        ));
    }
    let settings = RenderSettings {
        width,
        height,
        light_units,
        ..job.settings
    };
    let inputs = super::RenderInputs {
        scene,
        lights: &lights.value,
        accel: prepared.accel.as_ref(),
        camera: &camera,
        pool,
        mipmaps: Some(&prepared.mipmaps),
        environment: environment.as_deref(),
        area_lights: Some(&prepared.area_lights),
        cancel,
    };
    // Test-only (debug builds): a forced panic where the render starts, for tests/panics.rs.
    crate::panics::test_panic_point("render", &prepared.label);
    let output = job.output.as_ref();
    if let Some(samples) = job.partial_samples()? {
        let (part, stats) =
            super::partial::render_partial(&inputs, &settings, samples.clone(), progress)?;
        if let Some(out) = output {
            // What the part was rendered from, so that `glint merge` refuses foreign parts.
            let mut tag = crate::output::fingerprint::SceneTag::of(job, &camera, width, height)
                .map_err(|source| OutputError::Io {
                    path: out.path.clone(),
                    source,
                })?;
            tag.kernels = Some(prepared.accel.kernels());
            crate::output::partial::write_partial_exr_tagged(&out.path, &part, Some(&tag))?;
        }
        let note = format!(", samples {}..{} (partial)", samples.start, samples.end);
        return Ok((
            JobOutput {
                output: output.map(|o| o.path.clone()),
                width,
                height,
                samples,
                stats,
                note,
            },
            None,
        ));
    }
    let (image, aovs, stats, samples, note) = match &job.samples {
        Samples::Progressive(rule) => {
            let p =
                super::progressive::render_progressive_with(&inputs, &settings, rule, progress)?;
            let note = format!(
                "; stopped after {} passes ({:?}), estimated relative error {:.4}",
                p.passes, p.reason, p.relative_error
            );
            let o = p.output;
            (o.image, o.aovs, o.stats, 0..p.spp, note)
        }
        _ => {
            let (film, stats) = super::render_film(&inputs, &settings, 0..settings.spp, progress)?;
            let (image, aovs) = film.resolve();
            (image, aovs, stats, 0..settings.spp, String::new())
        }
    };
    if let Some(out) = output {
        match OutputFormat::from_path(&out.path)? {
            OutputFormat::Png => write_png(
                &out.path,
                &image,
                PngOptions {
                    exposure_ev: out.exposure_ev,
                    depth: if out.png16 {
                        PngDepth::Sixteen
                    } else {
                        PngDepth::Eight
                    },
                },
            ),
            OutputFormat::Exr => write_exr(&out.path, &image, &aovs),
        }?;
    }
    Ok((
        JobOutput {
            output: output.map(|o| o.path.clone()),
            width,
            height,
            samples,
            stats,
            note,
        },
        Some(JobImages { image, aovs }),
    ))
}

/// The aspect ratio (width / height) the camera fixes, if any.
pub fn fixed_aspect(camera: &Camera) -> Option<f32> {
    let aspect = match camera.projection {
        Projection::Perspective { aspect_ratio, .. } => aspect_ratio?,
        Projection::Orthographic { xmag, ymag } => (xmag / ymag).abs(),
    };
    (aspect.is_finite() && aspect > 0.0).then_some(aspect)
}

/// Image size from the job: both given are used as they are; one given derives the other from
/// the camera's aspect ratio ([`DEFAULT_ASPECT`] if it fixes none); none gives
/// [`DEFAULT_WIDTH`] wide.
pub fn image_size(width: Option<u32>, height: Option<u32>, camera: &Camera) -> (u32, u32) {
    let aspect = fixed_aspect(camera).unwrap_or(DEFAULT_ASPECT);
    let derive = |v: f32| (v.round() as u32).max(1);
    match (width, height) {
        (Some(w), Some(h)) => (w, h),
        (Some(w), None) => (w, derive(w as f32 / aspect)),
        (None, Some(h)) => (derive(h as f32 * aspect), h),
        (None, None) => (DEFAULT_WIDTH, derive(DEFAULT_WIDTH as f32 / aspect)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;

    fn camera(projection: Projection) -> Camera {
        Camera {
            name: "c".into(),
            world_from_camera: Mat4::IDENTITY,
            projection,
        }
    }

    #[test]
    fn size_follows_the_camera_aspect() {
        let free = camera(Projection::Perspective {
            yfov: 1.0,
            aspect_ratio: None,
        });
        assert_eq!(image_size(None, None, &free), (1280, 720));
        assert_eq!(image_size(Some(640), None, &free), (640, 360));
        let square = camera(Projection::Perspective {
            yfov: 1.0,
            aspect_ratio: Some(1.0),
        });
        assert_eq!(image_size(Some(300), None, &square), (300, 300));
        assert_eq!(image_size(None, Some(200), &square), (200, 200));
        let ortho = camera(Projection::Orthographic {
            xmag: 2.0,
            ymag: 1.0,
        });
        assert_eq!(image_size(Some(100), None, &ortho), (100, 50));
        assert_eq!(image_size(Some(7), Some(9), &ortho), (7, 9));
    }

    #[test]
    fn bad_options_are_refused_before_any_work() {
        let dir = tempfile::tempdir().unwrap();
        let job = |path: &str, f: &dyn Fn(&mut Job)| {
            let mut job = Job {
                output: Some(OutputSpec {
                    path: dir.path().join(path),
                    ..OutputSpec::default()
                }),
                ..Job::default()
            };
            f(&mut job);
            job.check()
        };
        assert!(job("a.png", &|_| {}).is_ok());
        assert!(job("a.png", &|j| j.settings.aovs.depth = true).is_err());
        assert!(job("a.png", &|j| j.samples = Samples::Range(0..2)).is_err());
        assert!(job("a.exr", &|j| j.output.as_mut().unwrap().png16 = true).is_err());
        assert!(job("a.png", &|j| j.settings.spp = 0).is_err());
        assert!(job("missing/a.png", &|_| {}).is_err());
        // ID AOVs are not sums: a partial render cannot carry them.
        let partial_ids = |j: &mut Job| {
            j.settings.aovs.coverage = true;
            j.samples = Samples::Shard { index: 0, count: 2 };
        };
        assert!(job("a.exr", &partial_ids).is_err());
        assert!(job("a.exr", &|j| j.settings.aovs.instance_id = true).is_ok());
        assert!(job("a.png", &|j| j.settings.aovs.material_id = true).is_err());
        let notes = job("a.exr", &|j| j.output.as_mut().unwrap().exposure_ev = 1.0).unwrap();
        assert_eq!(notes.len(), 1);
    }

    #[test]
    fn a_cancelled_job_fails_and_writes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.exr");
        let job = Job {
            width: Some(8),
            height: Some(6),
            backend: BackendKind::Bvh,
            output: Some(OutputSpec {
                path: path.clone(),
                ..OutputSpec::default()
            }),
            ..Job::default()
        };
        let prepared =
            PreparedScene::load(&job.scene, &job.selection, &job.load_options, job.backend)
                .unwrap();
        let cancel = std::sync::atomic::AtomicBool::new(true);
        let err = run_cancellable(&job, &prepared, None, None, &|_| {}, &cancel).unwrap_err();
        assert!(err.to_string().contains("cancelled"), "{err}");
        assert!(!path.exists());
        // The same job, not cancelled, renders.
        cancel.store(false, std::sync::atomic::Ordering::Relaxed);
        assert!(run_cancellable(&job, &prepared, None, None, &|_| {}, &cancel).is_ok());
        assert!(path.exists());
    }

    #[test]
    fn a_job_renders_without_an_output() {
        let job = Job {
            width: Some(8),
            height: Some(6),
            settings: RenderSettings {
                spp: 1,
                threads: 1,
                ..RenderSettings::default()
            },
            backend: BackendKind::Bvh,
            ..Job::default()
        };
        let prepared =
            PreparedScene::load(&job.scene, &job.selection, &job.load_options, job.backend)
                .unwrap();
        let notes = std::sync::Mutex::new(Vec::new());
        let done = run(&job, &prepared, None, None, &|n| {
            notes.lock().unwrap().push(n)
        })
        .unwrap();
        assert_eq!((done.width, done.height, done.samples), (8, 6, 0..1));
        assert!(done.output.is_none());
        assert!(done.stats.rays.camera == 48, "{:?}", done.stats.rays);
    }

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
