//! Ray generators for benchmarks: coherent camera rays and incoherent random rays.
//!
//! Every generator is deterministic (a fixed seed gives the same rays on every machine), so two
//! backends, two builds or two runs always trace the very same rays.

use crate::accel::{Ray, TriangleMesh};
use crate::render::{CameraRays, tiles};
use crate::scene::{Camera, Projection};
use glam::{Mat4, Vec3, vec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use std::f32::consts::TAU;

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
        node: None,
        znear: None,
        zfar: None,
        world_from_camera,
        projection: Projection::Perspective {
            yfov: FRAMING_YFOV_RAD,
            aspect_ratio: None,
        },
    }
}

/// One ray through the centre of every pixel of a `width × height` image seen by `camera`,
/// over `[0, ∞)`, with unit directions: the renderer's own camera rays
/// ([`CameraRays`]) in the renderer's own tile order ([`tiles::tiles`] of
/// [`tiles::TILE_SIZE`]² pixels, pixels in rows within a tile), so the coherent batches timed
/// here are the batches a render traces. An error names what makes the camera unusable.
pub fn camera_rays(camera: &Camera, width: u32, height: u32) -> Result<Vec<Ray>, String> {
    let project = CameraRays::new(camera, width, height)?;
    let mut rays = Vec::with_capacity(width as usize * height as usize);
    for tile in tiles::tiles(width, height, tiles::TILE_SIZE) {
        for local in 0..tile.pixel_count() {
            let (x, y) = tile.pixel(local);
            rays.push(project.ray(x as f32 + 0.5, y as f32 + 0.5));
        }
    }
    Ok(rays)
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
        let rays = camera_rays(&camera, 19, 11).unwrap();
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
        // A 2T × T image is two tiles side by side: the left tile's T² rays come first, and
        // they are exactly those pointing left of the optical axis.
        let t = tiles::TILE_SIZE;
        let rays = camera_rays(&camera, 2 * t, t).unwrap();
        let n = (t * t) as usize;
        let x_camera = |r: &Ray| camera_from_world.transform_vector3(r.dir).x;
        assert!(rays[..n].iter().all(|r| x_camera(r) < 0.0));
        assert!(rays[n..].iter().all(|r| x_camera(r) > 0.0));
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
            node: None,
            znear: None,
            zfar: None,
            world_from_camera: Mat4::from_translation(vec3(0.0, 0.0, 5.0)),
            projection: Projection::Orthographic {
                xmag: 2.0,
                ymag: 1.0,
            },
        };
        let rays = camera_rays(&camera, 2, 2).unwrap();
        assert!(rays.iter().all(|r| r.dir.abs_diff_eq(Vec3::NEG_Z, 1e-6)));
        // Pixel centres at ±½ of the half extents.
        let expected = [
            vec3(-1.0, 0.5, 5.0),
            vec3(1.0, 0.5, 5.0),
            vec3(-1.0, -0.5, 5.0),
            vec3(1.0, -0.5, 5.0),
        ];
        for (ray, want) in rays.iter().zip(expected) {
            assert!(
                ray.origin.abs_diff_eq(want, 1e-6),
                "{} vs {want}",
                ray.origin
            );
        }
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
