//! The direct-lighting integrator, one tile at a time, in batches.
//!
//! For each sample index the tile's camera rays are generated together and traced as one
//! coherent batch (Embree packets); the hits are turned into surface interactions; every
//! (light, hit) pair that can contribute yields one shadow ray, and all of them are traced as
//! one occlusion batch; mirror hits yield reflection rays, traced as the next batch, up to the
//! maximum depth. Buffers live in [`Scratch`] and are reused across tiles.
//!
//! Radiance along a path vertex with throughput β (product of mirror reflectances so far):
//! `L += β · Le` (front faces or double-sided), and for each light
//! `L += β · (diffuse_weight · ρ / π) · E(p) · cosθs · V(p, light)`, where `E(p)` is the
//! light's irradiance on a facing surface, `cosθs = dot(ns, wi)`, and a light below either
//! the shading or the geometric horizon contributes nothing.

use super::camera::CameraRays;
use super::film::{AovSelection, TileSums};
use super::filter::FilterSampler;
use super::sampler::PixelSampler;
use super::stats::RayCounts;
use super::tiles::Tile;
use super::visibility::{RayBatch, RayKind};
use crate::accel::{Accel, Coherence, Hit, Ray};
use crate::geometry::{SurfaceInteraction, shading_normal, spawn_ray, spawn_ray_to};
use crate::light::{Incident, LightSet, PunctualLight, ShadowTarget, Unlit};
use crate::material::{Lambert, ShadingMaterial, material_index, reflect, texture};
use crate::scene::{Mesh, Scene, TextureRef};
use crate::texture::differentials::{
    self, MirrorHit, SurfaceDifferentials, attribute_derivative, barycentric_derivatives,
};
use crate::texture::noise::{Band, Domain};
use crate::texture::{MipMap, ProceduralTexture, RayDifferential, TextureFilter, UvFootprint};
use glam::{Vec2, Vec3, Vec4};

/// Everything a tile render reads; shared by all workers.
pub(crate) struct TileContext<'a> {
    pub scene: &'a Scene,
    pub accel: &'a dyn Accel,
    pub camera: CameraRays,
    pub sampler: PixelSampler,
    /// Turns the sampler's point into a film offset and a filter weight.
    pub filter: FilterSampler,
    pub materials: Vec<ShadingMaterial>,
    pub lights: LightSet,
    /// Loop over per-type light lists (specialised) or the run-time typed list (general).
    pub typed_lights: bool,
    pub max_depth: u32,
    pub aovs: AovSelection,
    /// MIP chains of `scene.textures`, index-aligned (empty when the kernel reads no textures).
    pub mipmaps: std::borrow::Cow<'a, [MipMap]>,
    /// How textures are filtered.
    pub texture_filter: TextureFilter,
    /// Whether rays carry differentials: the scene has textures and the filter reads
    /// footprints. Only read by kernels with textures on.
    pub differentials: bool,
    /// Film distance between neighbouring samples, 1/√spp pixels.
    pub differential_spacing: f32,
    /// The environment light, if the render has one.
    pub environment: Option<&'a crate::light::environment::EnvironmentLight>,
    /// Whether camera rays that miss show the environment.
    pub environment_visible: bool,
    /// The scene's emissive triangles as lights (`None` when nothing emits).
    pub area_lights: Option<std::borrow::Cow<'a, crate::light::area::AreaLights>>,
    /// The direct integrator's rule for the path kernel: follow delta lobes only, light the
    /// rest by light sampling alone (no MIS, no indirect light).
    pub delta_only: bool,
    /// Light or BSDF sampling or both (path kernel).
    pub light_strategy: super::LightStrategy,
    /// Russian roulette on (path kernel).
    pub russian_roulette: bool,
    /// Alpha tests and camera back-face culling (`None`: every hit counts).
    pub visibility: Option<super::visibility::Visibility>,
}

/// The samples one pass adds: indices `first_sample .. first_sample + spp` of every pixel's
/// sequence. Passed to each tile apart from the [`TileContext`], which stays the same for
/// every pass of a render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Pass {
    /// First sample index of the pass.
    pub first_sample: u32,
    /// Samples per pixel in the pass.
    pub spp: u32,
}

/// A path vertex waiting for its ray's hit: which pixel it feeds and with what weight.
#[derive(Clone, Copy, Debug)]
struct PathVertex {
    pixel: u32,
    /// Includes the sample's filter weight.
    throughput: Vec3,
    /// The sample's filter weight (AOVs are weighted by it too).
    filter_weight: f32,
}

/// A diffuse hit waiting for its lights.
#[derive(Clone, Copy, Debug)]
struct ShadingPoint {
    p: Vec3,
    p_error: Vec3,
    ng: Vec3,
    ns: Vec3,
    pixel: u32,
    /// β · f: what the light's `E · cosθ` is multiplied by.
    weight: Vec3,
}

/// Per-worker buffers, reused for every tile the worker renders.
#[derive(Default)]
pub(crate) struct Scratch {
    rays: Vec<Ray>,
    paths: Vec<PathVertex>,
    hits: Vec<Option<Hit>>,
    next_rays: Vec<Ray>,
    next_paths: Vec<PathVertex>,
    points: Vec<ShadingPoint>,
    shadow_rays: Vec<Ray>,
    shadow_values: Vec<(u32, Vec3)>,
    occluded: Vec<bool>,
    /// Ray differentials, index-aligned with `rays` (empty unless carried).
    pub(super) diffs: Vec<RayDifferential>,
    /// The path tracer's buffers.
    pub(super) path: super::path::PathScratch,
    next_diffs: Vec<RayDifferential>,
    /// Filter weight of each tile pixel's sample in flight.
    weights: Vec<f32>,
}

/// Renders one tile: all samples of all its pixels. The const switches remove per-hit work
/// (see [`super::kernel`]).
pub(crate) fn render_tile<
    const TEXTURES: bool,
    const MIRRORS: bool,
    const VERTEX_COLORS: bool,
    const SHADING_NORMALS: bool,
    const NORMAL_MAPS: bool,
>(
    ctx: &TileContext<'_>,
    pass: Pass,
    tile: &Tile,
    s: &mut Scratch,
) -> (TileSums, RayCounts) {
    let mut sums = TileSums::new(tile.pixel_count(), ctx.aovs);
    let mut counts = RayCounts::default();
    // Differentials exist only in texture kernels, and only when a filter reads them.
    let carry = TEXTURES && ctx.differentials;
    for sample in pass.first_sample..pass.first_sample.saturating_add(pass.spp) {
        s.rays.clear();
        s.paths.clear();
        s.weights.clear();
        s.diffs.clear();
        for local in 0..tile.pixel_count() {
            let (x, y) = tile.pixel(local);
            let (ray, weight) = camera_sample(ctx, x, y, sample, carry.then_some(&mut s.diffs));
            s.rays.push(ray);
            s.weights.push(weight);
            s.paths.push(PathVertex {
                pixel: local as u32,
                throughput: Vec3::splat(weight),
                filter_weight: weight,
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

            s.points.clear();
            s.next_rays.clear();
            s.next_paths.clear();
            s.next_diffs.clear();
            let may_reflect = MIRRORS && depth < ctx.max_depth;
            for i in 0..s.rays.len() {
                let (Some(hit), path) = (s.hits[i], s.paths[i]) else {
                    continue;
                };
                let ray = s.rays[i];
                let diff = if carry { s.diffs.get(i) } else { None };
                shade_hit::<TEXTURES, VERTEX_COLORS, SHADING_NORMALS, NORMAL_MAPS>(
                    ctx,
                    &ray,
                    diff,
                    &hit,
                    path,
                    primary,
                    may_reflect,
                    &mut sums,
                    &mut s.points,
                    &mut s.next_rays,
                    &mut s.next_paths,
                    &mut s.next_diffs,
                );
            }

            s.shadow_rays.clear();
            s.shadow_values.clear();
            if !s.points.is_empty() {
                let batch = &mut ShadowBatch {
                    rays: &mut s.shadow_rays,
                    values: &mut s.shadow_values,
                    counts: &mut counts,
                };
                let lights = &ctx.lights;
                if ctx.typed_lights {
                    add_shadow_rays(&lights.points, &s.points, batch);
                    add_shadow_rays(&lights.ranged_points, &s.points, batch);
                    add_shadow_rays(&lights.spots, &s.points, batch);
                    add_shadow_rays(&lights.ranged_spots, &s.points, batch);
                    add_shadow_rays(&lights.directionals, &s.points, batch);
                } else {
                    add_shadow_rays(&lights.general, &s.points, batch);
                }
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
            std::mem::swap(&mut s.diffs, &mut s.next_diffs);
            depth += 1;
        }
        sums.end_sample(sample, &s.weights);
    }
    (sums, counts)
}

/// Base colour ρ and emitted radiance Le at a hit, textures and vertex colours applied (the
/// emissive texture is read only where the material emits).
#[inline(always)]
pub(super) fn surface_colors<const TEXTURES: bool, const VERTEX_COLORS: bool>(
    ctx: &TileContext<'_>,
    mesh: &Mesh,
    si: &SurfaceInteraction,
    footprint: Option<&Footprint>,
    material: &ShadingMaterial,
) -> (Vec3, Vec3) {
    let mut albedo = material.base_color;
    if VERTEX_COLORS && let Some(colors) = &mesh.colors {
        albedo *= si.interpolate(colors).unwrap_or(Vec4::ONE).truncate();
    }
    let mut emission = material.emissive;
    if TEXTURES {
        if let Some(t) = &material.base_color_texture {
            albedo *= texture_value(ctx, mesh, si, footprint, t).truncate();
        }
        if emission != Vec3::ZERO
            && let Some(t) = &material.emissive_texture
        {
            emission *= texture_value(ctx, mesh, si, footprint, t).truncate();
        }
        if let Some(procedural) = &material.procedural {
            albedo *= procedural_value(ctx, mesh, si, footprint, procedural);
        }
    }
    (albedo, emission)
}

/// Adds a camera ray's first hit to the AOV sums it has (weighted by the sample's filter
/// weight `w`): albedo (0 on unlit back faces), shading normal, and distance (camera ray
/// directions are unit, so `t` is the distance).
#[inline]
pub(super) fn record_first_hit(
    sums: &mut TileSums,
    pixel: usize,
    w: f32,
    lit: bool,
    albedo: Vec3,
    ns: Vec3,
    t: f32,
) {
    if let Some(a) = sums.albedo.get_mut(pixel) {
        *a += if lit { w * albedo } else { Vec3::ZERO };
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

/// The camera ray of sample `sample` of pixel `(x, y)` and its filter weight; pushes the ray's
/// differential to `diffs` when given. Offsets are from the pixel centre and may leave the
/// pixel (wide filters).
#[inline]
pub(super) fn camera_sample(
    ctx: &TileContext<'_>,
    x: u32,
    y: u32,
    sample: u32,
    diffs: Option<&mut Vec<RayDifferential>>,
) -> (Ray, f32) {
    let (offset, weight) = ctx.filter.sample(ctx.sampler.offset(x, y, sample));
    let (fx, fy) = (x as f32 + 0.5 + offset.x, y as f32 + 0.5 + offset.y);
    if let Some(diffs) = diffs {
        diffs.push(
            ctx.camera
                .ray_differential(fx, fy, ctx.differential_spacing),
        );
    }
    (ctx.camera.ray(fx, fy), weight)
}

/// Traces one batch of path rays: camera rays (`primary`) coherently, later rays
/// incoherently, counted by kind; hits the visibility rules reject are replaced by the next
/// accepted one. Returns the coherence used, for the batch's shadow rays.
#[inline]
pub(super) fn trace_batch(
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

/// Traces a batch of shadow rays (with the coherence and identity of the path batch they
/// light) and adds the value of each unblocked one to its pixel; alpha-rejected blockers do
/// not block.
#[inline]
pub(super) fn trace_shadows(
    ctx: &TileContext<'_>,
    rays: &[Ray],
    values: &[(u32, Vec3)],
    occluded: &mut Vec<bool>,
    (coherence, batch): (Coherence, RayBatch),
    counts: &mut RayCounts,
    sums: &mut TileSums,
) {
    if rays.is_empty() {
        return;
    }
    occluded.clear();
    occluded.resize(rays.len(), true);
    ctx.accel.occluded_many(rays, occluded, coherence);
    if let Some(visibility) = &ctx.visibility {
        visibility.resolve_occlusion(ctx, rays, occluded, batch, counts);
    }
    counts.shadow += rays.len() as u64;
    for (&(pixel, value), &blocked) in values.iter().zip(occluded.iter()) {
        if !blocked {
            sums.pending[pixel as usize] += value;
        }
    }
}

/// Shades one hit: records AOVs (camera rays), adds emission, queues the diffuse part for
/// light sampling and the mirror part as a reflection ray.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn shade_hit<
    const TEXTURES: bool,
    const VERTEX_COLORS: bool,
    const SHADING_NORMALS: bool,
    const NORMAL_MAPS: bool,
>(
    ctx: &TileContext<'_>,
    ray: &Ray,
    diff: Option<&RayDifferential>,
    hit: &Hit,
    path: PathVertex,
    primary: bool,
    may_reflect: bool,
    sums: &mut TileSums,
    points: &mut Vec<ShadingPoint>,
    next_rays: &mut Vec<Ray>,
    next_paths: &mut Vec<PathVertex>,
    next_diffs: &mut Vec<RayDifferential>,
) {
    let Some(mesh) = ctx.scene.meshes.get(hit.geom_id as usize) else {
        return;
    };
    let Some(mut si) = SurfaceInteraction::from_hit(mesh, hit, ray.dir) else {
        return;
    };
    let material = &ctx.materials[material_index(mesh.material, ctx.materials.len())];
    if SHADING_NORMALS && let Some(normals) = &mesh.normals {
        si.ns = shading_normal(&si, normals);
    }
    let lit = si.front_face || material.double_sided;

    // The hit's footprint: ∂p/∂x, ∂p/∂y on the tangent plane and the barycentric derivatives.
    let footprint = if TEXTURES {
        diff.and_then(|rd| Footprint::at(mesh, &si, rd))
    } else {
        None
    };
    if NORMAL_MAPS {
        super::normal_maps::apply(ctx, mesh, &mut si, footprint.as_ref(), material);
    }
    let (albedo, emission) =
        surface_colors::<TEXTURES, VERTEX_COLORS>(ctx, mesh, &si, footprint.as_ref(), material);

    let pixel = path.pixel as usize;
    if primary {
        record_first_hit(sums, pixel, path.filter_weight, lit, albedo, si.ns, hit.t);
    }
    if !lit {
        return;
    }
    if material.unlit {
        // KHR_materials_unlit: ρ leaves the surface as radiance; nothing is lit or reflected.
        sums.pending[pixel] += path.throughput * albedo;
        return;
    }
    sums.pending[pixel] += path.throughput * emission;

    let weight = path.throughput
        * Lambert {
            albedo: albedo * material.diffuse_weight,
        }
        .f();
    if weight != Vec3::ZERO {
        points.push(ShadingPoint {
            p: si.p,
            p_error: si.p_error,
            ng: si.ng,
            ns: si.ns,
            pixel: path.pixel,
            weight,
        });
    }
    if may_reflect && material.mirror_weight > 0.0 {
        let throughput = path.throughput * albedo * material.mirror_weight;
        if throughput != Vec3::ZERO {
            let wr = reflect(si.wo, si.ns);
            next_rays.push(spawn_ray(si.p, si.p_error, si.ng, wr));
            if let (Some(rd), Some(f)) = (diff, &footprint) {
                let (dn_dx, dn_dy) = if SHADING_NORMALS {
                    normal_derivatives(mesh, &si, f)
                } else {
                    (Vec3::ZERO, Vec3::ZERO)
                };
                let mirror = MirrorHit {
                    p: si.p,
                    wo: si.wo,
                    ns: si.ns,
                    dn_dx,
                    dn_dy,
                    wi: wr,
                };
                next_diffs.push(differentials::reflect(rd, &mirror, &f.surface));
            }
            next_paths.push(PathVertex {
                pixel: path.pixel,
                throughput,
                filter_weight: path.filter_weight,
            });
        }
    }
}

/// A hit's footprint from its ray differential.
pub(super) struct Footprint {
    /// ∂p/∂x and ∂p/∂y on the tangent plane.
    surface: SurfaceDifferentials,
    /// Barycentric derivatives (∂b₁, ∂b₂) along film x.
    db_dx: Vec2,
    /// Along film y.
    db_dy: Vec2,
}

impl Footprint {
    /// `None` if the triangle's vertices are out of range (the hit is then unfiltered).
    #[inline]
    pub(super) fn at(mesh: &Mesh, si: &SurfaceInteraction, rd: &RayDifferential) -> Option<Self> {
        let triangle = si.world_triangle(mesh)?;
        let surface = differentials::at_surface(rd, si.p, si.ng);
        Some(Self {
            db_dx: barycentric_derivatives(triangle, surface.dp_dx),
            db_dy: barycentric_derivatives(triangle, surface.dp_dy),
            surface,
        })
    }

    /// The derivatives of a per-vertex attribute.
    #[inline]
    fn of<T>(&self, values: &[T], si: &SurfaceInteraction) -> Option<(T, T)>
    where
        T: Copy
            + std::ops::Sub<Output = T>
            + std::ops::Mul<f32, Output = T>
            + std::ops::Add<Output = T>,
    {
        Some((
            attribute_derivative(values, si.vertices, self.db_dx)?,
            attribute_derivative(values, si.vertices, self.db_dy)?,
        ))
    }
}

/// ∂ns/∂x and ∂ns/∂y of the interpolated, normalised (and side-flipped) shading normal.
#[inline]
fn normal_derivatives(mesh: &Mesh, si: &SurfaceInteraction, f: &Footprint) -> (Vec3, Vec3) {
    let Some(normals) = &mesh.normals else {
        return (Vec3::ZERO, Vec3::ZERO);
    };
    let (Some(n), Some((dx, dy))) = (si.interpolate(normals), f.of(normals, si)) else {
        return (Vec3::ZERO, Vec3::ZERO);
    };
    // The normal matrix is linear, so it carries the derivatives along with the normal.
    let (n, dx, dy) = (
        si.normal_to_world(n),
        si.normal_to_world(dx),
        si.normal_to_world(dy),
    );
    let sign = if si.front_face { 1.0 } else { -1.0 };
    (
        sign * differentials::unit_normal_derivative(n, dx),
        sign * differentials::unit_normal_derivative(n, dy),
    )
}

/// Texture coordinates of set `set` at the hit and their footprint (zero without
/// differentials). A mesh without the set reads at (0, 0).
#[inline]
fn texcoords(
    mesh: &Mesh,
    si: &SurfaceInteraction,
    footprint: Option<&Footprint>,
    set: usize,
) -> (Vec2, UvFootprint) {
    let Some(uvs) = mesh.texcoords.get(set).and_then(|s| s.as_deref()) else {
        return (Vec2::ZERO, UvFootprint::default());
    };
    let uv = si.interpolate(uvs).unwrap_or(Vec2::ZERO);
    let duv = footprint
        .and_then(|f| f.of(uvs, si))
        .map(|(duv_dx, duv_dy)| UvFootprint { duv_dx, duv_dy })
        .unwrap_or_default();
    (uv, duv)
}

/// The texture's value at the hit: interpolated texture coordinates and their footprint, the
/// texture transform applied to both, then a filtered lookup.
#[inline]
pub(super) fn texture_value(
    ctx: &TileContext<'_>,
    mesh: &Mesh,
    si: &SurfaceInteraction,
    footprint: Option<&Footprint>,
    t: &TextureRef,
) -> Vec4 {
    let (uv, duv) = texcoords(mesh, si, footprint, t.texcoord);
    let m = t.transform.matrix2;
    let duv = UvFootprint {
        duv_dx: m * duv.duv_dx,
        duv_dy: m * duv.duv_dy,
    };
    match ctx.mipmaps.get(t.texture) {
        Some(mip) => crate::texture::lookup(
            mip,
            t.transform.transform_point2(uv),
            &duv,
            ctx.texture_filter,
        ),
        // No MIP chain (a caller built the context without one): the base level.
        None => match ctx.scene.textures.get(t.texture) {
            Some(texture) => texture::sample(texture, t.transform.transform_point2(uv)),
            None => Vec4::ONE,
        },
    }
}

/// A procedural texture's colour at the hit, band-limited as the filter asks.
#[inline]
pub(super) fn procedural_value(
    ctx: &TileContext<'_>,
    mesh: &Mesh,
    si: &SurfaceInteraction,
    footprint: Option<&Footprint>,
    procedural: &ProceduralTexture,
) -> Vec3 {
    let band = match ctx.texture_filter {
        TextureFilter::Nearest | TextureFilter::Bilinear | TextureFilter::Bicubic => Band::Point,
        TextureFilter::Trilinear => Band::Isotropic,
        TextureFilter::Anisotropic => Band::Anisotropic,
    };
    let (p, dx, dy) = match procedural.domain {
        Domain::Uv(set) => {
            let (uv, duv) = texcoords(mesh, si, footprint, set);
            (
                uv.extend(0.0),
                duv.duv_dx.extend(0.0),
                duv.duv_dy.extend(0.0),
            )
        }
        Domain::World => match footprint {
            Some(f) => (si.p, f.surface.dp_dx, f.surface.dp_dy),
            None => (si.p, Vec3::ZERO, Vec3::ZERO),
        },
    };
    procedural.color(p, dx, dy, band)
}

/// Where new shadow rays go.
struct ShadowBatch<'a> {
    rays: &'a mut Vec<Ray>,
    values: &'a mut Vec<(u32, Vec3)>,
    counts: &'a mut RayCounts,
}

/// Queues one shadow ray per (light, point) pair that can contribute, lights in the outer loop
/// so that consecutive rays (one packet) share a light and neighbouring origins.
#[inline]
fn add_shadow_rays<L: PunctualLight>(lights: &[L], points: &[ShadingPoint], b: &mut ShadowBatch) {
    for light in lights {
        for sp in points {
            let Incident {
                wi,
                irradiance,
                target,
            } = match light.incident(sp.p) {
                Ok(incident) => incident,
                Err(Unlit::OutsideCone) => {
                    b.counts.skipped_outside_cone += 1;
                    continue;
                }
                Err(Unlit::BeyondRange) => {
                    b.counts.skipped_beyond_range += 1;
                    continue;
                }
                Err(Unlit::AtLight) => {
                    b.counts.skipped_facing_away += 1;
                    continue;
                }
            };
            // Below the geometric horizon: the light cannot reach this side of the surface,
            // whatever the shading normal says (no light leaks).
            let cos_shading = sp.ns.dot(wi);
            if sp.ng.dot(wi) <= 0.0 || cos_shading <= 0.0 {
                b.counts.skipped_facing_away += 1;
                continue;
            }
            let ray = match target {
                ShadowTarget::Point(position) => spawn_ray_to(sp.p, sp.p_error, sp.ng, position),
                ShadowTarget::Infinity => spawn_ray(sp.p, sp.p_error, sp.ng, wi),
            };
            b.rays.push(ray);
            b.values
                .push((sp.pixel, sp.weight * irradiance * cos_shading));
        }
    }
}
