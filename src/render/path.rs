//! The path tracer: the rendering equation `L_o = L_e + ∫ L_i f |cos θ| dω`, estimated by
//! unidirectional paths with next-event estimation and multiple importance sampling.
//!
//! Like the direct integrator it runs one tile at a time as a wavefront: for each sample index
//! the tile's camera rays are traced as one coherent batch, then every live path is extended
//! by one vertex per round: its hit is shaded, its light samples become one occlusion batch,
//! and its BSDF samples become the next (incoherent) batch of rays.
//!
//! At a vertex with throughput β, outgoing direction ωo and BSDF f:
//! - **Emission** `β · Le · w`: `w = 1` for camera rays and after a delta lobe, otherwise the
//!   power-heuristic weight of the BSDF sample against the light sampler's density for the
//!   point it hit (area lights, the environment when the ray escapes).
//! - **Light sampling** (next-event estimation), while the depth is below `max_depth`: every
//!   punctual light (delta lights: weight 1, no MIS), one point on the emissive triangles
//!   chosen by power (see [`crate::light::area`]) and one environment direction, each
//!   `β · f(ωo, ωi) · |cos θi| · L · w / p_light`, with `w` the power heuristic of `p_light`
//!   against the BSDF's density `p_bsdf(ωi)`.
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
//! A light sample or a BSDF sample below the geometric horizon of the surface (the side the
//! ray arrived from) is dropped: shading normals never let light through the surface.

use super::LightStrategy;
use super::film::TileSums;
use super::integrator::{
    Footprint, Pass, Scratch, TileContext, camera_sample, record_first_hit, surface_colors,
    texture_value, trace_batch, trace_shadows,
};
use super::sampler::SampleStream;
use super::stats::RayCounts;
use super::tiles::Tile;
use super::visibility::RayBatch;
use crate::accel::{Hit, Ray};
use crate::bsdf::{Bsdf, Frame};
use crate::geometry::{SurfaceInteraction, shading_normal, spawn_ray, spawn_ray_to};
use crate::light::area::AreaSample;
use crate::light::{Incident, PunctualLight, ShadowTarget};
use crate::material::material_index;
use crate::material::scattering::SurfaceBsdf;
use crate::render::medium::Medium;
use glam::Vec3;

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
}

/// Buffers of the path tracer, reused across tiles.
#[derive(Default)]
pub(crate) struct PathScratch {
    rays: Vec<Ray>,
    paths: Vec<PathState>,
    hits: Vec<Option<Hit>>,
    next_rays: Vec<Ray>,
    next_paths: Vec<PathState>,
    shadow_rays: Vec<Ray>,
    shadow_values: Vec<(u32, Vec3)>,
    occluded: Vec<bool>,
    weights: Vec<f32>,
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

/// Renders one tile with the path tracer. The const switches remove per-hit work the scene
/// does not need, as in the direct integrator.
pub(crate) fn render_tile_path<
    const TEXTURES: bool,
    const VERTEX_COLORS: bool,
    const SHADING_NORMALS: bool,
    const NORMAL_MAPS: bool,
>(
    ctx: &TileContext<'_>,
    pass: Pass,
    tile: &Tile,
    scratch: &mut Scratch,
) -> (TileSums, RayCounts) {
    let s = &mut scratch.path;
    let mut sums = TileSums::new(tile.pixel_count(), ctx.aovs);
    let mut counts = RayCounts::default();
    // Camera rays carry differentials for their first hit's texture footprint; bounce rays
    // look textures up at the finest level.
    let carry = TEXTURES && ctx.differentials;
    for sample in pass.first_sample..pass.first_sample.saturating_add(pass.spp) {
        s.rays.clear();
        s.paths.clear();
        s.weights.clear();
        scratch.diffs.clear();
        for local in 0..tile.pixel_count() {
            let (x, y) = tile.pixel(local);
            let (ray, weight) =
                camera_sample(ctx, x, y, sample, carry.then_some(&mut scratch.diffs));
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
            });
        }
        let mut depth = 0;
        while !s.rays.is_empty() {
            let primary = depth == 0;
            let batch = RayBatch::new(tile, sample, depth);
            let coherence = trace_batch(ctx, &s.rays, &mut s.hits, primary, batch, &mut counts);
            if primary {
                super::ids::record_coverage(ctx, &mut sums, &s.hits);
            }
            s.next_rays.clear();
            s.next_paths.clear();
            s.shadow_rays.clear();
            s.shadow_values.clear();
            for i in 0..s.rays.len() {
                let (ray, path) = (s.rays[i], s.paths[i]);
                let Some(hit) = s.hits[i] else {
                    escaped(ctx, &ray, &path, primary, &mut sums);
                    continue;
                };
                let footprint_source = if carry && primary {
                    scratch.diffs.get(i)
                } else {
                    None
                };
                let mut vertex = Vertex {
                    ray: &ray,
                    hit: &hit,
                    path,
                    depth,
                    diff: footprint_source,
                };
                shade::<TEXTURES, VERTEX_COLORS, SHADING_NORMALS, NORMAL_MAPS>(
                    ctx,
                    &mut vertex,
                    &mut sums,
                    &mut Queues {
                        next_rays: &mut s.next_rays,
                        next_paths: &mut s.next_paths,
                        shadow_rays: &mut s.shadow_rays,
                        shadow_values: &mut s.shadow_values,
                        counts: &mut counts,
                    },
                );
            }
            trace_shadows(
                ctx,
                &s.shadow_rays,
                &s.shadow_values,
                &mut s.occluded,
                (coherence, batch),
                &mut counts,
                &mut sums,
            );
            std::mem::swap(&mut s.rays, &mut s.next_rays);
            std::mem::swap(&mut s.paths, &mut s.next_paths);
            depth += 1;
        }
        sums.end_sample(sample, &s.weights);
    }
    (sums, counts)
}

/// A ray that left the scene: the environment's radiance, weighted against environment
/// sampling unless the ray is a camera ray (shown only when the environment is visible) or
/// left a delta lobe.
#[inline]
fn escaped(ctx: &TileContext<'_>, ray: &Ray, path: &PathState, primary: bool, sums: &mut TileSums) {
    let Some(env) = ctx.environment else {
        return;
    };
    if primary && !ctx.environment_visible {
        return;
    }
    // An infinite segment inside an absorbing volume (an open mesh) transmits nothing.
    let beta = path.beta * path.medium.transmittance(f32::INFINITY);
    let dir = ray.dir.normalize_or_zero();
    let le = env.radiance(dir);
    if le == Vec3::ZERO {
        return;
    }
    let w = bsdf_hit_weight(ctx, path, || env.pdf(dir));
    sums.pending[path.pixel as usize] += beta * le * w;
}

/// The weight of light found by a BSDF-sampled ray (an emitter hit, an escape into the
/// environment): 1 after a camera ray or a delta lobe and in the direct integrator (which
/// never samples non-delta lobes); otherwise the power heuristic against the light sampler's
/// density `light_pdf()`, or 1/0 when only one strategy runs.
#[inline]
fn bsdf_hit_weight(ctx: &TileContext<'_>, path: &PathState, light_pdf: impl Fn() -> f32) -> f32 {
    if path.specular || ctx.delta_only {
        return 1.0;
    }
    match ctx.light_strategy {
        LightStrategy::Mis => power_heuristic(path.pdf, light_pdf()),
        LightStrategy::LightOnly => 0.0,
        LightStrategy::BsdfOnly => 1.0,
    }
}

/// The weight of a light sample of density `light_pdf` whose direction the BSDF samples with
/// density `bsdf_pdf`.
#[inline]
fn light_sample_weight(ctx: &TileContext<'_>, light_pdf: f32, bsdf_pdf: f32) -> f32 {
    if ctx.delta_only || ctx.light_strategy == LightStrategy::LightOnly {
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
    diff: Option<&'r crate::texture::RayDifferential>,
}

/// Where a vertex puts its light samples and its continuation.
struct Queues<'q> {
    next_rays: &'q mut Vec<Ray>,
    next_paths: &'q mut Vec<PathState>,
    shadow_rays: &'q mut Vec<Ray>,
    shadow_values: &'q mut Vec<(u32, Vec3)>,
    counts: &'q mut RayCounts,
}

/// Shades one path vertex: AOVs (camera rays), emission, light samples, the next ray.
#[inline(always)]
fn shade<
    const TEXTURES: bool,
    const VERTEX_COLORS: bool,
    const SHADING_NORMALS: bool,
    const NORMAL_MAPS: bool,
>(
    ctx: &TileContext<'_>,
    v: &mut Vertex<'_>,
    sums: &mut TileSums,
    q: &mut Queues<'_>,
) {
    let hit = v.hit;
    let Some(mesh) = ctx.scene.meshes.get(hit.geom_id as usize) else {
        return;
    };
    let Some(mut si) = SurfaceInteraction::from_hit(mesh, hit, v.ray.dir) else {
        return;
    };
    let material = &ctx.materials[material_index(mesh.material, ctx.materials.len())];
    if SHADING_NORMALS && let Some(normals) = &mesh.normals {
        si.ns = shading_normal(&si, normals);
    }
    let transmits = material.layers.is_some_and(|l| l.transmits());
    let lit = si.front_face || material.double_sided || transmits;
    if !v.path.medium.is_outside() {
        v.path.beta *= v.path.medium.transmittance(hit.t * v.ray.dir.length());
    }
    let footprint = if TEXTURES {
        v.diff.and_then(|rd| Footprint::at(mesh, &si, rd))
    } else {
        None
    };
    // The interpolated normal, before the base's normal map: a clear coat's normal map
    // perturbs this one.
    let vertex_ns = si.ns;
    let mapped_tangent = if NORMAL_MAPS {
        super::normal_maps::apply(ctx, mesh, &mut si, footprint.as_ref(), material)
    } else {
        None
    };
    let (albedo, emission) =
        surface_colors::<TEXTURES, VERTEX_COLORS>(ctx, mesh, &si, footprint.as_ref(), material);
    let path = &mut v.path;
    let pixel = path.pixel as usize;
    if v.depth == 0 {
        record_first_hit(sums, pixel, path.filter_weight, lit, albedo, si.ns, hit.t);
    }
    if !lit {
        return;
    }
    if material.unlit {
        // KHR_materials_unlit: ρ leaves the surface as radiance and nothing scatters. Light
        // sampling never picks unlit surfaces, so BSDF sampling finds them with weight 1.
        sums.pending[pixel] += path.beta * albedo;
        return;
    }
    if emission != Vec3::ZERO {
        let w = bsdf_hit_weight(ctx, path, || match &ctx.area_lights {
            Some(area) => area.pdf(
                path.origin,
                path.origin_normal,
                (hit.geom_id, hit.instance, hit.prim_id),
                si.p,
            ),
            None => 0.0,
        });
        sums.pending[pixel] += path.beta * emission * w;
    }
    if v.depth >= ctx.max_depth && !ctx.delta_only {
        return;
    }

    // The direct integrator's mapping reads the factors only.
    let metallic_roughness = if TEXTURES && !ctx.delta_only {
        super::normal_maps::metallic_roughness(ctx, mesh, &si, footprint.as_ref(), material)
    } else {
        (material.metallic, material.roughness)
    };
    let frame = match mapped_tangent {
        Some(t) => Frame::from_normal_tangent(si.ns, t),
        None => Frame::from_normal(si.ns),
    };
    let layers = match &material.layers {
        Some(l) if TEXTURES && l.has_textures() => {
            let mut l = super::layer_textures::at_hit(ctx, mesh, &si, footprint.as_ref(), l);
            if NORMAL_MAPS {
                l.coat_normal = super::layer_textures::coat_normal(
                    ctx,
                    mesh,
                    &si,
                    vertex_ns,
                    footprint.as_ref(),
                    material,
                    &frame,
                );
            }
            Some(l)
        }
        other => *other,
    };
    let bsdf = SurfaceBsdf::for_hit_with_layers(
        albedo,
        metallic_roughness,
        material,
        layers.as_ref(),
        ctx.delta_only,
        si.front_face,
    );
    let wo = frame.to_local(si.wo);
    if !bsdf.is_delta() {
        sample_lights::<TEXTURES>(ctx, &si, &frame, wo, &bsdf, path, q);
    }

    // The continuation. The direct integrator follows delta lobes only, up to max_depth
    // reflections as before; the path tracer samples the whole BSDF.
    if v.depth >= ctx.max_depth {
        return;
    }
    let u_lobe = path.stream.next_1d();
    let u = path.stream.next_2d();
    let Some(bs) = bsdf.sample(wo, u_lobe, u) else {
        return;
    };
    if ctx.delta_only && !bs.delta {
        return;
    }
    let wi = frame.to_world(bs.wi);
    // Reflections stay above the geometric surface, transmissions go below it.
    if (wi.dot(si.ng) <= 0.0) != bs.transmission {
        return;
    }
    let medium = if bs.transmission {
        let volume = material.layers.filter(|l| l.volume).map(|l| l.sigma);
        path.medium.after_transmission(volume, si.front_face)
    } else {
        path.medium
    };
    let mut beta = path.beta * bs.weight;
    if ctx.russian_roulette && v.depth + 1 >= RR_START_DEPTH && !ctx.delta_only {
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
    q.next_rays.push(ray);
    q.next_paths.push(PathState {
        beta,
        pdf: bs.pdf,
        specular: bs.delta,
        origin: si.p,
        origin_normal: si.ns,
        medium,
        ..*path
    });
}

/// Next-event estimation at a vertex: every punctual light, one area-light point, one
/// environment direction; each becomes one shadow ray carrying its contribution.
#[inline(always)]
fn sample_lights<const TEXTURES: bool>(
    ctx: &TileContext<'_>,
    si: &SurfaceInteraction,
    frame: &Frame,
    wo: Vec3,
    bsdf: &SurfaceBsdf,
    path: &mut PathState,
    q: &mut Queues<'_>,
) {
    let pixel = path.pixel;
    for light in &ctx.lights.general {
        let Ok(Incident {
            wi,
            irradiance,
            target,
        }) = light.incident(si.p)
        else {
            q.counts.skipped_outside_cone += 1;
            continue;
        };
        if !reachable(si, wi, bsdf) {
            q.counts.skipped_facing_away += 1;
            continue;
        }
        let wl = frame.to_local(wi);
        let value = path.beta * bsdf.eval(wo, wl) * irradiance * wl.z.abs();
        if value == Vec3::ZERO {
            continue;
        }
        q.shadow_rays.push(match target {
            ShadowTarget::Point(position) => spawn_ray_to(si.p, si.p_error, si.ng, position),
            ShadowTarget::Infinity => spawn_ray(si.p, si.p_error, si.ng, wi),
        });
        q.shadow_values.push((pixel, value));
    }

    let sample_surfaces = ctx.delta_only || ctx.light_strategy != LightStrategy::BsdfOnly;
    if let Some(area) = ctx.area_lights.as_ref().filter(|_| sample_surfaces) {
        let u_select = path.stream.next_1d();
        let u = path.stream.next_2d();
        if let Some(ls) = area.sample(si.p, si.ns, u_select, u)
            && ls.pdf > 0.0
            && reachable(si, ls.wi, bsdf)
        {
            let le = emitted_at::<TEXTURES>(ctx, &ls);
            let wl = frame.to_local(ls.wi);
            let f = bsdf.eval(wo, wl);
            if le != Vec3::ZERO && f != Vec3::ZERO {
                let w = light_sample_weight(ctx, ls.pdf, bsdf.pdf(wo, wl));
                let value = path.beta * f * le * (wl.z.abs() * w / ls.pdf);
                if value.is_finite() {
                    q.shadow_rays
                        .push(spawn_ray_to(si.p, si.p_error, si.ng, ls.point));
                    q.shadow_values.push((pixel, value));
                }
            }
        }
    }

    if let Some(env) = ctx.environment.filter(|_| sample_surfaces) {
        let u = path.stream.next_2d();
        if let Some(es) = env.sample(u)
            && es.pdf > 0.0
            && reachable(si, es.wi, bsdf)
        {
            let wl = frame.to_local(es.wi);
            let f = bsdf.eval(wo, wl);
            if f != Vec3::ZERO && es.radiance != Vec3::ZERO {
                let w = light_sample_weight(ctx, es.pdf, bsdf.pdf(wo, wl));
                let value = path.beta * f * es.radiance * (wl.z.abs() * w / es.pdf);
                if value.is_finite() {
                    q.shadow_rays
                        .push(spawn_ray(si.p, si.p_error, si.ng, es.wi));
                    q.shadow_values.push((pixel, value));
                }
            }
        }
    }
}

/// Whether light from direction `wi` can reach the shading point through the BSDF: above
/// both the geometric and the shading horizon, or, for a transmitting BSDF, below both
/// (shading normals never let light through the surface on their own).
#[inline(always)]
fn reachable(si: &SurfaceInteraction, wi: Vec3, bsdf: &SurfaceBsdf) -> bool {
    let (g, s) = (si.ng.dot(wi), si.ns.dot(wi));
    (g > 0.0 && s > 0.0) || (g < 0.0 && s < 0.0 && bsdf.transmits())
}

/// The radiance the sampled emitter point `ls` sends toward `-ls.wi` (back to the
/// shading point): its material's emission, textured, on a lit side only.
#[inline]
fn emitted_at<const TEXTURES: bool>(ctx: &TileContext<'_>, ls: &AreaSample) -> Vec3 {
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
    // Unlit surfaces ignore their emissive factor (their ρ is counted where rays hit them).
    if !(front_face || material.double_sided) || material.unlit {
        return Vec3::ZERO;
    }
    let mut emission = material.emissive;
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
    if TEXTURES && let Some(t) = &material.emissive_texture {
        emission *= texture_value(ctx, mesh, &si, None, t).truncate();
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
