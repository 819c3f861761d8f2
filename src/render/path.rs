//! The path tracer: the rendering equation `L_o = L_e + ∫ L_i f |cos θ| dω`, estimated by
//! unidirectional paths with next-event estimation and multiple importance sampling.
//!
//! It runs one tile at a time on the wavefront skeleton (`render::wavefront`): for each sample
//! index the tile's camera rays are traced as one coherent batch, then every live path is
//! extended by one vertex per round: its hit goes through the surface front end
//! ([`crate::material::at_hit`](fn@crate::material::at_hit)), its light sample (one per vertex, from the one
//! [`LightSampler`](crate::light::LightSampler)) joins one occlusion batch, and its BSDF
//! sample becomes the next (incoherent) batch of rays.
//!
//! The direct integrator is this kernel with `Integrator::Direct`: the same BSDF, light
//! sampling at every vertex, but the continuation follows specular (delta) lobes only, and
//! light found by those continuations counts with weight 1 (no MIS: non-delta lobes are never
//! BSDF-sampled). So direct light is exact in expectation and specular chains are followed up
//! to `max_depth` reflections.
//!
//! At a vertex with throughput β, outgoing direction ωo and BSDF f:
//! - **Emission** `β · Le · w`: `w = 1` for camera rays and after a delta lobe, otherwise the
//!   power-heuristic weight of the BSDF sample against the light sampler's density for the
//!   point it hit (area lights, the environment when the ray escapes).
//! - **Light sampling** (next-event estimation), while the depth is below `max_depth` and the
//!   BSDF has a lobe with a density: the few delta lights each, then one finite and one
//!   infinite light chosen by the light sampler, one shadow ray per sample,
//!   `β · f(ωo, ωi) · |cos θi| · L · w / p_light`, with `p_light` the selection probability
//!   (times the solid-angle density for area and environment samples) and `w` the power
//!   heuristic of `p_light` against the BSDF's density `p_bsdf(ωi)` (1 for delta lights).
//! - **BSDF sampling**: `β ← β · f · |cos θi| / p_bsdf`. Delta lobes (mirrors) carry no
//!   density; the ray they spawn counts the emitter it hits with weight 1.
//! - **Russian roulette** from [`RR_START_DEPTH`] on: the path survives with probability
//!   `q = min(1, max_c |β_c| / |w_filter|)` and is divided by `q`, which leaves the expected
//!   value unchanged (unbiased).
//!
//! `max_depth` counts bounces as pbrt-v4 does: vertices at depths `0..max_depth` (0 = the
//! camera ray's hit) are lit by light sampling and spawn a BSDF ray; the vertex at
//! `max_depth` only adds what it emits (the MIS partner of the last light sample). So
//! `max_depth = 1` is direct light only, 0 emission only.
//!
//! Transmission bounces are counted apart, against `max_transmission_depth` (Cycles counts
//! them apart too, but also within its total, which glint does not): a refraction, or a
//! reflection off the inside of a surface that transmits (light bouncing inside glass), does
//! not spend `max_depth`. A smooth glass sphere's rim traps paths in
//! many internal reflections near the critical angle; counted in `max_depth` they made its
//! rim read 0.976 in a white furnace at depth 32.
//!
//! A light sample or a BSDF sample below the geometric horizon of the surface (the side the
//! ray arrived from) is dropped: shading normals never let light through the surface.

use super::LightStrategy;
use super::film::TileSums;
use super::guided::{NO_RECORD, TrainingLog};
use super::medium::Medium;
use super::sampler::SampleStream;
use super::stats::RayCounts;
use super::tiles::Tile;
use super::visibility::RayBatch;
use super::wavefront::{
    Pass, ShadowQueue, TileContext, camera_differential, camera_sample, record_first_hit,
    trace_batch,
};
use crate::accel::{Hit, Ray};
use crate::bsdf::{Bsdf, BsdfFlags, Frame};
use crate::geometry::{SurfaceInteraction, spawn_ray, spawn_ray_to};
use crate::guiding::{Directional, Record};
use crate::light::area::AreaSample;
use crate::light::{LightSample, NoLightSample, ShadowTarget, Unlit};
use crate::material::{
    HitQuery, ShadingMaterial, SurfaceAtHit, SurfaceBsdf, at_hit, emitted, material_index,
};
use crate::texture::TexturePoint;
use glam::{Vec2, Vec3};

/// Depth (bounces) from which Russian roulette may end a path.
pub const RR_START_DEPTH: u32 = 3;

/// A path waiting for its ray's hit.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PathState {
    pixel: u32,
    /// Throughput, including the sample's filter weight.
    beta: Vec3,
    /// The sample's filter weight.
    filter_weight: f32,
    /// The path's random numbers.
    stream: SampleStream,
    /// Solid-angle density of the BSDF sample that produced this ray (unused when
    /// `specular`).
    pdf: f32,
    /// The ray is a camera ray or left a delta lobe: whatever it hits counts with weight 1.
    specular: bool,
    /// Where the ray left and the shading normal there (for the light density of the
    /// emitter it hits, which depends on both with the light BVH).
    origin: Vec3,
    origin_normal: Vec3,
    /// The medium the ray travels in (KHR_materials_volume; outside for every other scene).
    medium: Medium,
    /// Whether the path logs its vertices for training the guide (`render::guided`).
    trains: bool,
    /// Its last logged vertex, or [`NO_RECORD`].
    record: u32,
    /// Transmission bounces so far (they do not count against `max_depth`).
    transmissions: u32,
}

/// Buffers of the path tracer, reused across tiles.
#[derive(Default)]
pub(crate) struct PathScratch {
    rays: Vec<Ray>,
    paths: Vec<PathState>,
    hits: Vec<Option<Hit>>,
    next_rays: Vec<Ray>,
    next_paths: Vec<PathState>,
    shadows: ShadowQueue,
    weights: Vec<f32>,
    /// Film positions of the camera rays, index-aligned with the first round's `rays` (for
    /// their differentials; only when the render carries them).
    film: Vec<Vec2>,
    /// Training paths' logged vertices (`--guiding`, training passes only).
    log: TrainingLog,
}

/// The power heuristic (β = 2) weight of a sample drawn with density `a` against another
/// strategy of density `b`.
#[inline]
pub fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2.is_infinite() {
        return 1.0;
    }
    if a2 + b2 > 0.0 { a2 / (a2 + b2) } else { 0.0 }
}

/// Renders one tile with the path tracer (or the direct integrator, see the module doc). While
/// the pass trains the guide, training paths' records are appended to `records`.
pub(crate) fn render_tile(
    ctx: &TileContext<'_>,
    pass: Pass<'_>,
    tile: &Tile,
    s: &mut PathScratch,
    records: &mut Vec<Record>,
) -> (TileSums, RayCounts) {
    let mut sums = TileSums::new(tile.pixel_count(), ctx.aovs);
    let mut counts = RayCounts::default();
    // Camera rays carry differentials for their first hit's texture footprint (scenes with
    // textures and a filter that reads footprints); bounce rays look textures up at the
    // finest level.
    let carry = ctx.differentials;
    for sample in pass.first_sample..pass.first_sample.saturating_add(pass.spp) {
        s.rays.clear();
        s.paths.clear();
        s.weights.clear();
        s.film.clear();
        for local in 0..tile.pixel_count() {
            let (x, y) = tile.pixel(local);
            if !pass.samples_pixel(x, y) {
                // Stopped by adaptive sampling: no ray, no weight.
                s.weights.push(0.0);
                continue;
            }
            let (ray, weight, film) = camera_sample(ctx, x, y, sample);
            if carry {
                s.film.push(film);
            }
            s.rays.push(ray);
            s.weights.push(weight);
            s.paths.push(PathState {
                pixel: local as u32,
                beta: Vec3::splat(weight),
                filter_weight: weight,
                stream: ctx.sampler.stream(x, y, sample),
                pdf: 0.0,
                specular: true,
                origin: ray.origin,
                origin_normal: Vec3::ZERO,
                medium: Medium::OUTSIDE,
                trains: ctx
                    .guiding
                    .records(u64::from(y) << 32 | u64::from(x), sample),
                record: NO_RECORD,
                transmissions: 0,
            });
        }
        let mut depth = 0;
        while !s.rays.is_empty() {
            let primary = depth == 0;
            let batch = RayBatch::new(tile, sample, depth);
            let coherence = trace_batch(ctx, &s.rays, &mut s.hits, primary, batch, &mut counts);
            if primary {
                let pixels = s.paths.iter().map(|p| p.pixel as usize);
                super::ids::record_coverage(ctx, &mut sums, &s.hits, pixels.clone());
                super::amodal::record_amodal(ctx, &mut sums, &s.rays, &s.hits, pixels, batch);
            }
            s.next_rays.clear();
            s.next_paths.clear();
            s.shadows.clear();
            for i in 0..s.rays.len() {
                let (ray, path) = (s.rays[i], s.paths[i]);
                let Some(hit) = s.hits[i] else {
                    escaped(ctx, &ray, &path, depth, &mut sums, &mut s.log);
                    continue;
                };
                let film = if carry && primary {
                    s.film.get(i).copied()
                } else {
                    None
                };
                let mut vertex = Vertex {
                    ray: &ray,
                    hit: &hit,
                    path,
                    depth,
                    film,
                };
                shade(
                    ctx,
                    &mut vertex,
                    &mut sums,
                    &mut Queues {
                        next_rays: &mut s.next_rays,
                        next_paths: &mut s.next_paths,
                        shadows: &mut s.shadows,
                        counts: &mut counts,
                        log: &mut s.log,
                    },
                );
            }
            s.shadows
                .trace(ctx, (coherence, batch), &mut counts, &mut sums);
            if ctx.guiding.record_stride.is_some() {
                s.shadows
                    .for_each_unblocked(|record, value| s.log.credit(record, value));
            }
            std::mem::swap(&mut s.rays, &mut s.next_rays);
            std::mem::swap(&mut s.paths, &mut s.next_paths);
            depth += 1;
        }
        sums.end_sample(sample, &s.weights);
        s.log.drain_into(records);
    }
    (sums, counts)
}

/// A ray that left the scene: the environment's radiance, weighted against environment
/// sampling unless the ray is a camera ray (shown only when the environment is visible) or
/// left a delta lobe.
#[inline]
fn escaped(
    ctx: &TileContext<'_>,
    ray: &Ray,
    path: &PathState,
    depth: u32,
    sums: &mut TileSums,
    log: &mut TrainingLog,
) {
    let Some(env) = ctx.environment else {
        return;
    };
    let primary = depth == 0;
    if primary && !ctx.transport.environment_visible {
        return;
    }
    // An infinite segment inside an absorbing volume (an open mesh) transmits nothing.
    let beta = path.beta * path.medium.transmittance(f32::INFINITY);
    let dir = ray.dir.normalize_or_zero();
    // The environment's density only where MIS weighs the escape; one image lookup for both.
    let weighs = !path.specular
        && !ctx.transport.direct_only()
        && ctx.transport.light_strategy == LightStrategy::Mis;
    let (le, env_pdf) = if weighs {
        env.radiance_and_pdf_with(dir, ctx.lights.env_sampling())
    } else {
        (env.radiance(dir), 0.0)
    };
    if le == Vec3::ZERO {
        return;
    }
    let w = bsdf_hit_weight(ctx, path, || ctx.lights.environment_pdf_of(env_pdf));
    let value = clamped(
        ctx,
        beta * le * w,
        path.filter_weight,
        depth >= INDIRECT_DEPTH,
    );
    sums.pending[path.pixel as usize] += value;
    log.credit(path.record, value);
}

/// Depth of the ray (or, for a light sample, of the vertex plus one) from which light counts
/// as indirect for `--clamp-indirect`: light that reached the camera through at least two
/// bounces. Direct light (emitters seen, and light reflected once) is never clamped.
const INDIRECT_DEPTH: u32 = 2;

/// `--clamp-indirect X` (biased, off by default): an indirect contribution `value` of a sample
/// of filter weight `filter_weight`, scaled down so that its largest channel per unit filter
/// weight is at most X. Unchanged when the option is off or the light is direct.
#[inline(always)]
fn clamped(ctx: &TileContext<'_>, value: Vec3, filter_weight: f32, indirect: bool) -> Vec3 {
    match ctx.transport.clamp_indirect {
        Some(limit) if indirect => {
            let largest = value.abs().max_element();
            let cap = limit * filter_weight.abs();
            if largest > cap {
                value * (cap / largest)
            } else {
                value
            }
        }
        _ => value,
    }
}

/// The weight of light found by a BSDF-sampled ray (an emitter hit, an escape into the
/// environment): 1 after a camera ray or a delta lobe and in the direct integrator (which
/// never samples non-delta lobes); otherwise the power heuristic against the light sampler's
/// density `light_pdf()`, or 1/0 when only one strategy runs.
#[inline]
fn bsdf_hit_weight(ctx: &TileContext<'_>, path: &PathState, light_pdf: impl Fn() -> f32) -> f32 {
    if path.specular || ctx.transport.direct_only() {
        return 1.0;
    }
    match ctx.transport.light_strategy {
        LightStrategy::Mis => power_heuristic(path.pdf, light_pdf()),
        LightStrategy::LightOnly => 0.0,
        LightStrategy::BsdfOnly => 1.0,
    }
}

/// The weight of a light sample of density `light_pdf` whose direction the BSDF samples with
/// density `bsdf_pdf`.
#[inline]
fn light_sample_weight(ctx: &TileContext<'_>, light_pdf: f32, bsdf_pdf: f32) -> f32 {
    if ctx.transport.direct_only() || ctx.transport.light_strategy == LightStrategy::LightOnly {
        1.0
    } else {
        power_heuristic(light_pdf, bsdf_pdf)
    }
}

/// One hit being shaded.
struct Vertex<'r> {
    ray: &'r Ray,
    hit: &'r Hit,
    path: PathState,
    depth: u32,
    /// A camera ray's film position (for its differential), when the render carries them.
    film: Option<Vec2>,
}

/// Where a vertex puts its light sample and its continuation.
struct Queues<'q> {
    next_rays: &'q mut Vec<Ray>,
    next_paths: &'q mut Vec<PathState>,
    shadows: &'q mut ShadowQueue,
    counts: &'q mut RayCounts,
    log: &'q mut TrainingLog,
}

/// One path vertex, as pbrt-v4's `PathIntegrator::Li` reads: the surface front end, emission
/// with MIS ([`add_emission`]), a light sample unless every lobe is specular
/// ([`sample_light`]), the continuation ([`continue_path`]).
#[inline(always)]
fn shade(ctx: &TileContext<'_>, v: &mut Vertex<'_>, sums: &mut TileSums, q: &mut Queues<'_>) {
    let (hit, transport) = (v.hit, &ctx.transport);
    let Some(mesh) = ctx.scene.meshes.get(hit.geom_id as usize) else {
        return;
    };
    let material = &ctx.materials[material_index(mesh.material, ctx.materials.len())];
    if !v.path.medium.is_outside() {
        v.path.beta *= v.path.medium.transmittance(hit.t * v.ray.dir.length());
    }
    // Bounces that count against `max_depth`: transmission bounces have their own budget.
    let bounces = v.depth.saturating_sub(v.path.transmissions);
    // The direct integrator lights every vertex up to and including `max_depth`; the path
    // tracer's vertex at `max_depth` only adds what it emits.
    let lights_vertex = bounces < transport.max_depth || transport.direct_only();
    let query = HitQuery {
        mesh,
        material,
        hit,
        dir: v.ray.dir,
        // Built only for textured materials: most camera rays of a product shot miss the
        // model or hit untextured parts, and a differential is two more camera rays.
        differential: v
            .film
            .filter(|_| material.textured())
            .map(|film| camera_differential(ctx, film)),
        scatters: lights_vertex,
    };
    let Some(surface) = at_hit(&ctx.textures(), &query) else {
        return;
    };
    let si = &surface.si;
    if v.depth == 0 {
        let path = &v.path;
        record_first_hit(
            sums,
            path.pixel as usize,
            path.filter_weight,
            surface.albedo,
            si.ns,
            hit.t,
        );
    }
    add_emission(ctx, v, &surface, sums, q);
    let Some(bsdf) = surface.bsdf.as_ref().filter(|_| !surface.unlit) else {
        return;
    };
    let wo = surface.frame.to_local(si.wo);
    // The guide at this vertex (path tracer, `--guiding`, a wide lobe without delta lobes).
    let guide = if transport.direct_only() {
        None
    } else {
        ctx.guiding.at(si.p, bsdf, wo)
    };
    let path = &mut v.path;
    if bsdf.flags().has_density() {
        let at = Shading {
            si,
            frame: &surface.frame,
            wo,
            bsdf,
            transmits: bsdf.flags().transmits(),
            beta: path.beta,
            pixel: path.pixel,
            filter_weight: path.filter_weight,
            indirect: v.depth + 1 >= INDIRECT_DEPTH,
            guide,
            record: path.record,
        };
        sample_light(ctx, &at, &mut path.stream, q);
    }
    let at = Scattering {
        material,
        surface: &surface,
        bsdf,
        wo,
        guide,
    };
    continue_path(ctx, &at, path, v.depth, q);
}

/// The light a vertex's surface emits toward the path, weighted by MIS against the light
/// sampler where the light sampler could have drawn it: the emission of
/// [`at_hit`](fn@crate::material::at_hit), or an unlit material's base colour (weight 1:
/// light sampling never picks unlit surfaces).
#[inline(always)]
fn add_emission(
    ctx: &TileContext<'_>,
    v: &Vertex<'_>,
    surface: &SurfaceAtHit,
    sums: &mut TileSums,
    q: &mut Queues<'_>,
) {
    let (path, hit, si) = (&v.path, v.hit, &surface.si);
    let pixel = path.pixel as usize;
    if surface.unlit {
        // KHR_materials_unlit: ρ leaves the surface as radiance (from the sides that emit)
        // and nothing scatters.
        if surface.emits {
            sums.pending[pixel] += path.beta * surface.albedo;
            q.log.credit(path.record, path.beta * surface.albedo);
        }
        return;
    }
    if surface.emission == Vec3::ZERO {
        return;
    }
    let w = bsdf_hit_weight(ctx, path, || {
        ctx.lights.area_pdf(
            path.origin,
            path.origin_normal,
            (hit.geom_id, hit.instance, hit.prim_id),
            si.p,
        )
    });
    let value = path.beta * surface.emission * w;
    let value = clamped(ctx, value, path.filter_weight, v.depth >= INDIRECT_DEPTH);
    sums.pending[pixel] += value;
    q.log.credit(path.record, value);
}

/// What the continuation of a vertex reads of its surface.
struct Scattering<'s> {
    material: &'s ShadingMaterial,
    surface: &'s SurfaceAtHit,
    bsdf: &'s SurfaceBsdf,
    /// `ωo` in the BSDF's frame.
    wo: Vec3,
    /// The guide mixed into the continuation, if any.
    guide: Option<&'s Directional>,
}

/// The continuation of a vertex at `depth`: the path tracer samples the whole BSDF (or the
/// mixture with the guide), the direct integrator follows delta lobes only, up to
/// `max_depth` reflections; Russian roulette from [`RR_START_DEPTH`]; the new ray and path
/// join the next round.
#[inline(always)]
fn continue_path(
    ctx: &TileContext<'_>,
    at: &Scattering<'_>,
    path: &mut PathState,
    depth: u32,
    q: &mut Queues<'_>,
) {
    let transport = &ctx.transport;
    let (si, bsdf) = (&at.surface.si, at.bsdf);
    // Transmission bounces have their own budget, so `max_depth` counts the others.
    if depth.saturating_sub(path.transmissions) >= transport.max_depth {
        return;
    }
    // The direct integrator continues through delta lobes only: a BSDF without one ends the
    // path here (its sample would be drawn only to be discarded; nothing is drawn after it,
    // so skipping it changes no image).
    if transport.direct_only() && !bsdf.flags().contains(BsdfFlags::SPECULAR) {
        return;
    }
    let u_lobe = path.stream.next_1d();
    let u = path.stream.next_2d();
    let Some(bs) = draw_continuation(at, u_lobe, u) else {
        return;
    };
    if transport.direct_only() && !bs.delta {
        return;
    }
    // A transmission bounce spends its own budget instead of `max_depth`: a refraction, or a
    // reflection off the inside of a surface that transmits (light bouncing inside glass).
    let inside_glass = bsdf.flags().transmits() && (bs.transmission || !si.front_face);
    let transmissions = if inside_glass {
        if path.transmissions >= transport.max_transmission_depth {
            return;
        }
        path.transmissions + 1
    } else {
        path.transmissions
    };
    let wi = bs.wi;
    // Reflections stay above the geometric surface, transmissions go below it.
    if (wi.dot(si.ng) <= 0.0) != bs.transmission {
        return;
    }
    let medium = if bs.transmission {
        let volume = at.material.layers.filter(|l| l.volume).map(|l| l.sigma);
        path.medium.after_transmission(volume, si.front_face)
    } else {
        path.medium
    };
    let mut beta = path.beta * bs.weight;
    if transport.russian_roulette && depth + 1 >= RR_START_DEPTH && !transport.direct_only() {
        let fw = path.filter_weight.abs().max(f32::MIN_POSITIVE);
        let survive = (beta.abs().max_element() / fw).min(1.0);
        if survive <= 0.0 || path.stream.next_1d() >= survive {
            return;
        }
        beta /= survive;
    }
    if beta == Vec3::ZERO || !beta.is_finite() {
        return;
    }
    let ray = spawn_ray(si.p, si.p_error, si.ng, wi);
    let record = if path.trains && !bs.delta {
        q.log.push(si.p, wi, bs.pdf, beta, path.record)
    } else {
        path.record
    };
    q.next_rays.push(ray);
    q.next_paths.push(PathState {
        beta,
        pdf: bs.pdf,
        specular: bs.delta,
        origin: si.p,
        origin_normal: si.ns,
        medium,
        record,
        transmissions,
        ..*path
    });
}

/// The continuation's direction drawn from the BSDF, or from the one-sample mixture of BSDF
/// and guide (`render::guided`) where a guide is on; `None` when the draw fails.
#[inline(always)]
fn draw_continuation(at: &Scattering<'_>, u_lobe: f32, u: Vec2) -> Option<Continuation> {
    let frame = &at.surface.frame;
    match at.guide {
        Some(g) => {
            let gs = super::guided::sample(g, at.bsdf, frame, at.wo, u_lobe, u)?;
            Some(Continuation {
                wi: gs.wi,
                weight: gs.weight,
                pdf: gs.pdf,
                delta: false,
                transmission: gs.transmission,
            })
        }
        None => {
            let bs = at.bsdf.sample(at.wo, u_lobe, u)?;
            Some(Continuation {
                wi: frame.to_world(bs.wi),
                weight: bs.weight,
                pdf: bs.pdf,
                delta: bs.delta,
                transmission: bs.transmission,
            })
        }
    }
}

/// A continuation drawn at a vertex: from the BSDF, or from the mixture of BSDF and guide.
struct Continuation {
    /// World direction.
    wi: Vec3,
    /// `f · |cos θi| / pdf` (a delta lobe: its weight).
    weight: Vec3,
    /// The density `wi` was drawn with (the mixture's where guided).
    pdf: f32,
    delta: bool,
    transmission: bool,
}

/// Next-event estimation at a vertex: each split delta light, then one sample of each kind of
/// light (finite, infinite) from the light sampler; each sample is one shadow ray carrying its
/// contribution.
#[inline(always)]
fn sample_light(
    ctx: &TileContext<'_>,
    at: &Shading<'_>,
    stream: &mut SampleStream,
    q: &mut Queues<'_>,
) {
    let (lights, si) = (&ctx.lights, at.si);
    for sample in lights.delta(si.p) {
        at.add(ctx, sample, q);
    }
    for kind in lights.kinds().into_iter().flatten() {
        let u_choice = if kind.needs_choice {
            stream.next_1d()
        } else {
            0.0
        };
        let u = if kind.needs_position {
            stream.next_2d()
        } else {
            Vec2::ZERO
        };
        at.add(ctx, lights.sample(kind, si.p, si.ns, u_choice, u), q);
    }
}

/// A vertex's shading point and BSDF, as light samples are evaluated against them.
struct Shading<'s> {
    si: &'s SurfaceInteraction,
    frame: &'s Frame,
    wo: Vec3,
    bsdf: &'s SurfaceBsdf,
    transmits: bool,
    beta: Vec3,
    pixel: u32,
    /// The sample's filter weight and whether its light is indirect (`--clamp-indirect`).
    filter_weight: f32,
    indirect: bool,
    /// The guide mixed into this vertex's continuation: light samples weigh against the
    /// mixture's density.
    guide: Option<&'s Directional>,
    /// The path's last logged vertex (training).
    record: u32,
}

impl Shading<'_> {
    /// A light sample's contribution after `--clamp-indirect` (when on).
    #[inline(always)]
    fn clamped(&self, ctx: &TileContext<'_>, value: Vec3) -> Vec3 {
        clamped(ctx, value, self.filter_weight, self.indirect)
    }

    /// The density with which the continuation draws local direction `wl` (world `wi`).
    #[inline(always)]
    fn continuation_pdf(&self, wl: Vec3, wi: Vec3) -> f32 {
        super::guided::mixture_pdf(self.guide, self.bsdf, self.wo, wl, wi)
    }

    /// Queues the shadow ray of one light sample with its contribution
    /// `β · f · |cos θi| · L · w / p` (or counts why there is none).
    #[inline(always)]
    fn add(
        &self,
        ctx: &TileContext<'_>,
        sample: Result<LightSample, NoLightSample>,
        q: &mut Queues<'_>,
    ) {
        let (si, bsdf, wo) = (self.si, self.bsdf, self.wo);
        let sample = match sample {
            Ok(sample) => sample,
            Err(NoLightSample::Unlit(Unlit::OutsideCone)) => {
                q.counts.skipped_outside_cone += 1;
                return;
            }
            Err(NoLightSample::Unlit(Unlit::BeyondRange)) => {
                q.counts.skipped_beyond_range += 1;
                return;
            }
            Err(NoLightSample::Unlit(Unlit::AtLight)) => {
                q.counts.skipped_facing_away += 1;
                return;
            }
            Err(NoLightSample::None) => return,
        };
        match sample {
            LightSample::Delta {
                wi,
                irradiance,
                target,
                probability,
            } => {
                if !reachable(si, wi, self.transmits) {
                    q.counts.skipped_facing_away += 1;
                    return;
                }
                let wl = self.frame.to_local(wi);
                let value = self.beta * bsdf.eval(wo, wl) * irradiance * (wl.z.abs() / probability);
                if value == Vec3::ZERO || !value.is_finite() {
                    return;
                }
                let ray = match target {
                    ShadowTarget::Point(position) => {
                        spawn_ray_to(si.p, si.p_error, si.ng, position)
                    }
                    ShadowTarget::Infinity => spawn_ray(si.p, si.p_error, si.ng, wi),
                };
                q.shadows
                    .push(ray, self.pixel, self.record, self.clamped(ctx, value));
            }
            LightSample::Area(ls) => {
                if !reachable(si, ls.wi, self.transmits) {
                    return;
                }
                let le = emitted_at(ctx, &ls);
                let wl = self.frame.to_local(ls.wi);
                let f = bsdf.eval(wo, wl);
                if le == Vec3::ZERO || f == Vec3::ZERO {
                    return;
                }
                let w = light_sample_weight(ctx, ls.pdf, self.continuation_pdf(wl, ls.wi));
                let value = self.beta * f * le * (wl.z.abs() * w / ls.pdf);
                if value.is_finite() {
                    let ray = spawn_ray_to(si.p, si.p_error, si.ng, ls.point);
                    q.shadows
                        .push(ray, self.pixel, self.record, self.clamped(ctx, value));
                }
            }
            LightSample::Environment(es) => {
                if !reachable(si, es.wi, self.transmits) {
                    return;
                }
                let wl = self.frame.to_local(es.wi);
                let f = bsdf.eval(wo, wl);
                if f == Vec3::ZERO || es.radiance == Vec3::ZERO {
                    return;
                }
                let w = light_sample_weight(ctx, es.pdf, self.continuation_pdf(wl, es.wi));
                let value = self.beta * f * es.radiance * (wl.z.abs() * w / es.pdf);
                if value.is_finite() {
                    let ray = spawn_ray(si.p, si.p_error, si.ng, es.wi);
                    q.shadows
                        .push(ray, self.pixel, self.record, self.clamped(ctx, value));
                }
            }
        }
    }
}

/// Whether light from direction `wi` can reach the shading point through the BSDF: above
/// both the geometric and the shading horizon, or, for a transmitting BSDF, below both
/// (shading normals never let light through the surface on their own).
#[inline(always)]
fn reachable(si: &SurfaceInteraction, wi: Vec3, transmits: bool) -> bool {
    let (g, s) = (si.ng.dot(wi), si.ns.dot(wi));
    (g > 0.0 && s > 0.0) || (g < 0.0 && s < 0.0 && transmits)
}

/// The radiance the sampled emitter point `ls` sends toward `-ls.wi` (back to the
/// shading point): the emission rule of `material::emitted`, times the emitter's alpha
/// coverage.
#[inline]
fn emitted_at(ctx: &TileContext<'_>, ls: &AreaSample) -> Vec3 {
    let Some(mesh) = ctx.scene.meshes.get(ls.mesh as usize) else {
        return Vec3::ZERO;
    };
    let Some(&vertices) = mesh.indices.get(ls.triangle as usize) else {
        return Vec3::ZERO;
    };
    let material = &ctx.materials[material_index(mesh.material, ctx.materials.len())];
    let ng = ls.normal;
    let wo = -ls.wi;
    let front_face = ng.dot(wo) > 0.0;
    let si = SurfaceInteraction {
        p: ls.point,
        p_error: Vec3::ZERO,
        ng: if front_face { ng } else { -ng },
        ns: if front_face { ng } else { -ng },
        wo,
        front_face,
        barycentrics: ls.barycentrics,
        vertices,
        placement: None,
    };
    let at = TexturePoint {
        mesh,
        si: &si,
        footprint: None,
    };
    let emits = front_face || material.double_sided;
    let mut emission = emitted(&ctx.textures(), &at, material, emits);
    if emission == Vec3::ZERO {
        return emission;
    }
    // An emitter with alpha is hit by BSDF-sampled rays only where (MASK) or as often as
    // (BLEND) its coverage says; its light samples carry the same expectation.
    if let Some(visibility) = &ctx.visibility {
        emission *= visibility.emitter_coverage(ctx, ls.mesh, &si);
    }
    emission
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_heuristic_weights_sum_to_one() {
        for (a, b) in [(1.0f32, 1.0f32), (0.3, 2.0), (5.0, 0.01)] {
            let s = power_heuristic(a, b) + power_heuristic(b, a);
            assert!((s - 1.0).abs() < 1e-6);
        }
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
        assert_eq!(power_heuristic(f32::INFINITY, 1.0), 1.0);
    }
}
