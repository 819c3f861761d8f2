//! Rendering in passes: a fixed sample count, a time budget, or a target error.
//!
//! [`PassRenderer`] holds everything a render needs once (camera rays, material table,
//! lights, the kernel, the thread pool, the film) and adds passes of samples to the film;
//! pass `k` continues the sample sequence where pass `k − 1` stopped, so `n` samples in any
//! number of passes give the same image as `n` samples in one (Sobol and independent
//! sampling; stratified jitter needs the count up front and is refused here).
//!
//! [`render_progressive`] stops on whichever comes first:
//! - the time budget: each pass is sized from the measured time per sample so that it ends
//!   within the budget; rendering stops when not even one more sample fits. The overshoot is
//!   the error of that prediction (a few percent; at worst the first 2-sample pass).
//! - the target error: after each pass the film's estimated relative RMS error (two
//!   half-buffers of independent samples, [`Film::relative_error`]) is compared with it.
//! - the sample cap.
//!
//! Pass sizes at most double the total (2, 2, 4, 8, … samples), so the film is scanned for the
//! error a logarithmic number of times; with a target error, a pass is cut to the samples the
//! target still needs, predicted from error ∝ spp^−½ (+10%), so the last pass does not
//! overshoot the target by a whole doubling.

use super::film::{Film, Image};
use super::filter::FilterSampler;
use super::integrator::{Scratch, TileContext};
use super::kernel::{self, KernelFlags, TileFn};
use super::stats::{RayCounts, RenderStats};
use super::tiles::{self, Tile};
use super::{
    CameraRays, PixelSampler, Progress, RenderError, RenderInputs, RenderOutput, RenderSettings,
    thread_pool, validate,
};
use crate::accel::Accel;
use crate::light::LightSet;
use crate::material::ShadingMaterial;
use crate::scene::{Camera, Scene, SceneFeatures};
use crate::texture::MipMap;
use glam::Vec3;
use rayon::prelude::*;
use std::borrow::Cow;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// A render that accumulates passes of samples into one film.
pub struct PassRenderer<'a> {
    ctx: TileContext<'a>,
    render_tile: TileFn,
    pool: Pool<'a>,
    tiles: Vec<Tile>,
    film: Film,
    rays: RayCounts,
    elapsed: Duration,
    features: SceneFeatures,
    flags: KernelFlags,
    texture_bytes: u64,
}

/// The pool a render runs on: its own, or one shared by concurrent renders (`glint batch`).
enum Pool<'a> {
    Own(rayon::ThreadPool),
    Shared(&'a rayon::ThreadPool),
}

impl Pool<'_> {
    fn get(&self) -> &rayon::ThreadPool {
        match self {
            Pool::Own(pool) => pool,
            Pool::Shared(pool) => pool,
        }
    }
}

impl<'a> PassRenderer<'a> {
    /// Prepares a render of `scene` (ray-query structure `accel`) through `camera`, with the
    /// scene's own lights on a pool of its own. `settings.spp` is not used: each pass says how
    /// many samples it adds.
    pub fn new(
        scene: &'a Scene,
        accel: &'a dyn Accel,
        camera: &'a Camera,
        settings: &RenderSettings,
    ) -> Result<Self, RenderError> {
        Self::with_inputs(&RenderInputs::of_scene(scene, accel, camera), settings)
    }

    /// Prepares a render from [`RenderInputs`]: given lights, and optionally a shared pool.
    pub fn with_inputs(
        inputs: &RenderInputs<'a>,
        settings: &RenderSettings,
    ) -> Result<Self, RenderError> {
        let RenderInputs {
            scene,
            lights,
            accel,
            camera,
            pool,
            mipmaps,
            environment,
        } = *inputs;
        validate(settings)?;
        settings.filter.validate().map_err(RenderError::Settings)?;
        if accel.triangle_count() != scene.triangle_count() {
            return Err(RenderError::AccelMismatch {
                accel: accel.triangle_count(),
                scene: scene.triangle_count(),
            });
        }
        let camera_rays = CameraRays::for_render(camera, settings.width, settings.height)?;
        let features = SceneFeatures::of(scene);
        let flags = KernelFlags::for_scene(&features, settings.kernel);
        // MIP chains only when the kernel reads textures: the caller's, built at load, else
        // this render's own.
        let mipmaps: Cow<'a, [MipMap]> = match (flags.textures, mipmaps) {
            (false, _) => Cow::Borrowed(&[]),
            (true, Some(shared)) => Cow::Borrowed(shared),
            (true, None) => Cow::Owned(super::build_mipmaps(scene)),
        };
        let texture_bytes = mipmaps.iter().map(|m| m.bytes() as u64).sum();
        let area_lights = area_lights(scene);
        // The path kernel runs for the path tracer, and for the direct integrator when the
        // render has lights the classic kernel cannot sample (environment, emitters).
        let path_kernel = settings.integrator == super::Integrator::Path
            || environment.is_some()
            || area_lights.is_some();
        let ctx = TileContext {
            scene,
            accel,
            camera: camera_rays,
            sampler: PixelSampler::new(settings.sampling, settings.spp, settings.seed),
            filter: FilterSampler::new(settings.filter),
            first_sample: 0,
            materials: ShadingMaterial::table(scene),
            lights: LightSet::new(lights, settings.light_units)?,
            typed_lights: flags.typed_lights,
            spp: 0,
            max_depth: settings.max_depth,
            aovs: settings.aovs,
            mipmaps,
            texture_filter: settings.texture_filter,
            differentials: features.textures && settings.texture_filter.uses_footprint(),
            differential_spacing: 1.0 / (settings.spp as f32).sqrt(),
            environment,
            environment_visible: settings.environment_visible,
            area_lights,
            delta_only: settings.integrator == super::Integrator::Direct,
            light_strategy: settings.light_strategy,
            russian_roulette: settings.russian_roulette,
        };
        let pool = match pool {
            Some(shared) => Pool::Shared(shared),
            None => Pool::Own(thread_pool(settings.threads, accel.kind())?),
        };
        Ok(Self {
            ctx,
            render_tile: if path_kernel {
                kernel::select_path(&flags)
            } else {
                kernel::select(&flags)
            },
            pool,
            tiles: tiles::tiles(settings.width, settings.height, tiles::TILE_SIZE),
            film: Film::new(settings.width, settings.height, settings.aovs),
            rays: RayCounts::default(),
            elapsed: Duration::ZERO,
            features,
            flags,
            texture_bytes,
        })
    }

    /// Renders the samples with indices in `samples` (a partial render's range) as one pass.
    pub fn render_samples(
        &mut self,
        samples: std::ops::Range<u32>,
        progress: Option<Progress<'_>>,
    ) {
        self.ctx.first_sample = samples.start;
        self.render_pass(samples.end.saturating_sub(samples.start), progress);
    }

    /// The film and the statistics, unresolved (for partial renders and their merge).
    pub fn into_film(self) -> (Film, RenderStats) {
        let stats = self.stats();
        (self.film, stats)
    }

    fn stats(&self) -> RenderStats {
        RenderStats {
            elapsed: self.elapsed,
            rays: self.rays,
            features: self.features,
            kernel: self.flags,
            texture_bytes: self.texture_bytes,
        }
    }

    /// Adds `spp` samples per pixel (the next `spp` of each pixel's sequence) to the film.
    pub fn render_pass(&mut self, spp: u32, progress: Option<Progress<'_>>) {
        self.ctx.spp = spp;
        let (ctx, render_tile, tiles) = (&self.ctx, self.render_tile, &self.tiles);
        let done = AtomicUsize::new(0);
        let start = Instant::now();
        let results: Vec<_> = self.pool.get().install(|| {
            tiles
                .par_iter()
                .map_init(Scratch::default, |scratch, tile| {
                    let result = render_tile(ctx, tile, scratch);
                    let finished = done.fetch_add(1, Ordering::Relaxed) + 1;
                    if let Some(report) = progress {
                        report(finished, tiles.len());
                    }
                    result
                })
                .collect()
        });
        // Tiles are merged in tile order on this thread: each pixel's sum is the same whatever
        // order the workers finished in.
        for (tile, (sums, counts)) in self.tiles.iter().zip(&results) {
            self.film.add_tile(tile, sums);
            self.rays += *counts;
        }
        self.elapsed += start.elapsed();
        self.ctx.first_sample = self.ctx.first_sample.saturating_add(spp);
    }

    /// Samples per pixel rendered so far.
    pub fn samples_per_pixel(&self) -> u32 {
        self.ctx.first_sample
    }

    /// Render time so far (passes only, not the set-up).
    pub fn elapsed(&self) -> Duration {
        self.elapsed
    }

    /// The film so far.
    pub fn film(&self) -> &Film {
        &self.film
    }

    /// The image so far and the statistics.
    pub fn finish(&self) -> RenderOutput {
        let (image, aovs) = self.film.resolve();
        RenderOutput {
            image,
            aovs,
            stats: self.stats(),
        }
    }
}

/// The scene's emissive triangles as area lights, `None` if nothing emits. A triangle's
/// power uses its material's emissive factor (an emissive texture scales it per point, which
/// changes the sampling density's efficiency, not its correctness).
fn area_lights(scene: &Scene) -> Option<crate::light::area::AreaLights> {
    let emissive = |m: usize| {
        scene
            .meshes
            .get(m)
            .and_then(|mesh| scene.materials.get(mesh.material))
            .map(|mat| (mat.emissive, mat.double_sided))
            .unwrap_or((Vec3::ZERO, false))
    };
    if !scene.meshes.iter().enumerate().any(|(m, _)| emissive(m).0 != Vec3::ZERO) {
        return None;
    }
    let lights =
        crate::light::area::AreaLights::new(scene, |m, _| emissive(m).0, |m| emissive(m).1);
    (!lights.is_empty()).then_some(lights)
}

/// When a progressive render stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StopRule {
    /// Stop before the render time would exceed this.
    pub time_budget: Option<Duration>,
    /// Stop once the estimated relative RMS error is at or below this.
    pub target_error: Option<f64>,
    /// Never render more samples per pixel than this.
    pub max_spp: u32,
}

/// Default sample cap of a progressive render.
pub const DEFAULT_MAX_SPP: u32 = 1 << 16;

impl Default for StopRule {
    fn default() -> Self {
        Self {
            time_budget: None,
            target_error: None,
            max_spp: DEFAULT_MAX_SPP,
        }
    }
}

/// Why a progressive render stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// Another pass would not have fitted in the time budget.
    TimeBudget,
    /// The error estimate reached the target.
    TargetError,
    /// The sample cap was reached.
    MaxSpp,
}

/// A finished progressive render.
#[derive(Clone, Debug)]
pub struct ProgressiveOutput {
    /// The image, AOVs and statistics.
    pub output: RenderOutput,
    /// Per-pixel variance of the image (from the two half-buffers).
    pub variance: Image<Vec3>,
    /// Samples per pixel rendered.
    pub spp: u32,
    /// Passes rendered.
    pub passes: u32,
    /// The final relative RMS error estimate.
    pub relative_error: f64,
    /// Why it stopped.
    pub reason: StopReason,
}

/// Renders passes until `rule` says stop. `settings.spp` is ignored; `settings.sampling` must
/// be progressive (Sobol or independent).
pub fn render_progressive(
    scene: &Scene,
    accel: &dyn Accel,
    camera: &Camera,
    settings: &RenderSettings,
    rule: &StopRule,
    progress: Option<Progress<'_>>,
) -> Result<ProgressiveOutput, RenderError> {
    let inputs = RenderInputs::of_scene(scene, accel, camera);
    render_progressive_with(&inputs, settings, rule, progress)
}

/// [`render_progressive`] from [`RenderInputs`] (given lights, optionally a shared pool).
pub fn render_progressive_with(
    inputs: &RenderInputs<'_>,
    settings: &RenderSettings,
    rule: &StopRule,
    progress: Option<Progress<'_>>,
) -> Result<ProgressiveOutput, RenderError> {
    if !settings.sampling.progressive() {
        return Err(RenderError::Settings(format!(
            "the {} sampler needs the sample count up front; progressive rendering (time \
             budget, target error) needs --sampler sobol or independent",
            settings.sampling
        )));
    }
    if rule.time_budget.is_none() && rule.target_error.is_none() {
        return Err(RenderError::Settings(
            "a progressive render needs a time budget or a target error".into(),
        ));
    }
    if let Some(e) = rule.target_error
        && !(e > 0.0 && e.is_finite())
    {
        return Err(RenderError::Settings(format!(
            "target error {e} must be a positive number (e.g. 0.05 for 5%)"
        )));
    }
    let max_spp = rule.max_spp.max(2);
    let mut renderer = PassRenderer::with_inputs(inputs, settings)?;
    let mut passes = 0;
    // Two samples first: one in each half-buffer, the least the error estimate needs.
    let mut next = 2;
    let reason = loop {
        renderer.render_pass(next, progress);
        passes += 1;
        let spp = renderer.samples_per_pixel();
        // Samples the error target still asks for, from error ∝ spp^−½ (plain Monte Carlo;
        // Sobol converges at least as fast), plus 10% so one pass usually suffices.
        let mut wanted = spp;
        if let Some(target) = rule.target_error {
            let error = renderer.film().relative_error();
            if error <= target {
                break StopReason::TargetError;
            }
            if error.is_finite() {
                let more = spp as f64 * ((error / target).powi(2) * 1.1 - 1.0);
                wanted = wanted.min(more.ceil().clamp(2.0, u32::MAX as f64) as u32);
            }
        }
        if spp >= max_spp {
            break StopReason::MaxSpp;
        }
        // At most double the total, never past the cap and (with a budget) never past what
        // the measured time per sample says still fits.
        let mut pass = wanted.min(max_spp - spp);
        if let Some(budget) = rule.time_budget {
            let per_sample = renderer.elapsed().as_secs_f64() / spp as f64;
            let left = budget.as_secs_f64() - renderer.elapsed().as_secs_f64();
            let fits = (left / per_sample.max(1e-12)).floor();
            if fits < 1.0 {
                break StopReason::TimeBudget;
            }
            pass = pass.min(fits.min(u32::MAX as f64) as u32);
        }
        // Keep passes even so each half-buffer gets the same number of samples.
        next = if pass >= 2 { pass & !1 } else { pass };
    };
    let output = renderer.finish();
    Ok(ProgressiveOutput {
        variance: renderer.film().variance(),
        relative_error: renderer.film().relative_error(),
        spp: renderer.samples_per_pixel(),
        passes,
        reason,
        output,
    })
}
