//! Geometric ground truth from the pixel-centre ray: `z`, `position`, `uv` and the optical
//! flow `flow` / `flow_backward` (see `docs/ground-truth.md`).
//!
//! Like the ID AOVs ([`super::ids`]), these come from one ray per pixel through its centre,
//! traced in the first pass apart from the samples, with the camera rays' visibility rules
//! (alpha cut-outs, culled back faces). Each value is therefore exact at one point, never an
//! average across an edge. The first hit is kept whole ([`Hit`]: mesh, copy, triangle and
//! barycentrics), and the surface point is the barycentric combination of the triangle's
//! world-space corners, so that the same point can be found at another time:
//!
//! - `position`: that point, world space; `z`: its depth along the optical axis
//!   ([`FilmProjection::depth`]); `uv`: TEXCOORD_0 interpolated at it.
//! - `flow` (to `t + Δ`) and `flow_backward` (to `t − Δ`): the same triangle with the same
//!   barycentrics in the scene loaded at the other time (node animation, skin and morph
//!   weights applied there, [`OtherTime`]), projected by the camera at that time, minus the
//!   point's film position now: pixels, x right, y down.
//!
//! Invalid pixels hold NaN: a centre ray that misses (every AOV); a mesh without TEXCOORD_0
//! (`uv`); for flow, a point behind the camera or off the image at the other time, a point
//! another surface hides there (a ray from the other camera to the point hits something
//! else more than [`OCCLUSION_TOLERANCE`] of the distance in front of it), or a scene whose
//! meshes do not correspond at the two times.

pub use super::aov::GeometricSelection;
use super::film::{Aovs, Image, TileSums};
use super::projection::FilmProjection;
use super::stats::RayCounts;
use super::tiles::Tile;
use super::visibility::{RayBatch, RayKind};
use super::wavefront::TileContext;
use crate::accel::{Accel, Coherence, Hit, Ray};
use crate::scene::Scene;
use glam::{DVec2, DVec3, Vec2, Vec3};

/// The relative distance by which another surface must lie in front of a flow point at the
/// other time to hide it: floating-point slack for a ray that ends on the point's own
/// surface (or its neighbour across an edge).
pub const OCCLUSION_TOLERANCE: f64 = 1e-4;

/// The scene at another time, for flow: its meshes (the same meshes and triangles as the
/// rendered scene's, posed at that time), their ray queries (for occlusion) and the camera
/// at that time.
pub struct OtherTime<'a> {
    /// The scene at the other time.
    pub scene: &'a Scene,
    /// Its ray queries.
    pub accel: &'a dyn Accel,
    /// The camera's projection at that time.
    pub projection: &'a FilmProjection,
}

/// Traces the ray through the centre of each of `tile`'s pixels with the camera rays'
/// visibility rules and keeps its first hit in `sums.centre_hits`.
pub(super) fn trace_centre_hits(
    ctx: &TileContext<'_>,
    tile: &Tile,
    sums: &mut TileSums,
    counts: &mut RayCounts,
) {
    let (rays, mut hits) = ctx.trace_pixel_centres(tile);
    if let Some(visibility) = &ctx.visibility {
        // A batch identity no sample uses, so BLEND surfaces decide the same way for any
        // sample count.
        let batch = RayBatch::new(tile, u32::MAX, 0);
        visibility.resolve_hits(ctx, &rays, &mut hits, RayKind::Camera, batch, counts);
    }
    counts.camera += rays.len() as u64;
    sums.centre_hits = hits;
}

/// The world-space point of `hit` in `scene`: the barycentric combination of its triangle's
/// corners (`None` if the hit names no triangle of the scene).
pub fn hit_point(scene: &Scene, hit: &Hit) -> Option<DVec3> {
    let mesh = scene.meshes.get(hit.geom_id as usize)?;
    let vertices = *mesh.indices.get(hit.prim_id as usize)?;
    let [a, b, c] = mesh
        .world_triangle(hit.instance, vertices)?
        .map(|p| p.as_dvec3());
    let (u, v) = (f64::from(hit.u), f64::from(hit.v));
    Some(a * (1.0 - u - v) + b * u + c * v)
}

/// TEXCOORD_0 at `hit`, if its mesh has it.
fn hit_uv(scene: &Scene, hit: &Hit) -> Option<Vec2> {
    let mesh = scene.meshes.get(hit.geom_id as usize)?;
    let uvs = mesh.texcoords[0].as_ref()?;
    let [a, b, c] = *mesh.indices.get(hit.prim_id as usize)?;
    let corner = |i: u32| uvs.get(i as usize).copied();
    let (u, v) = (hit.u, hit.v);
    Some(corner(a)? * (1.0 - u - v) + corner(b)? * u + corner(c)? * v)
}

/// Whether `other`'s meshes correspond to `scene`'s one to one: the same count, and each the
/// same triangles and copies (only positions and placements may differ).
pub fn meshes_correspond(scene: &Scene, other: &Scene) -> bool {
    scene.meshes.len() == other.meshes.len()
        && scene.meshes.iter().zip(&other.meshes).all(|(a, b)| {
            a.indices == b.indices
                && a.positions.len() == b.positions.len()
                && a.copies() == b.copies()
        })
}

/// Fills `aovs`' geometric images from its centre hits (`aovs.centre_hits`, which the render
/// kept because a geometric AOV was selected): `scene` and `projection` are what was
/// rendered, `forward` and `backward` the scene at `t ± Δ` for the flows selected.
pub fn resolve(
    aovs: &mut Aovs,
    selection: GeometricSelection,
    scene: &Scene,
    projection: &FilmProjection,
    forward: Option<&OtherTime<'_>>,
    backward: Option<&OtherTime<'_>>,
) {
    let Some(hits) = aovs.centre_hits.as_ref() else {
        return;
    };
    let (width, height) = (hits.width, hits.height);
    let points: Vec<Option<DVec3>> = hits
        .pixels
        .iter()
        .map(|h| h.and_then(|h| hit_point(scene, &h)))
        .collect();
    fn image<T>(width: u32, height: u32, pixels: Vec<T>) -> Image<T> {
        Image {
            width,
            height,
            pixels,
        }
    }
    if selection.z {
        aovs.z = Some(image(
            width,
            height,
            points
                .iter()
                .map(|p| p.map_or(f32::NAN, |p| projection.camera_point(p).z as f32))
                .collect(),
        ));
    }
    if selection.position {
        aovs.position = Some(image(
            width,
            height,
            points
                .iter()
                .map(|p| p.map_or(Vec3::NAN, |p| p.as_vec3()))
                .collect(),
        ));
    }
    if selection.uv {
        aovs.uv = Some(image(
            width,
            height,
            hits.pixels
                .iter()
                .map(|h| h.and_then(|h| hit_uv(scene, &h)).unwrap_or(Vec2::NAN))
                .collect(),
        ));
    }
    let flow = |other: Option<&OtherTime<'_>>| {
        let pixels = match other {
            Some(other) => flow_to(hits, &points, scene, projection, other),
            None => vec![Vec2::NAN; points.len()],
        };
        image(width, height, pixels)
    };
    if selection.flow {
        aovs.flow = Some(flow(forward));
    }
    if selection.flow_backward {
        aovs.flow_backward = Some(flow(backward));
    }
}

/// The flow of every pixel to the other time (NaN where invalid; see the module doc).
fn flow_to(
    hits: &Image<Option<Hit>>,
    points: &[Option<DVec3>],
    scene: &Scene,
    projection: &FilmProjection,
    other: &OtherTime<'_>,
) -> Vec<Vec2> {
    let mut flow = vec![Vec2::NAN; points.len()];
    if !meshes_correspond(scene, other.scene) {
        return flow;
    }
    // Each valid pixel's film position now and then, its point then, and the ray that
    // checks the point is seen then.
    let mut candidates: Vec<(usize, DVec2, Ray, f64)> = Vec::new();
    for (index, (hit, point)) in hits.pixels.iter().zip(points).enumerate() {
        let (Some(hit), Some(point)) = (hit, point) else {
            continue;
        };
        let Some(now) = projection.film(*point) else {
            continue;
        };
        let Some(then) = hit_point(other.scene, hit) else {
            continue;
        };
        let Some(film) = other.projection.film(then) else {
            continue;
        };
        if !other.projection.on_film(film) {
            continue;
        }
        let to_point = then - other.projection.origin;
        let (origin, distance) = if other.projection.orthographic {
            let depth = other.projection.camera_point(then).z;
            if depth <= 0.0 {
                continue;
            }
            (
                then - other.projection.world_from_camera_cv.z_axis * depth,
                depth,
            )
        } else {
            (other.projection.origin, to_point.length())
        };
        let dir = (then - origin) / distance;
        let ray = Ray::new(origin.as_vec3(), dir.as_vec3());
        candidates.push((index, film - now, ray, distance));
    }
    let rays: Vec<Ray> = candidates.iter().map(|c| c.2).collect();
    let mut seen = vec![None; rays.len()];
    other
        .accel
        .intersect_many(&rays, &mut seen, Coherence::Incoherent);
    // The camera's visibility rules at the other time: an alpha cut-out or a culled back
    // face in front of the point hides nothing, as it hides nothing from the camera.
    let visibility = super::visibility::Visibility::new(other.scene, true, true, 0);
    let textures = crate::texture::TextureEvaluator {
        textures: &other.scene.textures,
        mipmaps: &[],
        filter: crate::texture::TextureFilter::default(),
    };
    for ((index, displacement, ray, distance), seen) in candidates.iter().zip(&seen) {
        let seen = match (&visibility, seen) {
            (Some(v), Some(s)) => v.first_camera_hit(other.scene, &textures, other.accel, ray, *s),
            _ => *seen,
        };
        let hidden = match (&seen, hits.pixels.get(*index).copied().flatten()) {
            (Some(s), Some(h)) => {
                let same =
                    s.geom_id == h.geom_id && s.instance == h.instance && s.prim_id == h.prim_id;
                !same && f64::from(s.t) < distance * (1.0 - OCCLUSION_TOLERANCE)
            }
            _ => false,
        };
        if !hidden && let Some(slot) = flow.get_mut(*index) {
            *slot = displacement.as_vec2();
        }
    }
    flow
}
