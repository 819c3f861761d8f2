//! Ray generators for benchmarks: coherent camera rays and incoherent random rays.
//!
//! Every generator is deterministic (a fixed seed gives the same rays on every machine), so two
//! backends, two builds or two runs always trace the very same rays.

use crate::accel::{Ray, TriangleMesh};
use crate::scene::{Camera, Projection};
use glam::{Mat4, Vec3, vec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use std::f32::consts::TAU;

/// Side of the square pixel tiles camera rays are grouped in. Eight by eight pixels fill
/// Embree's 8-wide packets with neighbours, which is what makes them coherent.
pub const TILE_SIDE_PX: u32 = 8;

/// Vertical field of view of [`framing_camera`]: a common "normal lens" angle.
pub const FRAMING_YFOV_RAD: f32 = std::f32::consts::FRAC_PI_4;

/// Direction from the bounds' centre towards the eye of [`framing_camera`]: to one side and
/// about 40° above the horizon, so that no face of a box-like scene is seen edge-on and a flat
/// terrain (in x–z) fills much of the view rather than a thin sliver.
const FRAMING_EYE_DIRECTION: Vec3 = vec3(0.6, 1.0, 1.0);

/// Distance of [`framing_camera`] from points that all lie at the centre (a single point), so
/// that the camera still has a position distinct from what it looks at.
const DEGENERATE_DISTANCE: f32 = 1.0;

/// An axis-aligned box in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Bounds {
    /// Bounds of all vertex positions of `meshes` (used by a triangle or not, as in
    /// [`crate::scene::Scene::bounds`]); `None` without vertices.
    pub fn of_meshes(meshes: &[TriangleMesh<'_>]) -> Option<Self> {
        let mut points = meshes.iter().flat_map(|m| m.positions.iter().copied());
        let first = points.next()?;
        let (min, max) = points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)));
        Some(Self { min, max })
    }

    /// The centre of the box.
    pub fn centre(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// The eight corners of the box.
    pub fn corners(&self) -> impl Iterator<Item = Vec3> + '_ {
        (0..8).map(move |i| {
            vec3(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            )
        })
    }

    /// Length of the box's diagonal, in scene units.
    pub fn diagonal_length(&self) -> f32 {
        (self.max - self.min).length()
    }
}

/// A pinhole camera that looks at the centre of `bounds` from [`FRAMING_EYE_DIRECTION`], with
/// the vertical field of view [`FRAMING_YFOV_RAD`], from the smallest distance at which all
/// of `points` lie within that angle of the axis both vertically and horizontally (so a square
/// or wider image shows them all). Pass [`Bounds::corners`] to frame the whole box, or the
/// scene's vertices to frame the geometry as tightly as this view allows (a sphere's box
/// corners lie well outside its silhouette). The aspect ratio is left to the image.
pub fn framing_camera(bounds: &Bounds, points: impl IntoIterator<Item = Vec3>) -> Camera {
    let centre = bounds.centre();
    let towards_eye = FRAMING_EYE_DIRECTION.normalize();
    // glTF cameras look down their −Z with +Y up; place the camera at the centre first to
    // read the points in its axes, then back it off along +Z.
    let at_centre = glam::camera::model::look_at_mat4(
        centre,
        centre - towards_eye,
        Vec3::Y,
        Vec3::NEG_Z,
        Vec3::Y,
    );
    // Rotate offsets from the centre rather than transform points, so that a point at the
    // centre is exactly at the origin (and a single-point scene gets the fallback distance).
    let camera_from_world_rotation = glam::Mat3::from_mat4(at_centre).transpose();
    let tan_half = (0.5 * FRAMING_YFOV_RAD).tan();
    // A point at (x, y, z) in those axes is at depth d − z from an eye backed off by d; it is
    // in view when |x|, |y| ≤ tan_half · (d − z), i.e. d ≥ z + max(|x|, |y|) / tan_half.
    let distance = points
        .into_iter()
        .map(|point| {
            let p = camera_from_world_rotation * (point - centre);
            p.z + p.x.abs().max(p.y.abs()) / tan_half
        })
        .fold(0.0f32, f32::max);
    let distance = if distance > 0.0 {
        distance
    } else {
        DEGENERATE_DISTANCE
    };
    let world_from_camera = Mat4::from_translation(towards_eye * distance) * at_centre;
    Camera {
        name: "framing camera".into(),
        world_from_camera,
        projection: Projection::Perspective {
            yfov: FRAMING_YFOV_RAD,
            aspect_ratio: None,
        },
    }
}

/// One ray through the centre of every pixel of a `width × height` image seen by `camera`,
/// over `[0, ∞)`, with unit directions.
///
/// The rays are ordered tile by tile ([`TILE_SIDE_PX`]² pixels, tiles in rows, pixels in rows
/// within a tile; the tiles of the last column and row may be cut short), so that any 64
/// consecutive rays of a full tile are neighbours: the coherent batches a renderer traces.
/// A perspective camera without its own aspect ratio takes the image's. Empty for an empty
/// image.
pub fn camera_rays(camera: &Camera, width: u32, height: u32) -> Vec<Ray> {
    let mut rays = Vec::with_capacity(width as usize * height as usize);
    if width == 0 || height == 0 {
        return rays;
    }
    let image_aspect = width as f32 / height as f32;
    let project = Projector::new(camera, image_aspect);
    for tile_y in (0..height).step_by(TILE_SIDE_PX as usize) {
        for tile_x in (0..width).step_by(TILE_SIDE_PX as usize) {
            for y in tile_y..(tile_y + TILE_SIDE_PX).min(height) {
                for x in tile_x..(tile_x + TILE_SIDE_PX).min(width) {
                    // Normalised device coordinates of the pixel centre: x right, y up, in
                    // [−1, 1]; image rows go down.
                    let ndc_x = 2.0 * (x as f32 + 0.5) / width as f32 - 1.0;
                    let ndc_y = 1.0 - 2.0 * (y as f32 + 0.5) / height as f32;
                    rays.push(project.ray(ndc_x, ndc_y));
                }
            }
        }
    }
    rays
}

/// Turns normalised device coordinates into world-space rays for one camera.
struct Projector {
    world_from_camera: Mat4,
    /// Half the view's width and height: tangents of the half angles for a perspective
    /// camera, scene units for an orthographic one.
    half_extent_x: f32,
    half_extent_y: f32,
    orthographic: bool,
}

impl Projector {
    fn new(camera: &Camera, image_aspect: f32) -> Self {
        let (half_extent_x, half_extent_y, orthographic) = match camera.projection {
            Projection::Perspective { yfov, aspect_ratio } => {
                let half_y = (0.5 * yfov).tan();
                (half_y * aspect_ratio.unwrap_or(image_aspect), half_y, false)
            }
            Projection::Orthographic { xmag, ymag } => (xmag, ymag, true),
        };
        Self {
            world_from_camera: camera.world_from_camera,
            half_extent_x,
            half_extent_y,
            orthographic,
        }
    }

    fn ray(&self, ndc_x: f32, ndc_y: f32) -> Ray {
        let x = ndc_x * self.half_extent_x;
        let y = ndc_y * self.half_extent_y;
        let (origin_camera, dir_camera) = if self.orthographic {
            (vec3(x, y, 0.0), Vec3::NEG_Z)
        } else {
            (Vec3::ZERO, vec3(x, y, -1.0))
        };
        Ray::new(
            self.world_from_camera.transform_point3(origin_camera),
            self.world_from_camera
                .transform_vector3(dir_camera)
                .normalize_or_zero(),
        )
    }
}

/// `count` rays over `[0, ∞)` with origins uniform inside `bounds` and unit directions uniform
/// on the sphere: the incoherent rays of diffuse bounces.
pub fn random_rays(bounds: &Bounds, count: usize, seed: u64) -> Vec<Ray> {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    (0..count)
        .map(|_| {
            let t = vec3(rng.random(), rng.random(), rng.random());
            let origin = bounds.min + (bounds.max - bounds.min) * t;
            Ray::new(origin, uniform_sphere(rng.random(), rng.random()))
        })
        .collect()
}

/// The rays of [`random_rays`] with the same arguments (same origins and directions), each
/// cut to a length uniform in `(0, diagonal]` of `bounds`: shadow rays towards points at
/// scene-sized distances, some blocked and some not.
pub fn random_segments(bounds: &Bounds, count: usize, seed: u64) -> Vec<Ray> {
    let diagonal = bounds.diagonal_length();
    // A second stream from the same seed, so the directions stay those of `random_rays`.
    let mut rng = Pcg64Mcg::seed_from_u64(seed ^ SEGMENT_STREAM);
    let mut rays = random_rays(bounds, count, seed);
    for ray in &mut rays {
        // 1 − u is in (0, 1] for u in [0, 1).
        ray.tfar = diagonal * (1.0 - rng.random::<f32>());
    }
    rays
}

/// Mixed into the seed of [`random_segments`]' lengths so they are independent of the rays.
const SEGMENT_STREAM: u64 = 0x5e63_e275_1e27_0fa1;

/// The unit vector for two uniform numbers in [0, 1): z uniform in [−1, 1] and the azimuth
/// uniform in [0, 2π) give a uniform density on the sphere (Archimedes' hat-box theorem).
#[inline]
fn uniform_sphere(u1: f32, u2: f32) -> Vec3 {
    let z = 1.0 - 2.0 * u1;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = TAU * u2;
    vec3(r * phi.cos(), r * phi.sin(), z)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box() -> Bounds {
        Bounds {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0),
        }
    }

    #[test]
    fn camera_rays_cover_every_pixel_once_in_tiles() {
        let camera = framing_camera(&unit_box(), unit_box().corners());
        // 19 × 11: partial tiles in the last column and row.
        let rays = camera_rays(&camera, 19, 11);
        assert_eq!(rays.len(), 19 * 11);
        // A pinhole camera: every ray leaves the eye, with a unit direction.
        let eye = camera.world_from_camera.transform_point3(Vec3::ZERO);
        assert!(rays.iter().all(|r| (r.origin - eye).length() < 1e-4));
        assert!(rays.iter().all(|r| (r.dir.length() - 1.0).abs() < 1e-5));
        let distinct: std::collections::HashSet<[u32; 3]> = rays
            .iter()
            .map(|r| r.dir.to_array().map(f32::to_bits))
            .collect();
        assert_eq!(distinct.len(), rays.len(), "two pixels share a ray");
    }

    #[test]
    fn camera_rays_come_tile_by_tile() {
        let camera = framing_camera(&unit_box(), unit_box().corners());
        let camera_from_world = camera.world_from_camera.inverse();
        // A 16 × 8 image is two tiles side by side: the left tile's 64 rays come first, and
        // they are exactly those pointing left of the optical axis.
        let rays = camera_rays(&camera, 16, 8);
        let x_camera = |r: &Ray| camera_from_world.transform_vector3(r.dir).x;
        assert!(rays[..64].iter().all(|r| x_camera(r) < 0.0));
        assert!(rays[64..].iter().all(|r| x_camera(r) > 0.0));
    }

    #[test]
    fn framing_camera_sees_the_whole_box_tightly() {
        let bounds = Bounds {
            min: vec3(-3.0, 0.0, 2.0),
            max: vec3(5.0, 0.5, 4.0),
        };
        let camera = framing_camera(&bounds, bounds.corners());
        let camera_from_world = camera.world_from_camera.inverse();
        let tan_half = (0.5 * FRAMING_YFOV_RAD).tan();
        let mut widest = 0.0f32;
        for corner in bounds.corners() {
            let p = camera_from_world.transform_point3(corner);
            assert!(p.z < 0.0, "corner {corner} behind the camera");
            // Inside the vertical field of view and, for a square image, the horizontal one.
            let angle = (p.x.abs().max(p.y.abs())) / -p.z;
            assert!(
                angle <= tan_half * (1.0 + 1e-5),
                "corner {corner} out of view"
            );
            widest = widest.max(angle);
        }
        // Tight: the farthest-out corner touches the edge of the view.
        assert!(
            (widest / tan_half - 1.0).abs() < 1e-4,
            "{widest} vs {tan_half}"
        );
        // The centre is on the optical axis, and the camera is rigid.
        let c = camera_from_world.transform_point3(bounds.centre());
        assert!(c.x.abs() < 1e-4 && c.y.abs() < 1e-4 && c.z < 0.0);
        let axes = glam::Mat3::from_mat4(camera.world_from_camera);
        assert!((axes.transpose() * axes).abs_diff_eq(glam::Mat3::IDENTITY, 1e-5));
    }

    #[test]
    fn a_point_is_framed_from_a_distance() {
        let point = Bounds {
            min: Vec3::ONE,
            max: Vec3::ONE,
        };
        let eye = framing_camera(&point, point.corners())
            .world_from_camera
            .transform_point3(Vec3::ZERO);
        assert!(((eye - Vec3::ONE).length() - DEGENERATE_DISTANCE).abs() < 1e-5);
    }

    #[test]
    fn orthographic_rays_are_parallel_and_span_the_view() {
        let camera = Camera {
            name: "ortho".into(),
            world_from_camera: Mat4::from_translation(vec3(0.0, 0.0, 5.0)),
            projection: Projection::Orthographic {
                xmag: 2.0,
                ymag: 1.0,
            },
        };
        let rays = camera_rays(&camera, 2, 2);
        assert!(rays.iter().all(|r| r.dir == Vec3::NEG_Z));
        // Pixel centres at ±½ of the half extents.
        let origins: Vec<Vec3> = rays.iter().map(|r| r.origin).collect();
        assert_eq!(
            origins,
            vec![
                vec3(-1.0, 0.5, 5.0),
                vec3(1.0, 0.5, 5.0),
                vec3(-1.0, -0.5, 5.0),
                vec3(1.0, -0.5, 5.0)
            ]
        );
    }

    #[test]
    fn random_rays_start_inside_and_spread_evenly() {
        let bounds = Bounds {
            min: vec3(-1.0, 2.0, 0.0),
            max: vec3(3.0, 2.5, 1.0),
        };
        let n = 100_000;
        let rays = random_rays(&bounds, n, 7);
        assert_eq!(rays.len(), n);
        assert!(
            rays.iter()
                .all(|r| r.origin.cmpge(bounds.min).all() && r.origin.cmple(bounds.max).all())
        );
        assert!(rays.iter().all(|r| (r.dir.length() - 1.0).abs() < 1e-5));
        // A uniform density on the sphere has mean 0 and E[d_i²] = 1/3 per axis; the standard
        // error of each mean over 100k rays is below 0.002.
        let mean = rays.iter().map(|r| r.dir).sum::<Vec3>() / n as f32;
        let mean_sq = rays.iter().map(|r| r.dir * r.dir).sum::<Vec3>() / n as f32;
        assert!(mean.abs().max_element() < 0.01, "mean direction {mean}");
        assert!((mean_sq - Vec3::splat(1.0 / 3.0)).abs().max_element() < 0.01);
        assert_eq!(rays, random_rays(&bounds, n, 7), "not deterministic");
        assert_ne!(rays, random_rays(&bounds, n, 8), "seed ignored");
    }

    #[test]
    fn random_segments_are_the_random_rays_cut_short() {
        let bounds = unit_box();
        let rays = random_rays(&bounds, 1000, 3);
        let segments = random_segments(&bounds, 1000, 3);
        let diagonal = bounds.diagonal_length();
        for (ray, segment) in rays.iter().zip(&segments) {
            assert_eq!(
                (ray.origin, ray.dir, ray.tnear),
                (segment.origin, segment.dir, segment.tnear)
            );
            assert!(segment.tfar > 0.0 && segment.tfar <= diagonal);
        }
    }
}
