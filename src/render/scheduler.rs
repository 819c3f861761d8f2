//! The tile scheduler every render goes through: it holds what a render needs once (camera
//! rays, material table, lights, the selected kernel, the thread pool, the film), splits each
//! pass of samples into [`tiles`](super::tiles) rendered in parallel, and adds their sums to
//! the film in tile order, so the image does not depend on which worker finished first.
//! [`super::render_film`] runs one pass; [`super::progressive`] runs many.

use super::film::{Film, TileSums};
use super::filter::FilterSampler;
use super::ids;
use super::kernel::KernelFlags;
use super::path::PathScratch;
use super::stats::{RayCounts, RenderStats};
use super::tiles::{self, Tile};
use super::wavefront::{Pass, TileContext, Transport};
use super::{
    CameraRays, PixelSampler, Progress, RenderError, RenderInputs, RenderOutput, RenderSettings,
    thread_pool, validate,
};
use crate::accel::Accel;
use crate::light::{LightSampler, LightSet};
use crate::material::ShadingMaterial;
use crate::scene::{Camera, Scene, SceneFeatures};
use crate::texture::MipMap;
use rayon::prelude::*;
use std::borrow::Cow;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Renders passes of samples tile by tile on a thread pool and accumulates them in one film.
pub struct TileScheduler<'a> {
    ctx: TileContext<'a>,
    pool: Pool<'a>,
    tiles: Vec<Tile>,
    /// Samples per pixel rendered so far: the next pass starts at this index.
    next_sample: u32,
    film: Film,
    rays: RayCounts,
    elapsed: Duration,
    features: SceneFeatures,
    flags: KernelFlags,
    texture_bytes: u64,
    texture_texels: u64,
    /// The metallic-roughness model the materials use (reported in the summary).
    brdf: super::BrdfModel,
    /// The caller's stop flag ([`RenderInputs::cancel`]).
    cancel: Option<&'a AtomicBool>,
    /// Whether the centre-ray ID AOVs still have to be traced (by the next pass).
    ids_pending: bool,
    /// Adaptive sampling's per-pixel state, when it is on.
    adaptive: Option<super::adaptive::Adaptive>,
    /// Path guiding's training, while it lasts.
    training: Option<Training>,
}

/// Path guiding's training state ([`super::guided`]): the trainer, the sample totals at which
/// the guide is relearned, and the records gathered since the last one.
struct Training {
    trainer: crate::guiding::Trainer,
    /// Sample totals, ascending: once a pass ends at or past the first, the guide is learned
    /// from the records since the previous one.
    ends: Vec<u32>,
    /// Per tile of each pass since the last learning, in tile order.
    records: Vec<Vec<crate::guiding::Record>>,
}

impl Training {
    /// Training over the bounds of `scene`, relearning at the totals of `passes`.
    fn new(scene: &Scene, passes: &[u32]) -> Self {
        let (lo, hi) = scene
            .bounds()
            .unwrap_or((glam::Vec3::splat(-1.0), glam::Vec3::splat(1.0)));
        let ends: Vec<u32> = passes
            .iter()
            .scan(0u32, |total, &p| {
                *total += p;
                Some(*total)
            })
            .collect();
        Self {
            trainer: crate::guiding::Trainer::new(lo, hi),
            ends,
            records: Vec::new(),
        }
    }
}

/// The environment distribution a render's light samples come from: compensated (MIS
/// compensation, Karlík et al. 2019) where the path tracer combines light and BSDF sampling by
/// MIS at every vertex that takes a light sample, so BSDF sampling covers the directions the
/// compensated distribution leaves out; the full one for light sampling alone and the direct
/// integrator (whose non-delta lobes are never BSDF-sampled).
fn env_sampling(settings: &RenderSettings) -> crate::light::environment::EnvSampling {
    use crate::light::environment::EnvSampling;
    let mis = settings.integrator == super::Integrator::Path
        && settings.light_strategy == super::LightStrategy::Mis;
    if mis && settings.mis_compensation {
        EnvSampling::Compensated
    } else {
        EnvSampling::Full
    }
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

impl<'a> TileScheduler<'a> {
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
            area_lights,
            cancel,
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
        let texture_texels = mipmaps.iter().map(|m| m.base_texels() as u64).sum();
        let area_lights: Option<Cow<'a, crate::light::area::AreaLights>> = match area_lights {
            Some(shared) => Some(Cow::Borrowed(shared)),
            None => Some(Cow::Owned(super::build_area_lights(
                scene,
                Some(&mipmaps).filter(|m| !m.is_empty()).map(|m| &**m),
            )?)),
        }
        .filter(|lights| !lights.is_empty());
        let visibility = super::visibility::Visibility::new(
            scene,
            flags.alpha,
            flags.cull_back_faces,
            settings.seed,
        );
        let flags = KernelFlags {
            area_lights: area_lights.is_some(),
            environment: environment.is_some(),
            alpha: visibility.as_ref().is_some_and(|v| v.tests_alpha()),
            cull_back_faces: visibility.as_ref().is_some_and(|v| v.culls()),
            ..flags
        };
        // BSDF sampling alone (a test of the estimators) leaves emitters and the environment
        // to the rays that hit them; the direct integrator always light-samples them.
        let samples_surfaces = settings.integrator == super::Integrator::Direct
            || settings.light_strategy != super::LightStrategy::BsdfOnly;
        let ctx = TileContext {
            scene,
            accel,
            camera: camera_rays,
            sampler: PixelSampler::new(settings.sampling, settings.spp, settings.seed),
            filter: FilterSampler::new(settings.filter),
            materials: ShadingMaterial::table(scene, settings.brdf),
            lights: LightSampler::new(
                &LightSet::new(lights, settings.light_units)?,
                area_lights.filter(|_| samples_surfaces),
                environment.filter(|_| samples_surfaces),
            )
            .with_env_sampling(env_sampling(settings)),
            aovs: settings.aovs,
            mipmaps,
            texture_filter: settings.texture_filter,
            differentials: features.textures && settings.texture_filter.uses_footprint(),
            differential_spacing: 1.0 / (settings.spp as f32).sqrt(),
            environment,
            visibility,
            guiding: super::guided::Guiding::default(),
            transport: Transport {
                integrator: settings.integrator,
                max_depth: settings.max_depth,
                max_transmission_depth: settings.max_transmission_depth,
                light_strategy: settings.light_strategy,
                russian_roulette: settings.russian_roulette,
                environment_visible: settings.environment_visible,
                clamp_indirect: settings.clamp_indirect,
            },
        };
        let pool = match pool {
            Some(shared) => Pool::Shared(shared),
            None => Pool::Own(thread_pool(settings.threads, accel.kind())?),
        };
        Ok(Self {
            ctx,
            pool,
            tiles: tiles::tiles(settings.width, settings.height, tiles::TILE_SIZE),
            next_sample: 0,
            film: Film::new(settings.width, settings.height, settings.aovs),
            rays: RayCounts::default(),
            elapsed: Duration::ZERO,
            features,
            flags,
            texture_bytes,
            texture_texels,
            brdf: settings.brdf,
            cancel,
            ids_pending: settings.aovs.instance_id
                || settings.aovs.material_id
                || settings.aovs.any_geometric(),
            training: if settings.guiding && settings.integrator == super::Integrator::Path {
                Some(Training::new(
                    scene,
                    &super::guided::training_passes(settings.spp),
                ))
            } else {
                None
            },
            adaptive: settings.adaptive.map(|threshold| {
                super::adaptive::Adaptive::new(
                    settings.width,
                    settings.height,
                    threshold,
                    settings.seed,
                )
            }),
        })
    }

    /// Renders the samples with indices in `samples` (a partial render's range) as one pass.
    pub fn render_samples(
        &mut self,
        samples: std::ops::Range<u32>,
        progress: Option<Progress<'_>>,
    ) {
        self.next_sample = samples.start;
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
            texture_texels: self.texture_texels,
            brdf: self.brdf,
        }
    }

    /// Adds `spp` samples per pixel (the next `spp` of each pixel's sequence) to the film.
    pub fn render_pass(&mut self, spp: u32, progress: Option<Progress<'_>>) {
        let width = self.film.size().0;
        let pass = Pass {
            first_sample: self.next_sample,
            spp,
            active: self.adaptive.as_ref().map(|a| (a.active(), width)),
        };
        if self.cancelled() {
            return;
        }
        let trains = self.training.as_ref().is_some_and(|t| !t.ends.is_empty());
        self.ctx.guiding.record_stride = trains.then(|| {
            let (w, h) = self.film.size();
            let paths = u64::from(w) * u64::from(h) * u64::from(spp);
            paths.div_ceil(super::guided::MAX_TRAINING_PATHS).max(1)
        });
        let (ctx, tiles) = (&self.ctx, &self.tiles);
        let (cancel, trace_ids) = (self.cancel, self.ids_pending);
        let done = AtomicUsize::new(0);
        let start = Instant::now();
        let results: Vec<_> = self.pool.get().install(|| {
            tiles
                .par_iter()
                .map_init(PathScratch::default, |scratch, tile| {
                    if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                        // The render is abandoned: its film is never returned.
                        return (TileSums::default(), RayCounts::default(), Vec::new());
                    }
                    let mut records = Vec::new();
                    let (sums, counts) =
                        super::path::render_tile(ctx, pass, tile, scratch, &mut records);
                    let mut result = (sums, counts, records);
                    if trace_ids {
                        let (sums, counts, _) = &mut result;
                        ids::trace_centre_ids(ctx, ctx.aovs, tile, sums, counts);
                        if ctx.aovs.any_geometric() {
                            super::ground_truth::trace_centre_hits(ctx, tile, sums, counts);
                        }
                    }
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
        let mut records = Vec::new();
        for (tile, (sums, counts, tile_records)) in self.tiles.iter().zip(results) {
            self.film.add_tile(tile, &sums);
            self.rays += counts;
            if trains {
                records.push(tile_records);
            }
        }
        if let Some(adaptive) = &mut self.adaptive {
            adaptive.record_pass(spp);
        }
        self.elapsed += start.elapsed();
        self.next_sample = self.next_sample.saturating_add(spp);
        self.ids_pending = false;
        if let Some(training) = &mut self.training {
            training.records.extend(records);
            // Relearn once the pass reached the next total of the training schedule.
            if training
                .ends
                .first()
                .is_some_and(|&e| self.next_sample >= e)
            {
                let guide = training.trainer.learn(training.records.iter().flatten());
                self.ctx.guiding.guide = Some(guide);
                training.records.clear();
                training.ends.retain(|&e| e > self.next_sample);
            }
            if training.ends.is_empty() {
                self.training = None;
                self.ctx.guiding.record_stride = None;
            }
        }
    }

    /// Path guiding in a progressive render: relearn the guide after 2, 4, 8 and
    /// [`super::guided::PROGRESSIVE_TRAINING_SPP`] samples per pixel (whatever its passes),
    /// then freeze it. Does nothing without guiding.
    pub fn train_progressively(&mut self) {
        if let Some(training) = &mut self.training {
            training.ends = std::iter::successors(Some(2u32), |&n| Some(n * 2))
                .take_while(|&n| n <= super::guided::PROGRESSIVE_TRAINING_SPP)
                .collect();
            training.records.clear();
        }
    }

    /// Whether the caller has asked the render to stop ([`RenderInputs::cancel`]).
    pub fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }

    /// Samples per pixel rendered so far.
    pub fn samples_per_pixel(&self) -> u32 {
        self.next_sample
    }

    /// Render time so far (passes only, not the set-up).
    pub fn elapsed(&self) -> Duration {
        self.elapsed
    }

    /// The film so far.
    pub fn film(&self) -> &Film {
        &self.film
    }

    /// Adaptive sampling (when on): decides, from the film so far, which pixels stop taking
    /// samples ([`super::adaptive::Adaptive::decide`]). Call between passes.
    /// Does nothing before [`super::adaptive::MIN_SAMPLES`] samples per pixel.
    pub fn adapt(&mut self) {
        if self.next_sample < super::adaptive::MIN_SAMPLES {
            return;
        }
        if let Some(adaptive) = &mut self.adaptive {
            adaptive.decide(&self.film);
        }
    }

    /// Fraction of pixels still taking samples (1 without adaptive sampling).
    pub fn active_fraction(&self) -> f64 {
        self.adaptive
            .as_ref()
            .map_or(1.0, super::adaptive::Adaptive::active_fraction)
    }

    /// The image so far and the statistics; with adaptive sampling, each pixel's unbiased
    /// estimate ([`super::adaptive::Adaptive::resolve`]) and the samples it took
    /// ([`super::Aovs::samples`]).
    pub fn finish(&self) -> RenderOutput {
        let (mut image, mut aovs) = self.film.resolve();
        if let Some(adaptive) = &self.adaptive {
            image = adaptive.resolve(image);
            aovs.samples = Some(adaptive.sample_counts());
        }
        RenderOutput {
            image,
            aovs,
            stats: self.stats(),
        }
    }
}
