//! Which hits a ray sees: alpha coverage (glTF `alphaMode`) and back-face culling of
//! single-sided materials.
//!
//! The ray backends report every triangle. This module decides, in Rust and so identically
//! for Embree and the BVH, whether a reported hit counts, and if not finds the next one:
//!
//! - **Alpha.** The coverage at a hit is α = baseColorFactor.a × baseColorTexture.a ×
//!   COLOR_0.a. OPAQUE hits always count. MASK hits count where α ≥ alphaCutoff. BLEND hits
//!   count with probability α: the hit is kept when a uniform number u satisfies u < α. A
//!   surface of coverage α therefore passes, on average, exactly the fraction 1 − α of
//!   whatever lies behind it and shows itself with weight α: the expectation of the random
//!   choice is alpha blending (`α · surface + (1 − α) · behind`), so the estimate stays
//!   unbiased, for camera, bounce and shadow rays alike.
//! - **Culling.** Camera rays skip back faces of single-sided materials (glTF: "back-face
//!   culling is enabled, i.e., only front-facing triangles are rendered"), so the camera
//!   sees what lies behind them. Bounce and shadow rays do not: a back face stops them and
//!   is shaded as the side it was hit from (its BSDF with the normals turned toward the ray,
//!   as for a double-sided material; it emits nothing, see `material::at_hit`). Culling them
//!   too would make visibility depend on the direction a ray is traced: the surface would
//!   block light crossing it one way and pass it the other, so V(x, y) ≠ V(y, x), and light
//!   sampling (rays from the shading point to the light) and any estimator tracing the other
//!   way would disagree. Keeping it opaque is reciprocal and costs shadow rays nothing;
//!   shading it (rather than absorbing) keeps an open single-sided mesh energy-conserving in
//!   a white furnace, and is what Blender Cycles, pbrt and Mitsuba do with a back face they
//!   hit. The visible consequence: a culled surface still casts its shadow
//!   (TextureSettingsTest's single-sided cell shows the check behind the culled quad in that
//!   quad's shadow).
//!
//! **Continuing past a rejected hit.** The same ray is traced again with `tnear` moved past
//! the rejected hit: origin and direction are unchanged, so the interval still ends where it
//! did (a shadow segment keeps its `tfar`) and nothing before the rejected hit can reappear.
//! The new `tnear` lies a relative gap [`REJECT_GAP`] (2⁻²⁰, eight ulps) beyond the rejected
//! `t`, not one ulp: a backend decides `tnear < t` on the scaled distance `T > |det|·tnear`
//! before dividing, and Embree divides with an approximate reciprocal whose rounding differs
//! by kernel and CPU, so the rejected triangle itself can pass that test again while its
//! reported `t` rounds to just below the new `tnear` (one ulp of progress then never gets past
//! it, and the ray would end on the rejected face after [`MAX_LAYERS`] tries). Should the
//! backend still report the same triangle again, the gap doubles. The gap also settles the
//! edges of closed surfaces: a ray through an edge or vertex shared by several back faces is
//! culled on all of them, and a front face that meets a culled back face at the same point (a
//! silhouette edge) is not shown through it. A surface closer than the gap behind a rejected
//! one (a relative 10⁻⁶ of the distance: coincident faces) is passed with it. A ray gives up
//! after [`MAX_LAYERS`] rejected hits: it is stopped there by an alpha-tested surface, and
//! sees nothing if the last rejected hit was a culled back face.
//!
//! **Shadow rays** are first asked the backend's cheap any-hit question; only the rays it
//! finds blocked are traced again closest hit first, until an accepted hit (blocked) or none
//! within `tfar` (visible). Scenes without MASK or BLEND materials never do this.
//!
//! **Texture lookups** read baseColorTexture.a at the hit's texture coordinates on the base
//! MIP level with the texture's magnification filter (the shading's lookup with a zero
//! footprint): no footprint is used. Thresholding a prefiltered α erodes thin cut-outs (leaves,
//! fences) at a distance; point lookups per sample leave the antialiasing to the pixel's
//! samples, which average the coverage correctly.
//!
//! **Random numbers for BLEND** are a hash of the render seed, the tile, the sample index, the
//! depth and kind of the ray batch, the ray's index in its batch, and the geometry and
//! primitive of the hit: deterministic, so images are byte-identical for any thread count,
//! and independent between rays and between the surfaces one ray crosses.
//!
//! Emitters are light-sampled with their coverage: [`Visibility::emitter_coverage`] (α for
//! BLEND, 0 or 1 for MASK) scales a sampled point's radiance, the expected value of what a
//! BSDF-sampled ray that hits it finds.

use super::sampler::mix64;
use super::stats::RayCounts;
use super::tiles::Tile;
use super::wavefront::TileContext;
use crate::accel::{Hit, Ray};
use crate::geometry::SurfaceInteraction;
use crate::scene::{AlphaMode, Material, Mesh, Scene, TextureRef};
use crate::texture::TextureEvaluator;
use std::cmp::Ordering;

/// Most hits one ray may reject before it keeps the last one (a ray through more alpha layers
/// than this is treated as stopped there).
pub const MAX_LAYERS: u32 = 1024;

/// How far past a rejected hit, relative to its distance, a re-trace starts (see the module
/// documentation): 2⁻²⁰, eight ulps of an f32, beyond the few ulps by which two kernels'
/// distances to the same triangle differ.
pub const REJECT_GAP: f32 = 1.0 / (1u32 << 20) as f32;

/// Which kind of ray a batch holds (part of the BLEND random numbers' identity).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum RayKind {
    /// Camera rays (back faces of single-sided materials are culled).
    Camera,
    /// Bounce or mirror rays.
    Bounce,
    /// Shadow rays.
    Shadow,
}

/// Where a batch of rays comes from: the identity its BLEND random numbers are derived from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct RayBatch {
    /// The tile's top-left pixel.
    pub x0: u32,
    /// See [`RayBatch::x0`].
    pub y0: u32,
    /// The sample index of every path in the batch.
    pub sample: u32,
    /// The depth of the batch's rays (0 = camera rays and their shadow rays).
    pub depth: u32,
}

impl RayBatch {
    /// The batch of sample `sample` at depth `depth` in `tile`.
    #[inline]
    pub(crate) fn new(tile: &Tile, sample: u32, depth: u32) -> Self {
        Self {
            x0: tile.x0,
            y0: tile.y0,
            sample,
            depth,
        }
    }

    /// A 64-bit key for the batch's rays of `kind` under render seed `seed`.
    #[inline]
    fn key(&self, seed: u64, kind: RayKind) -> u64 {
        let kind = match kind {
            RayKind::Camera => 1u64,
            RayKind::Bounce => 2,
            RayKind::Shadow => 3,
        };
        let mut h = mix64(seed ^ 0x243F_6A88_85A3_08D3);
        for word in [
            u64::from(self.x0) | (u64::from(self.y0) << 32),
            u64::from(self.sample) | (u64::from(self.depth) << 32),
            kind,
        ] {
            h = mix64(h ^ word);
        }
        h
    }
}

/// How a surface's coverage decides its hits.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Coverage {
    /// Every hit counts (OPAQUE, or a MASK or BLEND whose constant α lets everything count).
    Opaque,
    /// Hits count where α ≥ `cutoff`.
    Mask { cutoff: f32 },
    /// Hits count with probability α.
    Blend,
}

/// What the tests need to know about one mesh (geometry id).
#[derive(Clone, Copy, Debug, PartialEq)]
struct SurfaceRule {
    /// Camera rays cull its back faces.
    cull: bool,
    coverage: Coverage,
    /// baseColorFactor.a.
    factor: f32,
    /// The base colour texture, whose alpha channel multiplies α.
    texture: Option<TextureRef>,
    /// COLOR_0.a multiplies α (the mesh has vertex colours).
    vertex_alpha: bool,
}

impl SurfaceRule {
    /// Whether a hit on this surface may be rejected (by a camera ray when `camera`).
    #[inline]
    fn tests(&self, camera: bool) -> bool {
        self.coverage != Coverage::Opaque || (camera && self.cull)
    }
}

/// The per-mesh rules of one render, and the seed of its BLEND decisions.
#[derive(Clone, Debug)]
pub(crate) struct Visibility {
    rules: Vec<SurfaceRule>,
    /// Some mesh has MASK or BLEND coverage: shadow rays need the exact test.
    alpha: bool,
    /// Some mesh is single-sided: camera hits need the face test.
    cull: bool,
    seed: u64,
}

impl Visibility {
    /// The rules for `scene`'s meshes: alpha tests when `alpha`, camera culling when `cull`
    /// (the kernel flags), BLEND decisions seeded by the render's `seed`. `None` when no hit
    /// of the scene can be rejected, so such renders do no per-hit test at all.
    pub(crate) fn new(scene: &Scene, alpha: bool, cull: bool, seed: u64) -> Option<Self> {
        let default = Material::default();
        let rules: Vec<SurfaceRule> = scene
            .meshes
            .iter()
            .map(|mesh| {
                // Out-of-range material indices shade with glTF's default material (see
                // `material_index`), which is opaque and single-sided.
                let material = scene.materials.get(mesh.material).unwrap_or(&default);
                rule(mesh, material, scene.textures.len(), alpha, cull)
            })
            .collect();
        let alpha = rules.iter().any(|r| r.coverage != Coverage::Opaque);
        let cull = rules.iter().any(|r| r.cull);
        (alpha || cull).then_some(Self {
            rules,
            alpha,
            cull,
            seed,
        })
    }

    /// Whether some hit is alpha-tested.
    pub(crate) fn tests_alpha(&self) -> bool {
        self.alpha
    }

    /// Whether camera rays cull some back faces.
    pub(crate) fn culls(&self) -> bool {
        self.cull
    }

    /// Replaces every hit in `hits` (the backend's answers for `rays`) that the rules reject
    /// by the first accepted hit behind it, or by a miss.
    pub(crate) fn resolve_hits(
        &self,
        ctx: &TileContext<'_>,
        rays: &[Ray],
        hits: &mut [Option<Hit>],
        kind: RayKind,
        batch: RayBatch,
        counts: &mut RayCounts,
    ) {
        let camera = kind == RayKind::Camera;
        if !self.alpha && !camera {
            return;
        }
        let key = batch.key(self.seed, kind);
        for (index, (ray, slot)) in rays.iter().zip(hits.iter_mut()).enumerate() {
            let Some(hit) = *slot else {
                continue;
            };
            if !self.rule(&hit).is_some_and(|r| r.tests(camera)) {
                continue;
            }
            *slot = self.first_accepted(ctx, ray, hit, camera, ray_key(key, index), counts);
        }
    }

    /// Re-checks the shadow rays the backend found blocked: a ray stays blocked only if some
    /// hit within its interval is accepted.
    pub(crate) fn resolve_occlusion(
        &self,
        ctx: &TileContext<'_>,
        rays: &[Ray],
        occluded: &mut [bool],
        batch: RayBatch,
        counts: &mut RayCounts,
    ) {
        if !self.alpha {
            return;
        }
        let key = batch.key(self.seed, RayKind::Shadow);
        for (index, (ray, blocked)) in rays.iter().zip(occluded.iter_mut()).enumerate() {
            if !*blocked {
                continue;
            }
            counts.retraced += 1;
            *blocked = match ctx.accel.intersect(ray) {
                Some(hit) => self
                    .first_accepted(ctx, ray, hit, false, ray_key(key, index), counts)
                    .is_some(),
                None => false,
            };
        }
    }

    /// The expected coverage of the emitter point `si` on mesh `geom`: what a light sample
    /// there is scaled by, to match what BSDF-sampled rays see on average (α for BLEND, 0 or 1
    /// for MASK, 1 for opaque surfaces).
    pub(crate) fn emitter_coverage(
        &self,
        ctx: &TileContext<'_>,
        geom: u32,
        si: &SurfaceInteraction,
    ) -> f32 {
        let (Some(rule), Some(mesh)) = (
            self.rules.get(geom as usize),
            ctx.scene.meshes.get(geom as usize),
        ) else {
            return 1.0;
        };
        match rule.coverage {
            Coverage::Opaque => 1.0,
            Coverage::Mask { cutoff } => {
                if alpha_at(&ctx.textures(), rule, mesh, si) >= cutoff {
                    1.0
                } else {
                    0.0
                }
            }
            Coverage::Blend => alpha_at(&ctx.textures(), rule, mesh, si).clamp(0.0, 1.0),
        }
    }

    /// Whether the camera ray `rays_index` of `batch` would accept `hit` (one of the hits
    /// along it, not necessarily the first): the same culling and alpha decision, BLEND's
    /// random number included, that [`Visibility::resolve_hits`] makes for that ray. Amodal
    /// coverage ([`super::amodal`]) asks it of every surface a camera ray pierces.
    pub(crate) fn camera_accepts(
        &self,
        ctx: &TileContext<'_>,
        ray: &Ray,
        hit: &Hit,
        batch: RayBatch,
        ray_index: usize,
    ) -> bool {
        if !self.rule(hit).is_some_and(|r| r.tests(true)) {
            return true;
        }
        let key = ray_key(batch.key(self.seed, RayKind::Camera), ray_index);
        self.accepts(ctx, ray, hit, true, key)
    }

    #[inline]
    fn rule(&self, hit: &Hit) -> Option<&SurfaceRule> {
        self.rules.get(hit.geom_id as usize)
    }

    /// Starting from the backend's hit `hit` of `ray`, the first hit the rules accept, tracing
    /// on past rejected ones (see the module documentation).
    fn first_accepted(
        &self,
        ctx: &TileContext<'_>,
        ray: &Ray,
        hit: Hit,
        camera: bool,
        key: u64,
        counts: &mut RayCounts,
    ) -> Option<Hit> {
        let accepts = |ray: &Ray, hit: &Hit| self.accepts(ctx, ray, hit, camera, key);
        let culled = |ray: &Ray, hit: &Hit| self.culled(ray, hit, camera);
        let retrace = |ray: &Ray| ctx.accel.intersect(ray);
        first_accepted_with(ray, hit, accepts, culled, retrace, &mut counts.retraced)
    }

    /// Whether camera-ray culling rejects `hit`: a back face of a single-sided material, the
    /// ray travelling along the geometric normal (the shading's `front_face` is
    /// `dot(ng, −dir) > 0`; the edge-on case counts as a back face there too).
    #[inline]
    fn culled(&self, ray: &Ray, hit: &Hit, camera: bool) -> bool {
        camera
            && self
                .rule(hit)
                .is_some_and(|rule| rule.cull && hit.ng.dot(ray.dir) >= 0.0)
    }

    /// Whether `hit` of `ray` counts.
    #[inline]
    fn accepts(&self, ctx: &TileContext<'_>, ray: &Ray, hit: &Hit, camera: bool, key: u64) -> bool {
        self.accepts_in(ctx.scene, &ctx.textures(), ray, hit, camera, key)
    }

    /// [`Self::accepts`] with the scene and texture lookups given, not a tile's context.
    fn accepts_in(
        &self,
        scene: &Scene,
        textures: &TextureEvaluator<'_>,
        ray: &Ray,
        hit: &Hit,
        camera: bool,
        key: u64,
    ) -> bool {
        let Some(rule) = self.rule(hit) else {
            return true;
        };
        if self.culled(ray, hit, camera) {
            return false;
        }
        if rule.coverage == Coverage::Opaque {
            return true;
        }
        let Some(mesh) = scene.meshes.get(hit.geom_id as usize) else {
            return true;
        };
        // A hit the shading cannot use (degenerate triangle) keeps today's behaviour: it
        // stops the ray and renders black.
        let Some(si) = SurfaceInteraction::from_hit(mesh, hit, ray.dir) else {
            return true;
        };
        let alpha = alpha_at(textures, rule, mesh, &si);
        match rule.coverage {
            Coverage::Opaque => true,
            Coverage::Mask { cutoff } => alpha >= cutoff,
            Coverage::Blend => alpha >= 1.0 || (alpha > 0.0 && blend_uniform(key, hit) < alpha),
        }
    }

    /// The first hit a camera ray accepts along `ray`, starting from the backend's `hit`,
    /// for a ray traced outside a render (the flow's visibility ray in the scene at another
    /// time, `scene` with its ray queries `accel`): the same culling and alpha rules, alpha
    /// read through `textures` without a footprint, BLEND decided with key 0.
    pub(crate) fn first_camera_hit(
        &self,
        scene: &Scene,
        textures: &TextureEvaluator<'_>,
        accel: &dyn crate::accel::Accel,
        ray: &Ray,
        hit: Hit,
    ) -> Option<Hit> {
        if !self.rule(&hit).is_some_and(|r| r.tests(true)) {
            return Some(hit);
        }
        let accepts = |ray: &Ray, hit: &Hit| self.accepts_in(scene, textures, ray, hit, true, 0);
        let culled = |ray: &Ray, hit: &Hit| self.culled(ray, hit, true);
        let retrace = |ray: &Ray| accel.intersect(ray);
        let mut retraced = 0;
        first_accepted_with(ray, hit, accepts, culled, retrace, &mut retraced)
    }
}

/// The loop of [`Visibility::first_accepted`] over its three questions (does a hit count, is
/// it a culled back face, what does the backend find behind a `tnear`), apart so that it can
/// be tested against a backend that rounds as badly as any kernel may. `retraced` counts the
/// re-traces.
pub(crate) fn first_accepted_with(
    ray: &Ray,
    mut hit: Hit,
    accepts: impl Fn(&Ray, &Hit) -> bool,
    culled: impl Fn(&Ray, &Hit) -> bool,
    retrace: impl Fn(&Ray) -> Option<Hit>,
    retraced: &mut u64,
) -> Option<Hit> {
    let mut ray = *ray;
    let mut gap = REJECT_GAP;
    let mut rejected: Option<(u32, u32, u32)> = None;
    for _ in 0..MAX_LAYERS {
        if accepts(&ray, &hit) {
            return Some(hit);
        }
        let id = (hit.geom_id, hit.prim_id, hit.instance);
        if rejected == Some(id) {
            // The backend found the rejected triangle again: its distance rounds below the
            // gap. Widen it until the re-trace gets past (at most ~20 doublings).
            gap = (gap * 2.0).min(1.0);
        }
        rejected = Some(id);
        ray.tnear = (hit.t.max(ray.tnear) * (1.0 + gap)).next_up();
        // `tnear > tfar`, or a NaN bound: nothing left to find.
        if !matches!(
            ray.tnear.partial_cmp(&ray.tfar),
            Some(Ordering::Less | Ordering::Equal)
        ) {
            return None;
        }
        *retraced += 1;
        hit = retrace(&ray)?;
    }
    (!culled(&ray, &hit)).then_some(hit)
}

/// The rule of `mesh` with `material`; constant coverages that let every hit through become
/// [`Coverage::Opaque`], so they cost nothing per hit.
fn rule(
    mesh: &Mesh,
    material: &Material,
    texture_count: usize,
    alpha: bool,
    cull: bool,
) -> SurfaceRule {
    let texture = material
        .base_color_texture
        .filter(|t| t.texture < texture_count);
    let vertex_alpha = mesh.colors.is_some();
    let factor = material.base_color.w;
    let varies = texture.is_some() || vertex_alpha;
    let coverage = match (alpha, material.alpha) {
        (false, _) | (_, AlphaMode::Opaque) => Coverage::Opaque,
        (true, AlphaMode::Mask { cutoff }) if !varies && factor >= cutoff => Coverage::Opaque,
        (true, AlphaMode::Mask { cutoff }) => Coverage::Mask { cutoff },
        (true, AlphaMode::Blend) if !varies && factor >= 1.0 => Coverage::Opaque,
        (true, AlphaMode::Blend) => Coverage::Blend,
    };
    SurfaceRule {
        cull: cull && !material.double_sided,
        coverage,
        factor,
        texture,
        vertex_alpha,
    }
}

/// α at the surface point `si` of `mesh`.
#[inline]
fn alpha_at(
    textures: &TextureEvaluator<'_>,
    rule: &SurfaceRule,
    mesh: &Mesh,
    si: &SurfaceInteraction,
) -> f32 {
    let mut alpha = rule.factor;
    if rule.vertex_alpha
        && let Some(colors) = &mesh.colors
    {
        alpha *= si.interpolate(colors).map_or(1.0, |c| c.w);
    }
    if let Some(t) = &rule.texture {
        let at = crate::texture::TexturePoint {
            mesh,
            si,
            footprint: None,
        };
        alpha *= textures.value(&at, t).w;
    }
    alpha
}

/// The key of ray `index` of a batch with key `batch`.
#[inline]
fn ray_key(batch: u64, index: usize) -> u64 {
    mix64(batch ^ (index as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15))
}

/// The uniform number in `[0, 1)` that decides a BLEND hit of the ray with key `key`: a hash
/// of the ray and the triangle hit.
#[inline]
fn blend_uniform(key: u64, hit: &Hit) -> f32 {
    let surface = u64::from(hit.geom_id) | (u64::from(hit.prim_id) << 32);
    // Copies of a placed mesh decide independently; copy 0 (every unplaced mesh) hashes as
    // before.
    let copy = u64::from(hit.instance).wrapping_mul(0xD1B5_4A32_D192_ED03);
    let h = mix64(key ^ mix64(surface) ^ copy);
    // The top 24 bits: every f32 in [0, 1) of spacing 2⁻²⁴, never 1.
    (h >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A backend over surfaces along one ray, as a kernel with an approximate reciprocal
    /// answers: it accepts a surface whose true distance `d` passes `tnear < d·(1 + 2⁻²¹)`
    /// (the scaled test, rounded generously) and reports `t` three ulps short of `d`.
    fn sloppy_backend(surfaces: &[(f32, u32, bool)]) -> impl Fn(&Ray) -> Option<Hit> + '_ {
        move |ray: &Ray| {
            surfaces
                .iter()
                .filter(|(d, _, _)| ray.tnear < d * (1.0 + 1.0 / (1u32 << 21) as f32))
                .filter(|(d, _, _)| *d <= ray.tfar)
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map(|&(d, prim, front)| Hit {
                    t: f32::from_bits(d.to_bits() - 3),
                    geom_id: 0,
                    prim_id: prim,
                    instance: 0,
                    u: 0.0,
                    v: 0.0,
                    ng: if front { Vec3::Z } else { Vec3::NEG_Z },
                })
        }
    }

    /// Camera-ray culling over [`sloppy_backend`]: the ray travels along −z, so a hit whose
    /// normal is −z is a back face.
    fn resolve(surfaces: &[(f32, u32, bool)]) -> (Option<Hit>, u64) {
        let ray = Ray::new(Vec3::ZERO, Vec3::NEG_Z);
        let culled = |ray: &Ray, hit: &Hit| hit.ng.dot(ray.dir) >= 0.0;
        let backend = sloppy_backend(surfaces);
        let first = backend(&ray).expect("a first hit");
        let mut retraced = 0;
        let hit = first_accepted_with(
            &ray,
            first,
            |r, h| !culled(r, h),
            culled,
            backend,
            &mut retraced,
        );
        (hit, retraced)
    }

    #[test]
    fn a_culled_face_is_passed_even_when_the_backend_rounds_its_distance_short() {
        // One back face: before the gap, one-ulp steps never got past the reported t (three
        // ulps short) and the ray kept the culled face after MAX_LAYERS re-traces.
        let (hit, retraced) = resolve(&[(2.0, 0, false)]);
        assert_eq!(hit, None);
        assert!(retraced <= 2, "{retraced} re-traces");
    }

    #[test]
    fn edges_and_vertices_of_back_faces_are_culled_on_every_face() {
        // A ray through an edge (two faces) or a vertex (six faces) of a closed surface seen
        // from inside: all back faces at one point.
        let vertex: Vec<_> = (0..6).map(|prim| (3.0, prim, false)).collect();
        assert_eq!(resolve(&vertex[..2]).0, None);
        assert_eq!(resolve(&vertex).0, None);
        // A front face meeting a culled back face at the same point (a silhouette edge) is
        // not shown through it; one a little further is.
        assert_eq!(resolve(&[(3.0, 0, false), (3.0, 1, true)]).0, None);
        let further = resolve(&[(3.0, 0, false), (3.01, 1, true)]).0.expect("hit");
        assert_eq!(further.prim_id, 1);
    }

    #[test]
    fn blend_uniforms_are_uniform_and_depend_on_ray_and_triangle() {
        // 64 bins over 2¹⁶ keys: χ² with 63 degrees of freedom stays below 110 with
        // probability > 0.9998.
        let n = 1 << 16;
        let mut bins = [0u32; 64];
        let batch = RayBatch {
            x0: 16,
            y0: 32,
            sample: 3,
            depth: 1,
        }
        .key(7, RayKind::Shadow);
        let hit = |prim| Hit {
            t: 1.0,
            geom_id: 2,
            prim_id: prim,
            u: 0.0,
            v: 0.0,
            ng: glam::Vec3::Z,
            instance: 0,
        };
        for i in 0..n {
            let u = blend_uniform(ray_key(batch, i), &hit(5));
            assert!((0.0..1.0).contains(&u));
            bins[(u * 64.0) as usize] += 1;
        }
        let expected = n as f64 / 64.0;
        let chi2: f64 = bins
            .iter()
            .map(|&b| (b as f64 - expected).powi(2) / expected)
            .sum();
        assert!(chi2 < 110.0, "chi2 {chi2}");
        // Another triangle, another kind or another sample gives another number.
        let k = ray_key(batch, 0);
        assert_ne!(blend_uniform(k, &hit(5)), blend_uniform(k, &hit(6)));
        let other = RayBatch {
            x0: 16,
            y0: 32,
            sample: 4,
            depth: 1,
        };
        assert_ne!(other.key(7, RayKind::Shadow), batch);
        assert_ne!(
            RayBatch {
                x0: 16,
                y0: 32,
                sample: 3,
                depth: 1
            }
            .key(7, RayKind::Bounce),
            batch
        );
    }

    #[test]
    fn constant_coverage_that_hides_nothing_is_opaque() {
        let mesh = Mesh::default();
        let with = |alpha, a| Material {
            alpha,
            base_color: glam::Vec4::new(1.0, 1.0, 1.0, a),
            double_sided: true,
            ..Material::default()
        };
        let cov = |m: &Material| rule(&mesh, m, 0, true, true).coverage;
        assert_eq!(cov(&with(AlphaMode::Blend, 1.0)), Coverage::Opaque);
        assert_eq!(cov(&with(AlphaMode::Blend, 0.5)), Coverage::Blend);
        let mask = |c| AlphaMode::Mask { cutoff: c };
        assert_eq!(cov(&with(mask(0.5), 0.5)), Coverage::Opaque);
        assert_eq!(cov(&with(mask(0.5), 0.4)), Coverage::Mask { cutoff: 0.5 });
        assert_eq!(cov(&with(AlphaMode::Opaque, 0.0)), Coverage::Opaque);
        // With the alpha flag off nothing is tested; single-sided materials cull.
        assert_eq!(
            rule(&mesh, &with(AlphaMode::Blend, 0.5), 0, false, true).coverage,
            Coverage::Opaque
        );
        assert!(rule(&mesh, &Material::default(), 0, true, true).cull);
        assert!(!rule(&mesh, &with(AlphaMode::Opaque, 1.0), 0, true, true).cull);
    }
}
