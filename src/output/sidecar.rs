//! The camera sidecar: `OUT.json` beside an image, saying exactly how its pixels relate to the
//! scene (`--sidecar`; see `docs/ground-truth.md` for the conventions and a worked example).
//!
//! Conventions, stated in the file too:
//! - Pixels: pixel `(i, j)` (column `i`, row `j`, row 0 at the top) has its centre at
//!   `(u, v) = (i, j)` (OpenCV's convention: an array index is a pixel centre), so the
//!   principal point of a centred camera is `((W − 1)/2, (H − 1)/2)`.
//! - `K` maps OpenCV camera coordinates (x right, y down, z forward) to pixels:
//!   `(u, v, 1)ᵀ ∝ K (X, Y, Z)ᵀ` for a perspective camera, `(u, v, 1)ᵀ = K (X, Y, 1)ᵀ` for an
//!   orthographic one.
//! - `world_to_camera_opencv` takes world points (glTF's axes: y up, metres or scene units)
//!   to OpenCV camera coordinates; `camera_to_world_gltf` is glTF's camera frame (x right,
//!   y up, z backward: the camera looks down −z) in the world. Matrices are row-major lists
//!   of rows.
//! - `opengl_projection` is the OpenGL clip matrix for glTF's camera frame with the
//!   camera's near and far planes (NDC z in [−1, 1], y up).

use super::instances::InstanceAnnotation;
use super::{OutputError, write_atomically};
use crate::render::projection::FilmProjection;
use crate::scene::Projection;
use glam::{DMat3, DMat4};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The sidecar's schema name.
pub const SIDECAR_SCHEMA: &str = "glint.sidecar";

/// The sidecar's schema version; raised whenever a field changes meaning or is removed.
pub const SIDECAR_SCHEMA_VERSION: u32 = 1;

/// What the `pixel_centers` field says: array index = pixel centre.
pub const PIXEL_CENTERS: &str = "integer: pixel (i, j) has its centre at (u, v) = (i, j)";

/// A 3 × 3 matrix as rows.
pub type Mat3Rows = [[f64; 3]; 3];
/// A 4 × 4 matrix as rows.
pub type Mat4Rows = [[f64; 4]; 4];

/// Everything `OUT.json` says about one rendered image.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sidecar {
    /// [`SIDECAR_SCHEMA`].
    pub schema: String,
    /// [`SIDECAR_SCHEMA_VERSION`].
    pub schema_version: u32,
    /// The image file's name (beside the sidecar).
    pub image: String,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The pixel-centre convention ([`PIXEL_CENTERS`]).
    pub pixel_centers: String,
    /// The animation time rendered, seconds (`None`: the rest pose, animations not applied).
    pub time: Option<f32>,
    /// The glTF scene index rendered: the one asked for (`--scene`), else the file's default
    /// scene (its `scene` property, else its first); `None` only for a file without scenes
    /// (its root nodes render) and the demo scene.
    pub scene_index: Option<usize>,
    /// The camera.
    pub camera: CameraRecord,
    /// The flow AOVs' time step Δ, seconds: `flow` goes to `time + Δ`, `flow_backward` to
    /// `time − Δ` (`None` without flow AOVs).
    pub flow_dt: Option<f32>,
    /// The EXR channels of the ground-truth AOVs written with the image (empty for PNG).
    pub channels: Vec<String>,
    /// Per-instance annotations ([`InstanceAnnotation`]); empty unless requested.
    pub instances: Vec<InstanceAnnotation>,
    /// Whether annotations were requested (`--annotations`): an annotated image with no
    /// visible instance has empty `instances` too, and only this tells the two apart (the
    /// batch's resume and `--coco` re-render jobs whose sidecars lack them). Absent in
    /// sidecars of older glint versions: false.
    #[serde(default)]
    pub annotated: bool,
}

/// The camera of a sidecar.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CameraRecord {
    /// The camera's name (glTF camera name, or what glint calls a camera it made).
    pub name: String,
    /// The glTF node index holding the camera (`None` for a camera glint made).
    pub node: Option<u32>,
    /// `"perspective"` or `"orthographic"`.
    pub model: String,
    /// Intrinsics (see the module documentation); pixel centres at integers.
    #[serde(rename = "K")]
    pub k: Mat3Rows,
    /// World to camera, OpenCV axes (x right, y down, z forward).
    pub world_to_camera_opencv: Mat4Rows,
    /// Camera to world, glTF axes (x right, y up, z backward).
    pub camera_to_world_gltf: Mat4Rows,
    /// The camera's position in the world.
    pub position: [f64; 3],
    /// Perspective: the vertical field of view, radians.
    pub yfov: Option<f64>,
    /// Perspective: the aspect ratio the rays use (the file's, else the image's).
    pub aspect_ratio: Option<f64>,
    /// Orthographic: half the view's width, scene units.
    pub xmag: Option<f64>,
    /// Orthographic: half the view's height, scene units.
    pub ymag: Option<f64>,
    /// The near plane distance used in `opengl_projection`.
    pub znear: f64,
    /// The far plane distance (`None`: infinite, a perspective camera without `zfar`).
    pub zfar: Option<f64>,
    /// OpenGL clip-from-camera matrix (glTF camera axes), glTF's formulas.
    pub opengl_projection: Mat4Rows,
}

fn rows3(m: DMat3) -> Mat3Rows {
    let t = m.transpose();
    [
        t.x_axis.to_array(),
        t.y_axis.to_array(),
        t.z_axis.to_array(),
    ]
}

fn rows4(m: DMat4) -> Mat4Rows {
    let t = m.transpose();
    [
        t.x_axis.to_array(),
        t.y_axis.to_array(),
        t.z_axis.to_array(),
        t.w_axis.to_array(),
    ]
}

impl CameraRecord {
    /// The record of the camera `projection` projects with.
    pub fn of(projection: &FilmProjection) -> Self {
        let camera = projection.camera();
        let (znear, zfar) = projection.clip();
        let (model, yfov, aspect_ratio, xmag, ymag) = match camera.projection {
            Projection::Perspective { yfov, .. } => (
                "perspective",
                Some(f64::from(yfov)),
                Some(projection.aspect()),
                None,
                None,
            ),
            Projection::Orthographic { xmag, ymag } => (
                "orthographic",
                None,
                None,
                Some(f64::from(xmag)),
                Some(f64::from(ymag)),
            ),
        };
        Self {
            name: camera.name.clone(),
            node: camera.node,
            model: model.into(),
            k: rows3(projection.k_opencv()),
            world_to_camera_opencv: rows4(projection.world_to_camera_opencv()),
            camera_to_world_gltf: rows4(projection.camera_to_world_gltf()),
            position: projection.origin.to_array(),
            yfov,
            aspect_ratio,
            xmag,
            ymag,
            znear,
            zfar,
            opengl_projection: rows4(projection.opengl_projection()),
        }
    }
}

impl Sidecar {
    /// The sidecar of an image `image` (its file name) rendered through `projection` at
    /// animation time `time` of scene `scene_index`, with the ground-truth `channels` and
    /// flow step `flow_dt`; no instances yet.
    pub fn new(
        image: &str,
        projection: &FilmProjection,
        time: Option<f32>,
        scene_index: Option<usize>,
        flow_dt: Option<f32>,
        channels: Vec<String>,
    ) -> Self {
        Self {
            schema: SIDECAR_SCHEMA.into(),
            schema_version: SIDECAR_SCHEMA_VERSION,
            image: image.into(),
            width: projection.size.0,
            height: projection.size.1,
            pixel_centers: PIXEL_CENTERS.into(),
            time,
            scene_index,
            camera: CameraRecord::of(projection),
            flow_dt,
            channels,
            instances: Vec::new(),
            annotated: false,
        }
    }

    /// The camera's projection again, from the record (for `glint check-gt`): K, pose and
    /// size give every film position and depth.
    pub fn projection(&self) -> SidecarProjection {
        SidecarProjection::from_record(&self.camera)
    }
}

/// The projection a sidecar describes, read back from its matrices: OpenCV intrinsics and
/// pose, pixel centres at integers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SidecarProjection {
    /// Whether the camera is orthographic.
    pub orthographic: bool,
    /// `K`.
    pub k: DMat3,
    /// World to camera (OpenCV axes).
    pub world_to_camera: DMat4,
}

impl SidecarProjection {
    fn from_record(record: &CameraRecord) -> Self {
        let m3 = |r: &Mat3Rows| DMat3::from_cols_array_2d(r).transpose();
        let m4 = |r: &Mat4Rows| DMat4::from_cols_array_2d(r).transpose();
        Self {
            orthographic: record.model == "orthographic",
            k: m3(&record.k),
            world_to_camera: m4(&record.world_to_camera_opencv),
        }
    }

    /// The pixel `(u, v)` (centres at integers) and depth of world point `p`; `None` behind
    /// a perspective camera.
    pub fn project(&self, p: glam::DVec3) -> Option<(glam::DVec2, f64)> {
        let c = self.world_to_camera.transform_point3(p);
        let h = if self.orthographic {
            self.k * glam::DVec3::new(c.x, c.y, 1.0)
        } else {
            if c.z <= 0.0 {
                return None;
            }
            self.k * (c / c.z)
        };
        Some((h.truncate(), c.z))
    }

    /// The world point seen at pixel `(u, v)` (centres at integers) at depth `z`.
    pub fn unproject(&self, uv: glam::DVec2, z: f64) -> glam::DVec3 {
        let n = self.k.inverse() * uv.extend(1.0);
        let c = if self.orthographic {
            glam::DVec3::new(n.x, n.y, z)
        } else {
            n * z
        };
        self.world_to_camera.inverse().transform_point3(c)
    }
}

/// The sidecar path of an image: `OUT.json` for `OUT.png` / `OUT.exr`.
pub fn sidecar_path(image: &Path) -> PathBuf {
    image.with_extension("json")
}

/// Writes `sidecar` as pretty JSON to `path`, atomically.
pub fn write_sidecar(path: &Path, sidecar: &Sidecar) -> Result<(), OutputError> {
    let text = serde_json::to_string_pretty(sidecar).map_err(|e| OutputError::Encode {
        path: path.to_path_buf(),
        format: "JSON",
        message: e.to_string(),
    })?;
    write_atomically(path, |writer| {
        writer
            .write_all(text.as_bytes())
            .and_then(|()| writer.write_all(b"\n"))
            .map_err(|source| OutputError::Io {
                path: path.to_path_buf(),
                source,
            })
    })
}

/// Why a sidecar could not be read.
#[derive(Debug, thiserror::Error)]
pub enum SidecarError {
    /// The file cannot be read.
    #[error("cannot read {path}: {source}; render with --sidecar to write it")]
    Io {
        /// The sidecar's path.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The file is not a sidecar of this schema.
    #[error("{path} is not a glint sidecar of schema version {SIDECAR_SCHEMA_VERSION}: {message}")]
    Parse {
        /// The sidecar's path.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

/// Reads a sidecar written by [`write_sidecar`].
pub fn read_sidecar(path: &Path) -> Result<Sidecar, SidecarError> {
    let text = std::fs::read_to_string(path).map_err(|source| SidecarError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let sidecar: Sidecar = serde_json::from_str(&text).map_err(|e| SidecarError::Parse {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    if sidecar.schema != SIDECAR_SCHEMA || sidecar.schema_version != SIDECAR_SCHEMA_VERSION {
        return Err(SidecarError::Parse {
            path: path.to_path_buf(),
            message: format!(
                "it says schema {:?} version {}",
                sidecar.schema, sidecar.schema_version
            ),
        });
    }
    Ok(sidecar)
}
