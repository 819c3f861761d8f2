//! Where a world point lands on the film: the inverse of [`super::camera::CameraRays`], and
//! the camera's intrinsics and pose in the conventions computer-vision tools use.
//!
//! Film coordinates are [`super::camera`]'s: x right, y down, `(0, 0)` the image's top-left
//! corner, pixel `(i, j)`'s centre at `(i + ½, j + ½)`. With the camera's frame in OpenCV
//! axes (x right, y down, z forward: glTF's camera frame with y and z negated) and a point
//! `(X, Y, Z)` in it:
//!
//! - perspective: `x = cx + fx·X/Z`, `y = cy + fy·Y/Z` with `fx = W / (2·a·tan(yfov/2))`,
//!   `fy = H / (2·tan(yfov/2))` (`a` the aspect ratio the rays use) and `(cx, cy) = (W/2, H/2)`;
//! - orthographic: `x = cx + fx·X`, `y = cy + fy·Y` with `fx = W / (2·xmag)`,
//!   `fy = H / (2·ymag)`;
//!
//! and in both `Z` is the depth along the optical axis (the `z` AOV). The arithmetic is in
//! f64 so that projecting a point costs no precision beyond the point's own.

use crate::scene::{Camera, DEFAULT_ZNEAR, Projection};
use glam::{DMat3, DMat4, DVec2, DVec3, DVec4, Vec3};

/// A camera's projection onto a `width × height` film.
#[derive(Clone, Debug, PartialEq)]
pub struct FilmProjection {
    /// Whether rays are parallel.
    pub orthographic: bool,
    /// Focal lengths in pixels (perspective) or pixels per scene unit (orthographic).
    pub focal: DVec2,
    /// The principal point in film coordinates (pixel centres at half-integers).
    pub centre: DVec2,
    /// World from camera, OpenCV axes: columns right, down, forward.
    pub world_from_camera_cv: DMat3,
    /// The camera's position (perspective) or the image centre's ray origin (orthographic).
    pub origin: DVec3,
    /// Image size in pixels.
    pub size: (u32, u32),
    /// The glTF camera, for the sidecar's other fields.
    camera: Camera,
    /// The aspect ratio the rays use (perspective).
    aspect: f64,
}

impl FilmProjection {
    /// The projection of `camera` onto a `width × height` image; an error says what makes the
    /// camera unusable (as [`super::camera::CameraRays::new`] does).
    pub fn new(camera: &Camera, width: u32, height: u32) -> Result<Self, String> {
        // The same checks as the rays: a camera that renders projects.
        super::camera::CameraRays::new(camera, width, height)?;
        let m = camera.world_from_camera.as_dmat4();
        let right = m.transform_vector3(DVec3::X).normalize();
        let up = m.transform_vector3(DVec3::Y).normalize();
        let back = m.transform_vector3(DVec3::Z).normalize();
        let (w, h) = (f64::from(width), f64::from(height));
        let (orthographic, focal, aspect) = match camera.projection {
            Projection::Perspective { yfov, aspect_ratio } => {
                let aspect = aspect_ratio.map_or(w / h, f64::from);
                let tan_half = (f64::from(yfov) * 0.5).tan();
                (
                    false,
                    DVec2::new(w / (2.0 * aspect * tan_half), h / (2.0 * tan_half)),
                    aspect,
                )
            }
            Projection::Orthographic { xmag, ymag } => (
                true,
                DVec2::new(w / (2.0 * f64::from(xmag)), h / (2.0 * f64::from(ymag))),
                w / h,
            ),
        };
        Ok(Self {
            orthographic,
            focal,
            centre: DVec2::new(w * 0.5, h * 0.5),
            world_from_camera_cv: DMat3::from_cols(right, -up, -back),
            origin: m.w_axis.truncate(),
            size: (width, height),
            camera: camera.clone(),
            aspect,
        })
    }

    /// `p` in the camera's OpenCV frame.
    #[inline]
    pub fn camera_point(&self, p: DVec3) -> DVec3 {
        self.world_from_camera_cv.transpose() * (p - self.origin)
    }

    /// The depth of world point `p` along the optical axis (positive in front).
    #[inline]
    pub fn depth(&self, p: Vec3) -> f64 {
        self.camera_point(p.as_dvec3()).z
    }

    /// The film position of world point `p`, or `None` for a perspective camera when `p` is
    /// not in front of it (depth ≤ 0).
    #[inline]
    pub fn film(&self, p: DVec3) -> Option<DVec2> {
        let c = self.camera_point(p);
        if self.orthographic {
            return Some(self.centre + self.focal * DVec2::new(c.x, c.y));
        }
        if c.z <= 0.0 {
            return None;
        }
        Some(self.centre + self.focal * DVec2::new(c.x, c.y) / c.z)
    }

    /// Whether film position `f` lies on the image, `[0, W) × [0, H)`.
    #[inline]
    pub fn on_film(&self, f: DVec2) -> bool {
        f.x >= 0.0 && f.y >= 0.0 && f.x < f64::from(self.size.0) && f.y < f64::from(self.size.1)
    }

    /// The world point at film position `f` and optical-axis depth `z` (the inverse of
    /// [`FilmProjection::film`] and [`FilmProjection::depth`]).
    pub fn unproject(&self, f: DVec2, z: f64) -> DVec3 {
        let xy = (f - self.centre) / self.focal;
        let c = if self.orthographic {
            DVec3::new(xy.x, xy.y, z)
        } else {
            DVec3::new(xy.x * z, xy.y * z, z)
        };
        self.origin + self.world_from_camera_cv * c
    }

    /// OpenCV's intrinsic matrix with pixel centres at integers (principal point half a pixel
    /// up and left of the film's).
    pub fn k_opencv(&self) -> DMat3 {
        DMat3::from_cols(
            DVec3::new(self.focal.x, 0.0, 0.0),
            DVec3::new(0.0, self.focal.y, 0.0),
            DVec3::new(self.centre.x - 0.5, self.centre.y - 0.5, 1.0),
        )
    }

    /// World to camera, OpenCV axes, as a 4 × 4 rigid transform.
    pub fn world_to_camera_opencv(&self) -> DMat4 {
        let r = self.world_from_camera_cv.transpose();
        let t = -(r * self.origin);
        DMat4::from_cols(
            r.x_axis.extend(0.0),
            r.y_axis.extend(0.0),
            r.z_axis.extend(0.0),
            t.extend(1.0),
        )
    }

    /// Camera to world, glTF axes (x right, y up, z backward).
    pub fn camera_to_world_gltf(&self) -> DMat4 {
        let cv = self.world_from_camera_cv;
        DMat4::from_cols(
            cv.x_axis.extend(0.0),
            (-cv.y_axis).extend(0.0),
            (-cv.z_axis).extend(0.0),
            self.origin.extend(1.0),
        )
    }

    /// The camera's near plane ([`DEFAULT_ZNEAR`] when it has none) and far plane (`None`:
    /// infinite).
    pub fn clip(&self) -> (f64, Option<f64>) {
        let near = f64::from(self.camera.znear.unwrap_or(DEFAULT_ZNEAR));
        (near, self.camera.zfar.map(f64::from))
    }

    /// glTF's OpenGL projection matrix for this camera (clip from glTF camera space). An
    /// orthographic camera without a far plane gets `far = near + 2·max(xmag, ymag)·1e3`,
    /// the one case glTF does not define (it requires `zfar` there).
    pub fn opengl_projection(&self) -> DMat4 {
        let (n, far) = self.clip();
        match self.camera.projection {
            Projection::Perspective { yfov, .. } => {
                let t = (f64::from(yfov) * 0.5).tan();
                let (zz, zw) = match far {
                    Some(f) => ((f + n) / (n - f), 2.0 * f * n / (n - f)),
                    None => (-1.0, -2.0 * n),
                };
                DMat4::from_cols(
                    DVec4::new(1.0 / (self.aspect * t), 0.0, 0.0, 0.0),
                    DVec4::new(0.0, 1.0 / t, 0.0, 0.0),
                    DVec4::new(0.0, 0.0, zz, -1.0),
                    DVec4::new(0.0, 0.0, zw, 0.0),
                )
            }
            Projection::Orthographic { xmag, ymag } => {
                let (x, y) = (f64::from(xmag), f64::from(ymag));
                let f = far.unwrap_or(n + 2e3 * x.abs().max(y.abs()));
                DMat4::from_cols(
                    DVec4::new(1.0 / x, 0.0, 0.0, 0.0),
                    DVec4::new(0.0, 1.0 / y, 0.0, 0.0),
                    DVec4::new(0.0, 0.0, 2.0 / (n - f), 0.0),
                    DVec4::new(0.0, 0.0, (f + n) / (n - f), 1.0),
                )
            }
        }
    }

    /// The glTF camera projected.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// The aspect ratio the rays use (perspective: the file's, else the image's).
    pub fn aspect(&self) -> f64 {
        self.aspect
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;

    fn cameras() -> Vec<Camera> {
        let placed = Mat4::from_rotation_translation(
            glam::Quat::from_euler(glam::EulerRot::YXZ, 0.4, -0.3, 0.1),
            Vec3::new(1.0, 2.0, 3.0),
        );
        let base = |projection| Camera {
            name: "t".into(),
            node: None,
            znear: None,
            zfar: None,
            world_from_camera: placed,
            projection,
        };
        vec![
            base(Projection::Perspective {
                yfov: 0.8,
                aspect_ratio: None,
            }),
            base(Projection::Perspective {
                yfov: 0.8,
                aspect_ratio: Some(2.0),
            }),
            base(Projection::Orthographic {
                xmag: 2.0,
                ymag: 1.5,
            }),
        ]
    }

    #[test]
    fn projecting_a_camera_ray_returns_its_film_position() {
        for camera in cameras() {
            let rays = super::super::camera::CameraRays::new(&camera, 64, 48).unwrap();
            let projection = FilmProjection::new(&camera, 64, 48).unwrap();
            for (x, y) in [(0.5, 0.5), (31.25, 7.75), (63.5, 47.5)] {
                let ray = rays.ray(x, y);
                let p = ray.origin + ray.dir * 3.7;
                let f = projection.film(p.as_dvec3()).unwrap();
                assert!((f - DVec2::new(f64::from(x), f64::from(y))).length() < 1e-4);
                let z = projection.depth(p);
                let back = projection.unproject(f, z);
                assert!((back - p.as_dvec3()).length() < 1e-5, "{back} vs {p}");
            }
        }
    }

    #[test]
    fn opencv_matrices_agree_with_the_film_projection() {
        for camera in cameras() {
            let projection = FilmProjection::new(&camera, 64, 48).unwrap();
            let p = DVec3::new(0.3, 1.1, -2.0);
            let c = projection.world_to_camera_opencv().transform_point3(p);
            let k = projection.k_opencv();
            let uv = if projection.orthographic {
                k * DVec3::new(c.x, c.y, 1.0)
            } else {
                k * c / c.z
            };
            if let Some(f) = projection.film(p) {
                // OpenCV's pixel centres are at integers, the film's at half-integers.
                assert!((uv.truncate() + DVec2::splat(0.5) - f).length() < 1e-9);
            }
            // glTF's camera frame is OpenCV's with y and z negated.
            let flip = DMat4::from_diagonal(DVec4::new(1.0, -1.0, -1.0, 1.0));
            let round =
                projection.camera_to_world_gltf() * flip * projection.world_to_camera_opencv();
            assert!(round.abs_diff_eq(DMat4::IDENTITY, 1e-12));
        }
    }
}
