//! The image size of a job: as given, or derived from the camera's aspect ratio.

use crate::scene::{Camera, Projection};

/// Image width when the job gives neither width nor height.
pub const DEFAULT_WIDTH: u32 = 1280;
/// Aspect ratio (width / height) for cameras that do not fix one: 16:9.
pub const DEFAULT_ASPECT: f32 = 16.0 / 9.0;

/// The aspect ratio (width / height) the camera fixes, if any.
pub fn fixed_aspect(camera: &Camera) -> Option<f32> {
    let aspect = match camera.projection {
        Projection::Perspective { aspect_ratio, .. } => aspect_ratio?,
        Projection::Orthographic { xmag, ymag } => (xmag / ymag).abs(),
    };
    (aspect.is_finite() && aspect > 0.0).then_some(aspect)
}

/// Image size from the job: both given are used as they are; one given derives the other from
/// the camera's aspect ratio ([`DEFAULT_ASPECT`] if it fixes none); none gives
/// [`DEFAULT_WIDTH`] wide.
pub fn image_size(width: Option<u32>, height: Option<u32>, camera: &Camera) -> (u32, u32) {
    let aspect = fixed_aspect(camera).unwrap_or(DEFAULT_ASPECT);
    let derive = |v: f32| (v.round() as u32).max(1);
    match (width, height) {
        (Some(w), Some(h)) => (w, h),
        (Some(w), None) => (w, derive(w as f32 / aspect)),
        (None, Some(h)) => (derive(h as f32 * aspect), h),
        (None, None) => (DEFAULT_WIDTH, derive(DEFAULT_WIDTH as f32 / aspect)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;

    fn camera(projection: Projection) -> Camera {
        Camera {
            name: "c".into(),
            node: None,
            znear: None,
            zfar: None,
            world_from_camera: Mat4::IDENTITY,
            projection,
        }
    }

    #[test]
    fn size_follows_the_camera_aspect() {
        let free = camera(Projection::Perspective {
            yfov: 1.0,
            aspect_ratio: None,
        });
        assert_eq!(image_size(None, None, &free), (1280, 720));
        assert_eq!(image_size(Some(640), None, &free), (640, 360));
        let square = camera(Projection::Perspective {
            yfov: 1.0,
            aspect_ratio: Some(1.0),
        });
        assert_eq!(image_size(Some(300), None, &square), (300, 300));
        assert_eq!(image_size(None, Some(200), &square), (200, 200));
        let ortho = camera(Projection::Orthographic {
            xmag: 2.0,
            ymag: 1.0,
        });
        assert_eq!(image_size(Some(100), None, &ortho), (100, 50));
        assert_eq!(image_size(Some(7), Some(9), &ortho), (7, 9));
    }
}
