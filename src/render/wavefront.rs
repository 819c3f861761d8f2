//! The wavefront skeleton every integrator runs on, free of any one integrator's state: what
//! a tile render reads ([`TileContext`]), the samples a pass adds ([`Pass`]), camera samples,
//! batched tracing of path rays (camera rays coherently, Embree packets) with the visibility
//! rules applied, batched shadow rays, and the first-hit AOVs.
//!
//! An integrator loops, per sample index: generate the tile's camera rays
//! ([`camera_sample`]), then per round trace the batch ([`trace_batch`]), shade each hit
//! (queueing light samples and continuation rays) and trace the round's shadow rays
//! ([`trace_shadows`]). Its buffers are its own (`path::PathScratch`).

use super::camera::CameraRays;
use super::film::{AovSelection, TileSums};
use super::filter::FilterSampler;
use super::sampler::PixelSampler;
use super::stats::RayCounts;
use super::visibility::{RayBatch, RayKind, Visibility};
use super::{Integrator, LightStrategy};
use crate::accel::{Accel, Coherence, Hit, Ray};
use crate::light::LightSampler;
use crate::light::environment::EnvironmentLight;
use crate::material::ShadingMaterial;
use crate::scene::Scene;
use crate::texture::{MipMap, RayDifferential, TextureEvaluator, TextureFilter};
use glam::{Vec2, Vec3};
use std::borrow::Cow;

/// Everything a tile render reads; shared by all workers, the same for every pass.
pub(crate) struct TileContext<'a> {
    /// Geometry, materials and textures.
    pub scene: &'a Scene,
    /// The scene's ray queries.
    pub accel: &'a dyn Accel,
    /// Camera rays for the image.
    pub camera: CameraRays,
    /// Where samples go inside a pixel.
    pub sampler: PixelSampler,
    /// Turns the sampler's point into a film offset and a filter weight.
    pub filter: FilterSampler,
    /// The AOVs the film sums.
    pub aovs: AovSelection,
    /// The scene's materials prepared for shading, plus the default material at the end.
    pub materials: Vec<ShadingMaterial>,
    /// MIP chains of `scene.textures`, index-aligned (empty when nothing is textured).
    pub mipmaps: Cow<'a, [MipMap]>,
    /// How textures are filtered.
    pub texture_filter: TextureFilter,
    /// Whether camera rays carry differentials: the scene has textures and the filter reads
    /// footprints.
    pub differentials: bool,
    /// Film distance between neighbouring samples, 1/√spp pixels.
    pub differential_spacing: f32,
    /// Alpha tests and camera back-face culling (`None`: every hit counts).
    pub visibility: Option<Visibility>,
    /// The one light sampler.
    pub lights: LightSampler<'a>,
    /// The environment seen by rays that escape (light-sampled or not).
    pub environment: Option<&'a EnvironmentLight>,
    /// Path guiding (`--guiding`): the guide of this pass and whether it trains.
    pub guiding: super::guided::Guiding,
    /// The integrator's settings.
    pub transport: Transport,
}

/// What the light-transport estimator does, from the render settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Transport {
    /// Direct light only (continue through specular lobes only) or full path tracing.
    pub integrator: Integrator,
    /// Vertices lit and continued: see `path`'s module doc.
    pub max_depth: u32,
    /// Transmission bounces allowed besides `max_depth` (see `path`'s module doc).
    pub max_transmission_depth: u32,
    /// Light or BSDF sampling or both.
    pub light_strategy: LightStrategy,
    /// Russian roulette on.
    pub russian_roulette: bool,
    /// Whether camera rays that miss show the environment.
    pub environment_visible: bool,
    /// `--clamp-indirect` (biased): the largest channel an indirect contribution may add,
    /// per unit filter weight.
    pub clamp_indirect: Option<f32>,
}

impl Transport {
    /// Whether this is the direct integrator (specular chains plus light sampling).
    #[inline]
    pub fn direct_only(&self) -> bool {
        self.integrator == Integrator::Direct
    }
}

impl TileContext<'_> {
    /// The texture evaluator of this render.
    #[inline]
    pub fn textures(&self) -> TextureEvaluator<'_> {
        TextureEvaluator {
            textures: &self.scene.textures,
            mipmaps: &self.mipmaps,
            filter: self.texture_filter,
        }
    }

    /// The rays through the exact centres of `tile`'s pixels and their first hits, before any
    /// visibility rule: the point samples of the ID and ground-truth AOVs.
    pub(super) fn trace_pixel_centres(
        &self,
        tile: &super::tiles::Tile,
    ) -> (Vec<Ray>, Vec<Option<Hit>>) {
        let rays: Vec<Ray> = (0..tile.pixel_count())
            .map(|local| {
                let (x, y) = tile.pixel(local);
                self.camera.ray(x as f32 + 0.5, y as f32 + 0.5)
            })
            .collect();
        let mut hits = vec![None; rays.len()];
        self.accel
            .intersect_many(&rays, &mut hits, Coherence::Coherent);
        (rays, hits)
    }
}

/// The samples one pass adds: indices `first_sample .. first_sample + spp` of every pixel's
/// sequence. Passed to each tile apart from the [`TileContext`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Pass<'a> {
    /// First sample index of the pass.
    pub first_sample: u32,
    /// Samples per pixel in the pass.
    pub spp: u32,
    /// Adaptive sampling: which pixels take samples (row-major over the image, `width`
    /// pixels a row); `None`: all.
    pub active: Option<(&'a [bool], u32)>,
}

impl Pass<'_> {
    /// Whether pixel `(x, y)` takes this pass's samples.
    #[inline]
    pub fn samples_pixel(&self, x: u32, y: u32) -> bool {
        self.active.is_none_or(|(active, width)| {
            active
                .get(y as usize * width as usize + x as usize)
                .copied()
                .unwrap_or(true)
        })
    }
}

/// The camera ray of sample `sample` of pixel `(x, y)`, its filter weight and its position on
/// the film (for its differential, [`camera_differential`], built only where a textured
/// material needs it). Offsets are from the pixel centre and may leave the pixel (wide
/// filters).
#[inline]
pub(crate) fn camera_sample(
    ctx: &TileContext<'_>,
    x: u32,
    y: u32,
    sample: u32,
) -> (Ray, f32, Vec2) {
    let (offset, weight) = ctx.filter.sample(ctx.sampler.offset(x, y, sample));
    let film = Vec2::new(x as f32 + 0.5 + offset.x, y as f32 + 0.5 + offset.y);
    (ctx.camera.ray(film.x, film.y), weight, film)
}

/// The differential of the camera ray through film position `film` (neighbours one sample
/// spacing away).
#[inline]
pub(crate) fn camera_differential(ctx: &TileContext<'_>, film: Vec2) -> RayDifferential {
    ctx.camera
        .ray_differential(film.x, film.y, ctx.differential_spacing)
}

/// Traces one batch of path rays: camera rays (`primary`) coherently, later rays
/// incoherently, counted by kind; hits the visibility rules reject are replaced by the next
/// accepted one. Returns the coherence used, for the batch's shadow rays.
#[inline]
pub(crate) fn trace_batch(
    ctx: &TileContext<'_>,
    rays: &[Ray],
    hits: &mut Vec<Option<Hit>>,
    primary: bool,
    batch: RayBatch,
    counts: &mut RayCounts,
) -> Coherence {
    let coherence = if primary {
        Coherence::Coherent
    } else {
        Coherence::Incoherent
    };
    hits.clear();
    hits.resize(rays.len(), None);
    ctx.accel.intersect_many(rays, hits, coherence);
    if let Some(visibility) = &ctx.visibility {
        let kind = if primary {
            RayKind::Camera
        } else {
            RayKind::Bounce
        };
        visibility.resolve_hits(ctx, rays, hits, kind, batch, counts);
    }
    if primary {
        counts.camera += rays.len() as u64;
    } else {
        counts.reflection += rays.len() as u64;
    }
    coherence
}

/// Shadow rays queued by one round: each ray with the pixel and value it adds if unblocked.
#[derive(Default)]
pub(crate) struct ShadowQueue {
    rays: Vec<Ray>,
    values: Vec<(u32, Vec3)>,
    /// Per ray, the last logged vertex of its path (`render::guided`, training only).
    records: Vec<u32>,
    occluded: Vec<bool>,
}

impl ShadowQueue {
    /// Empties the queue for the next round.
    #[inline]
    pub fn clear(&mut self) {
        self.rays.clear();
        self.values.clear();
        self.records.clear();
    }

    /// Queues `ray`, which adds `value` to `pixel` if nothing blocks it; `record` is its
    /// path's last logged vertex for training the guide (`render::guided::NO_RECORD`: none).
    #[inline]
    pub fn push(&mut self, ray: Ray, pixel: u32, record: u32, value: Vec3) {
        self.rays.push(ray);
        self.values.push((pixel, value));
        self.records.push(record);
    }

    /// After [`ShadowQueue::trace`]: each unblocked ray's path record and value.
    pub fn for_each_unblocked(&self, mut f: impl FnMut(u32, Vec3)) {
        for ((&(_, value), &blocked), &record) in
            self.values.iter().zip(&self.occluded).zip(&self.records)
        {
            if !blocked {
                f(record, value);
            }
        }
    }

    /// Traces the queued rays (with the coherence and identity of the path batch they light)
    /// and adds the value of each unblocked one to its pixel; alpha-rejected blockers do not
    /// block.
    #[inline]
    pub fn trace(
        &mut self,
        ctx: &TileContext<'_>,
        (coherence, batch): (Coherence, RayBatch),
        counts: &mut RayCounts,
        sums: &mut TileSums,
    ) {
        if self.rays.is_empty() {
            return;
        }
        self.occluded.clear();
        self.occluded.resize(self.rays.len(), true);
        ctx.accel
            .occluded_many(&self.rays, &mut self.occluded, coherence);
        if let Some(visibility) = &ctx.visibility {
            visibility.resolve_occlusion(ctx, &self.rays, &mut self.occluded, batch, counts);
        }
        counts.shadow += self.rays.len() as u64;
        for (&(pixel, value), &blocked) in self.values.iter().zip(self.occluded.iter()) {
            if !blocked {
                sums.pending[pixel as usize] += value;
            }
        }
    }
}

/// Adds a camera ray's first hit to the AOV sums it has (weighted by the sample's filter
/// weight `w`): albedo, shading normal, and distance (camera ray directions are unit, so `t`
/// is the distance).
#[inline]
pub(crate) fn record_first_hit(
    sums: &mut TileSums,
    pixel: usize,
    w: f32,
    albedo: Vec3,
    ns: Vec3,
    t: f32,
) {
    if let Some(a) = sums.albedo.get_mut(pixel) {
        *a += w * albedo;
    }
    if let Some(n) = sums.normal.get_mut(pixel) {
        *n += w * ns;
    }
    if let Some(d) = sums.depth.get_mut(pixel) {
        *d += w * t;
    }
    if let Some(a) = sums.alpha.get_mut(pixel) {
        *a += w;
    }
}
