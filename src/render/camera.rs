//! Camera rays from glTF cameras.
//!
//! Film coordinates are continuous pixels: x to the right, y down, `(0, 0)` the top-left
//! corner of the image and `(W, H)` the bottom-right one; pixel `(i, j)` covers
//! `[i, i+1) × [j, j+1)`. They map to normalised device coordinates
//! `ndc = (2x/W − 1, 1 − 2y/H)` in `[−1, 1]²`, +y up.
//!
//! - Perspective: direction `(ndc.x · a · tan(yfov/2), ndc.y · tan(yfov/2), −1)` in camera
//!   space, from the camera's origin, with `a` the camera's aspect ratio, or `W/H` if it has
//!   none (glTF: "when undefined, the aspect ratio of the rendering viewport must be used").
//! - Orthographic: origin `(ndc.x · xmag, ndc.y · ymag, 0)`, direction `(0, 0, −1)`.
//!
//! glTF's znear/zfar are not used: rays start at the camera.

use crate::accel::Ray;
use crate::scene::{Camera, Projection};
use crate::texture::RayDifferential;
use glam::Vec3;

/// Generates camera rays for an image of a given size. Directions are unit length, so hit
/// distances are in scene units.
#[derive(Clone, Copy, Debug)]
pub struct CameraRays {
    kind: Kind,
    /// World-space position (perspective) or the image centre's origin (orthographic).
    origin: Vec3,
    /// World-space vector for ndc.x = 1 (scaled by the half-extent).
    right: Vec3,
    /// World-space vector for ndc.y = 1.
    up: Vec3,
    /// World-space viewing direction (camera −Z).
    forward: Vec3,
    /// 2 / W and 2 / H.
    inv_half_size: (f32, f32),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Perspective,
    Orthographic,
}

impl CameraRays {
    /// [`CameraRays::new`] with its error as a [`RenderError`](super::RenderError) naming
    /// the camera.
    pub fn for_render(
        camera: &Camera,
        width: u32,
        height: u32,
    ) -> Result<Self, super::RenderError> {
        Self::new(camera, width, height).map_err(|reason| super::RenderError::Camera {
            name: camera.name.clone(),
            reason,
        })
    }

    /// Rays for `camera` over a `width × height` image; an error names what is unusable.
    pub fn new(camera: &Camera, width: u32, height: u32) -> Result<Self, String> {
        if width == 0 || height == 0 {
            return Err(format!("image size {width}×{height} has no pixels"));
        }
        let m = camera.world_from_camera;
        if !m.is_finite() || m.determinant() == 0.0 {
            return Err("its transform is not finite or not invertible".into());
        }
        let origin = m.transform_point3(Vec3::ZERO);
        let forward = m.transform_vector3(-Vec3::Z);
        let (kind, right, up, origin) = match camera.projection {
            Projection::Perspective { yfov, aspect_ratio } => {
                if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
                    return Err(format!("yfov {yfov} rad is outside (0, π)"));
                }
                let aspect = aspect_ratio.unwrap_or(width as f32 / height as f32);
                if !(aspect > 0.0 && aspect.is_finite()) {
                    return Err(format!("aspectRatio {aspect} is not positive"));
                }
                let tan_half = (yfov * 0.5).tan();
                (
                    Kind::Perspective,
                    m.transform_vector3(Vec3::X * (aspect * tan_half)),
                    m.transform_vector3(Vec3::Y * tan_half),
                    origin,
                )
            }
            Projection::Orthographic { xmag, ymag } => {
                if !(xmag != 0.0 && ymag != 0.0 && xmag.is_finite() && ymag.is_finite()) {
                    return Err(format!(
                        "xmag {xmag} and ymag {ymag} must be finite and non-zero"
                    ));
                }
                (
                    Kind::Orthographic,
                    m.transform_vector3(Vec3::X * xmag),
                    m.transform_vector3(Vec3::Y * ymag),
                    origin,
                )
            }
        };
        let forward = forward.normalize_or_zero();
        if forward == Vec3::ZERO {
            return Err("its transform collapses the viewing direction".into());
        }
        Ok(Self {
            kind,
            origin,
            right,
            up,
            forward,
            inv_half_size: (2.0 / width as f32, 2.0 / height as f32),
        })
    }

    /// The ray through film position `(x, y)` (continuous pixel coordinates, y down).
    #[inline]
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        let ndc_x = x * self.inv_half_size.0 - 1.0;
        let ndc_y = 1.0 - y * self.inv_half_size.1;
        match self.kind {
            Kind::Perspective => {
                let dir = (self.right * ndc_x + self.up * ndc_y + self.forward).normalize();
                Ray::new(self.origin, dir)
            }
            Kind::Orthographic => {
                let origin = self.origin + self.right * ndc_x + self.up * ndc_y;
                Ray::new(origin, self.forward)
            }
        }
    }

    /// The neighbours of the ray through `(x, y)`: the rays through `(x + spacing, y)` and
    /// `(x, y + spacing)`, for texture filtering. `spacing` is one pixel divided by √spp, the
    /// film distance between a pixel's samples.
    #[inline]
    pub fn ray_differential(&self, x: f32, y: f32, spacing: f32) -> RayDifferential {
        let rx = self.ray(x + spacing, y);
        let ry = self.ray(x, y + spacing);
        RayDifferential {
            rx_origin: rx.origin,
            rx_dir: rx.dir,
            ry_origin: ry.origin,
            ry_dir: ry.dir,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;

    fn perspective(yfov: f32, aspect: Option<f32>) -> Camera {
        Camera {
            name: "test".into(),
            node: None,
            znear: None,
            zfar: None,
            world_from_camera: Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0)),
            projection: Projection::Perspective {
                yfov,
                aspect_ratio: aspect,
            },
        }
    }

    #[test]
    fn image_corners_span_the_field_of_view() {
        let yfov = 1.0f32;
        let rays = CameraRays::new(&perspective(yfov, None), 200, 100).unwrap();
        let top = rays.ray(100.0, 0.0);
        assert_eq!(top.origin, Vec3::new(1.0, 2.0, 3.0));
        let angle = top.dir.angle_between(-Vec3::Z);
        assert!((angle - yfov / 2.0).abs() < 1e-6 && top.dir.y > 0.0);
        let right = rays.ray(200.0, 50.0);
        let expected = (2.0 * (yfov / 2.0).tan()).atan();
        assert!((right.dir.angle_between(-Vec3::Z) - expected).abs() < 1e-6 && right.dir.x > 0.0);
        // A fixed aspect ratio overrides the image's.
        let fixed = CameraRays::new(&perspective(yfov, Some(1.0)), 200, 100).unwrap();
        let r = fixed.ray(200.0, 50.0);
        assert!((r.dir.angle_between(-Vec3::Z) - yfov / 2.0).abs() < 1e-6);
    }

    #[test]
    fn orthographic_rays_are_parallel() {
        let camera = Camera {
            name: "ortho".into(),
            node: None,
            znear: None,
            zfar: None,
            world_from_camera: Mat4::IDENTITY,
            projection: Projection::Orthographic {
                xmag: 2.0,
                ymag: 1.0,
            },
        };
        let rays = CameraRays::new(&camera, 4, 2).unwrap();
        let corner = rays.ray(0.0, 0.0);
        assert_eq!(corner.origin, Vec3::new(-2.0, 1.0, 0.0));
        assert_eq!(corner.dir, -Vec3::Z);
    }

    #[test]
    fn unusable_cameras_are_errors() {
        assert!(CameraRays::new(&perspective(0.0, None), 4, 4).is_err());
        assert!(CameraRays::new(&perspective(1.0, Some(-1.0)), 4, 4).is_err());
        assert!(CameraRays::new(&perspective(1.0, None), 0, 4).is_err());
        let mut flat = perspective(1.0, None);
        flat.world_from_camera = Mat4::from_scale(Vec3::new(1.0, 1.0, 0.0));
        assert!(CameraRays::new(&flat, 4, 4).is_err());
    }
}
