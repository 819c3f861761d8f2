//! The renderer: direct illumination from punctual lights, mirror reflections and emission,
//! in radiometric units (radiance in W/(m²·sr)).
//!
//! - [`prepare`]: scene → acceleration structure (reusable across renders).
//! - [`render`]: one image of a prepared scene through one camera.
//! - [`camera`], [`sampler`], [`film`], [`tiles`]: the pieces, each a small type.
//! - [`kernel`]: the shading kernel specialised for the scene's features.
//! - [`stats`]: what a render traced and what it skipped.
//!
//! Tiles render in parallel on a dedicated rayon pool of [`RenderSettings::threads`] threads.

pub mod camera;
pub mod film;
pub(crate) mod integrator;
pub mod kernel;
pub mod partial;
pub mod sampler;
pub mod stats;
pub mod tiles;

pub use camera::CameraRays;
pub use film::{AovSelection, Aovs, Film, Image};
pub use kernel::{KernelChoice, KernelFlags};
pub use sampler::{PixelSampler, PixelSampling};
pub use stats::{RayCounts, RenderStats};

use crate::accel::{Accel, AccelError, BackendKind, BuildOptions};
use crate::light::{LightError, LightSet, LightUnits};
use crate::material::ShadingMaterial;
use crate::scene::{Camera, Scene, SceneFeatures};
use crate::texture::{MipMap, TextureFilter};
use glam::Vec3;
use integrator::{Scratch, TileContext};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// Largest accepted image side, in pixels.
pub const MAX_IMAGE_SIDE: u32 = 1 << 16;
/// Largest accepted pixel count (2²⁸ ≈ 268 Mpixels: 3 GiB of radiance alone).
pub const MAX_PIXELS: u64 = 1 << 28;

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
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
            spp: 16,
            seed: 0,
            max_depth: 8,
            threads: 0,
            sampling: PixelSampling::Stratified,
            aovs: AovSelection::default(),
            light_units: LightUnits::Radiometric,
            kernel: KernelChoice::Specialised,
            texture_filter: TextureFilter::default(),
        }
    }
}

/// A finished render.
#[derive(Clone, Debug)]
pub struct RenderOutput {
    /// Radiance per pixel, W/(m²·sr), box-filtered over the pixel's samples.
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
    let inputs = RenderInputs {
        scene,
        lights: &scene.lights,
        accel,
        camera,
        pool: None,
    };
    let (film, stats) = render_film(&inputs, settings, 0..settings.spp, progress)?;
    let (image, aovs) = film.resolve();
    Ok(RenderOutput { image, aovs, stats })
}

/// What a render reads besides its settings, for callers that share one scene across many
/// renders ([`partial`], `glint batch`): the lights are passed apart from the scene so that
/// jobs with different lights (default lights follow the camera) need no copy of the scene,
/// and `pool` lets concurrent jobs share one pool instead of each starting its own.
#[derive(Clone, Copy)]
pub struct RenderInputs<'a> {
    /// The scene's geometry, materials and textures (its `lights` are not read).
    pub scene: &'a Scene,
    /// The lights to render with.
    pub lights: &'a [crate::scene::Light],
    /// The scene's ray-query structure, from [`prepare`].
    pub accel: &'a dyn Accel,
    /// The camera.
    pub camera: &'a Camera,
    /// The pool to render on; `None` starts one of [`RenderSettings::threads`] threads.
    pub pool: Option<&'a rayon::ThreadPool>,
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
    let RenderInputs {
        scene,
        lights,
        accel,
        camera,
        pool,
    } = *inputs;
    validate(settings)?;
    if samples.start >= samples.end || samples.end > settings.spp {
        return Err(RenderError::Settings(format!(
            "sample range {}..{} must be non-empty and within 0..{} (the samples per pixel)",
            samples.start, samples.end, settings.spp
        )));
    }
    if accel.triangle_count() != scene.triangle_count() {
        return Err(RenderError::AccelMismatch {
            accel: accel.triangle_count(),
            scene: scene.triangle_count(),
        });
    }
    let camera_rays =
        CameraRays::new(camera, settings.width, settings.height).map_err(|reason| {
            RenderError::Camera {
                name: camera.name.clone(),
                reason,
            }
        })?;
    let features = SceneFeatures::of(scene);
    let flags = KernelFlags::for_scene(&features, settings.kernel);
    // MIP chains are built once per render, only when the kernel reads textures.
    let mipmaps: Vec<MipMap> = if flags.textures {
        scene.textures.par_iter().map(MipMap::new).collect()
    } else {
        Vec::new()
    };
    let texture_bytes = mipmaps.iter().map(|m| m.bytes() as u64).sum();
    let ctx = TileContext {
        scene,
        accel,
        camera: camera_rays,
        sampler: PixelSampler::new(settings.sampling, settings.spp, settings.seed),
        materials: ShadingMaterial::table(scene),
        lights: LightSet::new(lights, settings.light_units)?,
        typed_lights: flags.typed_lights,
        samples: samples.clone(),
        max_depth: settings.max_depth,
        aovs: settings.aovs,
        mipmaps,
        texture_filter: settings.texture_filter,
        differentials: features.textures && settings.texture_filter.uses_footprint(),
        differential_spacing: 1.0 / (settings.spp as f32).sqrt(),
    };
    let render_tile = kernel::select(&flags);
    let own_pool;
    let pool = match pool {
        Some(shared) => shared,
        None => {
            own_pool = thread_pool(settings.threads, accel.kind())?;
            &own_pool
        }
    };

    let tiles = tiles::tiles(settings.width, settings.height, tiles::TILE_SIZE);
    let done = AtomicUsize::new(0);
    let start = Instant::now();
    let results: Vec<_> = pool.install(|| {
        tiles
            .par_iter()
            .map_init(Scratch::default, |scratch, tile| {
                let result = render_tile(&ctx, tile, scratch);
                let finished = done.fetch_add(1, Ordering::Relaxed) + 1;
                if let Some(report) = progress {
                    report(finished, tiles.len());
                }
                result
            })
            .collect()
    });
    let elapsed = start.elapsed();

    let mut film = Film::new(
        settings.width,
        settings.height,
        samples.len() as u32,
        settings.aovs,
    );
    let mut rays = RayCounts::default();
    for (tile, (sums, counts)) in tiles.iter().zip(&results) {
        film.add_tile(tile, sums);
        rays += *counts;
    }
    Ok((
        film,
        RenderStats {
            elapsed,
            rays,
            features,
            kernel: flags,
            texture_bytes,
        },
    ))
}

fn validate(s: &RenderSettings) -> Result<(), RenderError> {
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
    Ok(())
}

/// The pool the tiles run on. With Embree, every worker sets flush-to-zero and
/// denormals-are-zero first, as Embree recommends for threads that trace rays.
pub fn thread_pool(threads: usize, backend: BackendKind) -> Result<rayon::ThreadPool, RenderError> {
    let builder = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("glint-render-{i}"));
    #[cfg(feature = "embree")]
    let builder = builder.start_handler(move |_| {
        if backend == BackendKind::Embree {
            crate::accel::embree::set_denormal_modes();
        }
    });
    #[cfg(not(feature = "embree"))]
    let _ = backend;
    builder.build().map_err(|e| RenderError::Threads {
        threads,
        reason: e.to_string(),
    })
}
