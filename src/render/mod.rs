//! The renderer: the rendering equation by path tracing, or direct light only, in radiometric
//! units (radiance in W/(m²·sr)).
//!
//! - [`prepare`]: scene → acceleration structure (reusable across renders).
//! - [`render`]: one image of a prepared scene through one camera.
//! - [`camera`], [`sampler`], [`film`], [`tiles`]: the pieces, each a small type.
//! - `wavefront`: the skeleton every integrator runs on (camera samples, batched tracing,
//!   shadow batches, first-hit AOVs); [`path`]: the integrator (path tracing, or direct light
//!   with `Integrator::Direct`).
//! - [`kernel`]: which per-hit work a scene needs.
//! - [`stats`]: what a render traced and what it skipped.
//!
//! Tiles render in parallel on a dedicated rayon pool of [`RenderSettings::threads`] threads.

pub mod adaptive;
pub mod amodal;
pub mod aov;
pub mod camera;
pub mod film;
pub mod filter;
pub mod ground_truth;
pub mod guided;
pub mod ids;
pub mod kernel;
pub mod medium;
pub mod partial;
pub mod path;
pub mod progressive;
pub mod projection;
pub mod sampler;
pub mod scheduler;
pub mod stats;
pub mod tiles;
pub(crate) mod visibility;
pub(crate) mod wavefront;

pub use crate::bsdf::BrdfModel;
pub use camera::CameraRays;
pub use film::{AovSelection, Aovs, Film, Image};
pub use filter::{FilterKind, FilterSpec};
pub use kernel::{KernelChoice, KernelFlags};
pub use progressive::{ProgressiveOutput, StopReason, StopRule, render_progressive};
pub use sampler::{PixelSampler, PixelSampling};
pub use scheduler::TileScheduler;
pub use stats::{RayCounts, RenderStats};

use crate::accel::{Accel, AccelError, BackendKind, BuildOptions};
use crate::light::{LightError, LightUnits};
use crate::scene::{Camera, Scene};
use crate::texture::TextureFilter;
use glam::Vec3;

/// Largest accepted image side, in pixels.
pub const MAX_IMAGE_SIDE: u32 = 1 << 16;
/// Largest accepted pixel count (2²⁸ ≈ 268 Mpixels: 3 GiB of radiance alone).
pub const MAX_PIXELS: u64 = 1 << 28;

/// The default transmission bounce budget ([`RenderSettings::max_transmission_depth`]):
/// enough for a smooth glass sphere's rim, where light bounces many times inside near the
/// critical angle, to read within 1 % of a depth-512 render in a white furnace
/// (`tests/transport/furnace_gltf.rs`).
pub const DEFAULT_MAX_TRANSMISSION_DEPTH: u32 = 64;

/// How to render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Seed of the per-(pixel, sample) sequence.
    pub seed: u64,
    /// Maximum number of mirror bounces (0: no reflection rays).
    pub max_depth: u32,
    /// Maximum number of transmission bounces, counted apart from `max_depth` (as Cycles
    /// counts them): a refraction, and a reflection off the inside of a surface that
    /// transmits (light bouncing inside glass), spends this budget instead of `max_depth`.
    pub max_transmission_depth: u32,
    /// Worker threads; 0 uses every core.
    pub threads: usize,
    /// Where samples go inside a pixel.
    pub sampling: PixelSampling,
    /// Auxiliary images to produce.
    pub aovs: AovSelection,
    /// Units of the scene's light intensities.
    pub light_units: LightUnits,
    /// Specialised or general shading kernel.
    pub kernel: KernelChoice,
    /// How textures are filtered (anisotropic by default).
    pub texture_filter: TextureFilter,
    /// Pixel reconstruction filter.
    pub filter: FilterSpec,
    /// Which light-transport estimator runs.
    pub integrator: Integrator,
    /// Whether camera rays that miss show the environment (the alpha channel is coverage
    /// either way).
    pub environment_visible: bool,
    /// Which strategies estimate light from area lights and the environment in the path
    /// tracer (MIS by default; the single strategies exist to test the estimators).
    pub light_strategy: LightStrategy,
    /// Whether the path tracer ends paths by Russian roulette (unbiased either way; off, every
    /// path runs to `max_depth`).
    pub russian_roulette: bool,
    /// The metallic-roughness model: energy-compensated (default) or the glTF spec's
    /// Appendix B exactly.
    pub brdf: BrdfModel,
    /// Adaptive sampling ([`adaptive`]): the per-pixel relative RMS error below which a pixel
    /// may stop taking samples (unbiased: stopping is a Russian roulette); `None`: every
    /// pixel takes every sample.
    pub adaptive: Option<f32>,
    /// Biased, off by default: the largest luminance one indirect contribution (a path vertex
    /// after the first bounce, or light reached through one) may add to a pixel; larger ones
    /// are scaled down to it. Removes fireflies and the energy they carry.
    pub clamp_indirect: Option<f32>,
    /// MIS compensation (on by default): where the path tracer combines environment samples
    /// with BSDF samples by MIS, environment directions come from the map's excess over its
    /// mean (Karlík et al. 2019), leaving the dim part to BSDF sampling. Unbiased either way.
    pub mis_compensation: bool,
    /// Path guiding ([`guided`], [`crate::guiding`]; off by default): the path tracer learns
    /// where light comes from in its first passes and then draws half of each rough vertex's
    /// continuations from what it learned. Unbiased; path tracer only.
    pub guiding: bool,
}

/// How the path tracer estimates light from surfaces and the environment it can also hit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LightStrategy {
    /// Light sampling and BSDF sampling, combined by the power heuristic.
    #[default]
    Mis,
    /// Light sampling only: emitters hit by BSDF-sampled rays are not counted.
    LightOnly,
    /// BSDF sampling only: no light samples toward area lights or the environment (punctual
    /// lights, which no ray can hit, are still sampled).
    BsdfOnly,
}

/// The light-transport estimator.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Integrator {
    /// Unidirectional path tracing with next-event estimation and MIS ([`path`]): the
    /// default, of the engine as of `glint render`, batch jobs and Python.
    #[default]
    Path,
    /// Direct light only (punctual, area and environment lights by light sampling) plus
    /// specular chains (delta lobes: smooth metal, glass, coat), with the path tracer's BSDF;
    /// exact for up to four delta lights.
    Direct,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
            spp: 16,
            seed: 0,
            max_depth: 8,
            max_transmission_depth: DEFAULT_MAX_TRANSMISSION_DEPTH,
            threads: 0,
            sampling: PixelSampling::Sobol,
            aovs: AovSelection::default(),
            light_units: LightUnits::Radiometric,
            kernel: KernelChoice::Specialised,
            texture_filter: TextureFilter::default(),
            filter: FilterSpec::default(),
            integrator: Integrator::default(),
            environment_visible: true,
            light_strategy: LightStrategy::Mis,
            russian_roulette: true,
            brdf: BrdfModel::default(),
            adaptive: None,
            clamp_indirect: None,
            mis_compensation: true,
            guiding: false,
        }
    }
}

/// A finished render.
#[derive(Clone, Debug)]
pub struct RenderOutput {
    /// Radiance per pixel, W/(m²·sr), reconstructed with the settings' pixel filter.
    pub image: Image<Vec3>,
    /// The selected auxiliary images.
    pub aovs: Aovs,
    /// What the render did.
    pub stats: RenderStats,
}

/// Why a render could not run.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The settings are unusable.
    #[error("invalid render settings: {0}")]
    Settings(String),
    /// The camera is unusable.
    #[error(
        "camera \"{name}\": {reason}; fix the camera in the scene or pick another with --camera"
    )]
    Camera {
        /// The camera's name.
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// A light is unusable.
    #[error(transparent)]
    Light(#[from] LightError),
    /// The acceleration structure could not be built.
    #[error("could not build the {backend} ray-query structure: {source}")]
    Accel {
        /// Which backend.
        backend: BackendKind,
        /// Why.
        source: AccelError,
    },
    /// The acceleration structure was built from other geometry.
    #[error(
        "the ray-query structure holds {accel} triangles but the scene has {scene}: build it \
         from this scene with render::prepare"
    )]
    AccelMismatch {
        /// Triangles in the structure.
        accel: usize,
        /// Triangles in the scene.
        scene: usize,
    },
    /// The caller asked the render to stop ([`RenderInputs::cancel`]); no image was made.
    #[error("the render was cancelled")]
    Cancelled,
    /// The worker threads could not be started.
    #[error("could not start {threads} render threads: {reason}")]
    Threads {
        /// Requested count (0: all cores).
        threads: usize,
        /// Why.
        reason: String,
    },
}

/// Builds the ray-query structure for `scene` with `backend`: the part of a render that
/// depends only on the scene, so batch jobs can share one across many renders.
pub fn prepare(
    scene: &Scene,
    backend: BackendKind,
    options: BuildOptions,
) -> Result<Box<dyn Accel>, RenderError> {
    crate::accel::build(backend, &scene.triangle_meshes(), options)
        .map_err(|source| RenderError::Accel { backend, source })
}

/// A progress report: `(tiles done, tiles in total)`, called from worker threads.
pub type Progress<'a> = &'a (dyn Fn(usize, usize) + Sync);

/// Renders `scene` (whose ray-query structure is `accel`, from [`prepare`]) through `camera`.
pub fn render(
    scene: &Scene,
    accel: &dyn Accel,
    camera: &Camera,
    settings: &RenderSettings,
    progress: Option<Progress<'_>>,
) -> Result<RenderOutput, RenderError> {
    let inputs = RenderInputs::of_scene(scene, accel, camera);
    render_with(&inputs, settings, progress)
}

/// [`render`] from [`RenderInputs`]: all `settings.spp` samples, in one pass, or with
/// adaptive sampling ([`RenderSettings::adaptive`]) in passes between which converged pixels
/// stop.
pub fn render_with(
    inputs: &RenderInputs<'_>,
    settings: &RenderSettings,
    progress: Option<Progress<'_>>,
) -> Result<RenderOutput, RenderError> {
    if settings.adaptive.is_none() && !settings.guiding {
        let (film, stats) = render_film(inputs, settings, 0..settings.spp, progress)?;
        let (image, aovs) = film.resolve();
        return Ok(RenderOutput { image, aovs, stats });
    }
    let mut renderer = TileScheduler::with_inputs(inputs, settings)?;
    // Passes end where adaptive sampling decides and where the guide is relearned.
    let adaptive_passes = if settings.adaptive.is_some() {
        adaptive::schedule(settings.spp)
    } else {
        Vec::new()
    };
    let decisions: Vec<u32> = adaptive_passes
        .iter()
        .scan(0u32, |total, &p| {
            *total += p;
            Some(*total)
        })
        .collect();
    let training = if settings.guiding {
        guided::training_passes(settings.spp)
    } else {
        Vec::new()
    };
    for pass in guided::merged_schedule(settings.spp, &adaptive_passes, &training) {
        if decisions.contains(&renderer.samples_per_pixel()) {
            renderer.adapt();
        }
        renderer.render_pass(pass, progress);
        if renderer.cancelled() {
            return Err(RenderError::Cancelled);
        }
    }
    Ok(renderer.finish())
}

/// What a render reads besides its settings, for callers that share one scene across many
/// renders ([`partial`], `glint batch`): the lights are passed apart from the scene so that
/// jobs with different lights (default lights follow the camera) need no copy of the scene,
/// and `pool` lets concurrent jobs share one pool instead of each starting its own.
#[derive(Clone, Copy)]
pub struct RenderInputs<'a> {
    /// The scene's geometry, materials and textures. Its `lights` are not read here: `lights`
    /// is the full list (for a job, `scene::defaults::lights_for` builds it from the scene's).
    pub scene: &'a Scene,
    /// The lights to render with.
    pub lights: &'a [crate::scene::Light],
    /// The scene's ray-query structure, from [`prepare`].
    pub accel: &'a dyn Accel,
    /// The camera.
    pub camera: &'a Camera,
    /// The pool to render on; `None` starts one of [`RenderSettings::threads`] threads.
    pub pool: Option<&'a rayon::ThreadPool>,
    /// The scene's MIP chains from [`build_mipmaps`], built once at load and shared by every
    /// render of the scene; `None` builds them for this render (when it reads textures).
    pub mipmaps: Option<&'a [crate::texture::MipMap]>,
    /// The environment light, if any.
    pub environment: Option<&'a crate::light::environment::EnvironmentLight>,
    /// The scene's emissive triangles from [`build_area_lights`], built once at load; `None`
    /// builds them for this render.
    pub area_lights: Option<&'a crate::light::area::AreaLights>,
    /// Set by the caller to stop the render: checked before each tile and between passes
    /// (tiles already started finish), after which the render fails with
    /// [`RenderError::Cancelled`]. `None`: not cancellable.
    pub cancel: Option<&'a std::sync::atomic::AtomicBool>,
}

/// Emissive-triangle counts from which lights are chosen by the light BVH rather than by
/// power alone (a BVH over a handful of emitters costs more than it saves).
pub const LIGHT_BVH_MIN_EMITTERS: usize = 16;

/// The scene's emissive triangles as area lights, with their selection tables: work that
/// depends only on the scene, done once at load. A triangle's power uses its material's
/// emissive factor times its emissive texture's mean over the triangle's own uv footprint
/// ([`crate::light::emission_average`]): the texture's value still varies inside the triangle,
/// which changes how well the sampling density fits, not the estimate's mean. `mipmaps` are
/// the scene's MIP chains from [`build_mipmaps`] when already built; without them (or for a
/// texture they lack) the emissive textures' chains are built here. Empty when nothing emits.
pub fn build_area_lights(
    scene: &Scene,
    mipmaps: Option<&[crate::texture::MipMap]>,
) -> Result<crate::light::area::AreaLights, RenderError> {
    use crate::light::area::{AreaLights, SelectionMode};
    use crate::light::emission_average::triangle_mean;
    use crate::texture::MipMap;
    use std::collections::BTreeMap;
    let emitting = |m: &crate::scene::Material| m.emissive.max_element() > 0.0;
    // The MIP chains of emissive textures the caller did not supply.
    let own: BTreeMap<usize, MipMap> = scene
        .materials
        .iter()
        .filter(|m| emitting(m))
        .filter_map(|m| m.emissive_texture.map(|t| t.texture))
        .filter(|&t| mipmaps.is_none_or(|given| given.get(t).is_none()))
        .filter_map(|t| {
            scene
                .textures
                .get(t)
                .map(|texture| (t, MipMap::new(texture)))
        })
        .collect();
    let mip_of = |t: usize| {
        own.get(&t)
            .or_else(|| mipmaps.and_then(|given| given.get(t)))
    };
    let emitters: usize = scene
        .meshes
        .iter()
        .filter(|m| scene.materials.get(m.material).is_some_and(emitting))
        .map(crate::scene::Mesh::drawn_triangles)
        .sum();
    let mode = if emitters >= LIGHT_BVH_MIN_EMITTERS {
        SelectionMode::Bvh
    } else {
        SelectionMode::Power
    };
    let le = |mesh: u32, triangle: u32| {
        let Some(mesh) = scene.meshes.get(mesh as usize) else {
            return glam::Vec3::ZERO;
        };
        let Some(material) = scene.materials.get(mesh.material).filter(|m| emitting(m)) else {
            return glam::Vec3::ZERO;
        };
        let texture_mean = material
            .emissive_texture
            .and_then(|t| {
                let mip = mip_of(t.texture)?;
                triangle_mean(mesh, triangle as usize, &t, mip)
            })
            // No (valid) texture: the factor alone, as the shading does.
            .unwrap_or(glam::Vec3::ONE);
        material.emissive * texture_mean
    };
    AreaLights::from_scene(scene, le, mode).map_err(|e| RenderError::Settings(e.to_string()))
}

/// The MIP chains of every texture of `scene`, index-aligned with `scene.textures`: work that
/// depends only on the scene, done once at load.
pub fn build_mipmaps(scene: &Scene) -> Vec<crate::texture::MipMap> {
    use rayon::prelude::*;
    scene
        .textures
        .par_iter()
        .map(crate::texture::MipMap::new)
        .collect()
}

impl<'a> RenderInputs<'a> {
    /// The scene with its own lights, on a pool of the render's own.
    pub fn of_scene(scene: &'a Scene, accel: &'a dyn Accel, camera: &'a Camera) -> Self {
        Self {
            scene,
            lights: &scene.lights,
            accel,
            camera,
            pool: None,
            mipmaps: None,
            environment: None,
            area_lights: None,
            cancel: None,
        }
    }
}

/// Renders the samples with indices in `samples` (of `settings.spp`, whose strata and seed
/// fix every sample's position) and returns the unresolved film: per-pixel sums over exactly
/// those samples. `render` is this over `0..spp`, resolved.
pub fn render_film(
    inputs: &RenderInputs<'_>,
    settings: &RenderSettings,
    samples: std::ops::Range<u32>,
    progress: Option<Progress<'_>>,
) -> Result<(Film, RenderStats), RenderError> {
    // The settings themselves are validated once, by the scheduler (spp = 0 included, so
    // that it is reported as such rather than as an empty range).
    if settings.adaptive.is_some() {
        return Err(RenderError::Settings(
            "adaptive sampling renders whole images (render_with), not sample ranges or \
             partial renders"
                .into(),
        ));
    }
    if settings.guiding {
        return Err(RenderError::Settings(
            "path guiding trains across a whole render's passes (render_with), so it cannot \
             render sample ranges or partial renders; drop --guiding"
                .into(),
        ));
    }
    if settings.spp > 0 && (samples.start >= samples.end || samples.end > settings.spp) {
        return Err(RenderError::Settings(format!(
            "sample range {}..{} must be non-empty and within 0..{} (the samples per pixel)",
            samples.start, samples.end, settings.spp
        )));
    }
    let mut renderer = TileScheduler::with_inputs(inputs, settings)?;
    renderer.render_samples(samples, progress);
    if renderer.cancelled() {
        return Err(RenderError::Cancelled);
    }
    Ok(renderer.into_film())
}

pub(crate) fn validate(s: &RenderSettings) -> Result<(), RenderError> {
    let bad = |m: String| Err(RenderError::Settings(m));
    if s.width == 0 || s.height == 0 || s.width > MAX_IMAGE_SIDE || s.height > MAX_IMAGE_SIDE {
        return bad(format!(
            "image size {}×{} must be between 1 and {MAX_IMAGE_SIDE} pixels per side",
            s.width, s.height
        ));
    }
    if s.width as u64 * s.height as u64 > MAX_PIXELS {
        return bad(format!(
            "image size {}×{} exceeds {MAX_PIXELS} pixels",
            s.width, s.height
        ));
    }
    if s.spp == 0 {
        return bad("samples per pixel must be at least 1".into());
    }
    if let Some(t) = s.adaptive
        && !(t > 0.0 && t.is_finite())
    {
        return bad(format!(
            "adaptive threshold {t} must be a positive relative error, e.g. 0.01"
        ));
    }
    if s.guiding && s.integrator != Integrator::Path {
        return bad("path guiding (--guiding) needs the path tracer: add --integrator path".into());
    }
    if let Some(c) = s.clamp_indirect
        && !(c > 0.0 && c.is_finite())
    {
        return bad(format!(
            "indirect clamp {c} must be a positive radiance (W/(m²·sr)), e.g. 10"
        ));
    }
    Ok(())
}

/// The pool the tiles run on; each worker is set up for `backend` first
/// ([`BackendKind::prepare_worker_thread`]).
pub fn thread_pool(threads: usize, backend: BackendKind) -> Result<rayon::ThreadPool, RenderError> {
    let builder = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("glint-render-{i}"))
        .start_handler(move |_| backend.prepare_worker_thread());
    builder.build().map_err(|e| RenderError::Threads {
        threads,
        reason: e.to_string(),
    })
}

impl Integrator {
    /// Every integrator, in the order the command line lists them.
    pub const ALL: [Integrator; 2] = [Integrator::Path, Integrator::Direct];

    /// Name on the command line and in job files: `path`, `direct`.
    pub fn name(self) -> &'static str {
        match self {
            Integrator::Path => "path",
            Integrator::Direct => "direct",
        }
    }
}

impl std::fmt::Display for Integrator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Integrator {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Integrator::ALL
            .into_iter()
            .find(|i| i.name() == s)
            .ok_or_else(|| format!("unknown integrator '{s}' (expected path or direct)"))
    }
}
