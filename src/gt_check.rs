//! `glint check-gt`: checks that an output's geometric ground truth agrees with itself and
//! with its camera sidecar (see `docs/ground-truth.md`).
//!
//! - **Reprojection**: every pixel with a finite `z` is carried back to the world with the
//!   sidecar's `K` and pose (pixel centres at integers) and compared with its `position`; the
//!   error is relative to the scene's scale in the image, the largest distance from the
//!   camera to a valid pixel's position.
//! - **Flow** (with the next frame, `--next`): each pixel's forward flow lands at a film
//!   position in the next frame, whose `flow_backward` (bilinear over the four pixels
//!   around it) must bring it back: the error is `|forward + backward|` in pixels. Pixels
//!   whose four neighbours are not all valid, or not all on the pixel's own instance (when
//!   both files have `instance_id`), or whose neighbours' backward flows differ by more than
//!   [`SMOOTH_FLOW_SPREAD`] pixels (an edge between surfaces moving differently, where
//!   interpolation means nothing), or whose backward flow is not smooth enough for bilinear
//!   interpolation to be exact within [`MAX_INTERPOLATION_ERROR`] pixels (estimated from
//!   second differences across the cell: a crease or a self-occlusion edge inside it), are
//!   left out and counted.

use crate::output::sidecar::{Sidecar, SidecarError, read_sidecar, sidecar_path};
use glam::{DVec2, DVec3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The largest spread (pixels) of the four backward flows around a landing point for it to
/// count as smooth in the flow check.
pub const SMOOTH_FLOW_SPREAD: f64 = 0.5;

/// The largest bilinear interpolation error (pixels, estimated from second differences of the
/// next frame's backward flow) for a landing point to be compared in the flow check.
pub const MAX_INTERPOLATION_ERROR: f64 = 0.01;

/// Why an output cannot be checked.
#[derive(Debug, thiserror::Error)]
pub enum CheckError {
    /// The EXR cannot be read.
    #[error("cannot read {path}: {message}")]
    Exr {
        /// The file.
        path: PathBuf,
        /// The reader's message.
        message: String,
    },
    /// The sidecar cannot be read.
    #[error(transparent)]
    Sidecar(#[from] SidecarError),
    /// A channel the check needs is missing.
    #[error("{path} has no channel {channel}: render it with --aov {aov}")]
    Missing {
        /// The file.
        path: PathBuf,
        /// The channel.
        channel: String,
        /// The AOV that writes it.
        aov: String,
    },
    /// The EXR and its sidecar disagree on the image size.
    #[error("{path} is {found} but its sidecar says {expected}")]
    Size {
        /// The file.
        path: PathBuf,
        /// The EXR's size.
        found: String,
        /// The sidecar's.
        expected: String,
    },
}

/// One output: its float channels and its sidecar.
pub struct GroundTruthFile {
    /// The EXR's path.
    pub path: PathBuf,
    /// The sidecar beside it.
    pub sidecar: Sidecar,
    channels: HashMap<String, Vec<f32>>,
    /// The `instance_id` channel, if the file has it.
    instance_ids: Option<Vec<u32>>,
}

impl GroundTruthFile {
    /// Reads `path` (an EXR written by glint) and its sidecar.
    pub fn read(path: &Path) -> Result<Self, CheckError> {
        use exr::prelude::FlatSamples;
        use exr::prelude::traits::*;
        let sidecar = read_sidecar(&sidecar_path(path))?;
        let fail = |message: String| CheckError::Exr {
            path: path.to_path_buf(),
            message,
        };
        // The header's declared size against the budgets, before any pixel is allocated.
        crate::output::budget::check_exr(
            path,
            crate::render::MAX_PIXELS,
            crate::output::budget::memory_budget(),
        )
        .map_err(&fail)?;
        let image = exr::prelude::read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .first_valid_layer()
            .all_attributes()
            .from_file(path)
            .map_err(|e| fail(e.to_string()))?;
        let size = image.layer_data.size;
        if (size.0, size.1) != (sidecar.width as usize, sidecar.height as usize) {
            return Err(CheckError::Size {
                path: path.to_path_buf(),
                found: format!("{}×{}", size.0, size.1),
                expected: format!("{}×{}", sidecar.width, sidecar.height),
            });
        }
        let mut channels = HashMap::new();
        let mut instance_ids = None;
        for channel in &image.layer_data.channel_data.list {
            match &channel.sample_data {
                FlatSamples::F32(samples) => {
                    channels.insert(channel.name.to_string(), samples.clone());
                }
                FlatSamples::U32(ids) if channel.name.to_string() == "instance_id" => {
                    instance_ids = Some(ids.clone());
                }
                _ => {}
            }
        }
        Ok(Self {
            path: path.to_path_buf(),
            sidecar,
            channels,
            instance_ids,
        })
    }

    /// Channel `name`, or an error naming the AOV that writes it.
    pub fn channel(&self, name: &str, aov: &str) -> Result<&[f32], CheckError> {
        self.channels
            .get(name)
            .map(Vec::as_slice)
            .ok_or_else(|| CheckError::Missing {
                path: self.path.clone(),
                channel: name.into(),
                aov: aov.into(),
            })
    }

    fn vec3(&self, names: [&str; 3], aov: &str, i: usize) -> Result<DVec3, CheckError> {
        Ok(DVec3::new(
            f64::from(self.channel(names[0], aov)?[i]),
            f64::from(self.channel(names[1], aov)?[i]),
            f64::from(self.channel(names[2], aov)?[i]),
        ))
    }
}

/// The largest disagreement of one check, and where.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Disagreement {
    /// The largest error (relative for reprojection, pixels for flow).
    pub largest: f64,
    /// The pixel `(x, y)` where it occurs.
    pub at: (u32, u32),
    /// Pixels compared.
    pub compared: usize,
    /// Pixels left out (invalid, or not smooth for the flow check).
    pub skipped: usize,
}

impl Disagreement {
    /// Whether the largest disagreement is over `tolerance` (or not a number).
    pub fn exceeds(&self, tolerance: f64) -> bool {
        self.largest.is_nan() || self.largest > tolerance
    }

    fn add(&mut self, error: f64, at: (u32, u32)) {
        self.compared += 1;
        if error > self.largest || error.is_nan() {
            self.largest = error;
            self.at = at;
        }
    }
}

/// Reprojection: `z` with K and pose against `position`, relative to the largest camera
/// distance of a valid pixel.
pub fn reprojection(file: &GroundTruthFile) -> Result<Disagreement, CheckError> {
    let z = file.channel("z", "z")?;
    let w = file.sidecar.width;
    let projection = file.sidecar.projection();
    let camera = DVec3::from_array(file.sidecar.camera.position);
    let position = ["position.X", "position.Y", "position.Z"];
    let mut scale = 0.0f64;
    for (i, _) in z.iter().enumerate().filter(|(_, z)| z.is_finite()) {
        let p = file.vec3(position, "position", i)?;
        scale = scale.max((p - camera).length());
    }
    let mut result = Disagreement::default();
    for (i, &zi) in z.iter().enumerate() {
        let p = file.vec3(position, "position", i)?;
        let (x, y) = ((i % w as usize) as u32, (i / w as usize) as u32);
        if !zi.is_finite() || !p.is_finite() {
            // Both must be invalid together.
            if zi.is_finite() != p.is_finite() {
                result.add(f64::INFINITY, (x, y));
            } else {
                result.skipped += 1;
            }
            continue;
        }
        let back = projection.unproject(DVec2::new(f64::from(x), f64::from(y)), f64::from(zi));
        result.add((back - p).length() / scale.max(f64::MIN_POSITIVE), (x, y));
    }
    Ok(result)
}

/// Flow: forward flow of `file` against the backward flow of `next` (the following frame).
pub fn flow_round_trip(
    file: &GroundTruthFile,
    next: &GroundTruthFile,
) -> Result<Disagreement, CheckError> {
    let (fx, fy) = (
        file.channel("flow.X", "flow")?,
        file.channel("flow.Y", "flow")?,
    );
    let (bx, by) = (
        next.channel("flow_backward.X", "flow_backward")?,
        next.channel("flow_backward.Y", "flow_backward")?,
    );
    if (file.sidecar.width, file.sidecar.height) != (next.sidecar.width, next.sidecar.height) {
        return Err(CheckError::Size {
            path: next.path.clone(),
            found: format!("{}×{}", next.sidecar.width, next.sidecar.height),
            expected: format!(
                "{}×{} as {} (the frames of a flow check must have one size)",
                file.sidecar.width,
                file.sidecar.height,
                file.path.display()
            ),
        });
    }
    let (w, h) = (next.sidecar.width as i64, next.sidecar.height as i64);
    let ids = file.instance_ids.as_ref().zip(next.instance_ids.as_ref());
    // The next frame's backward flow at pixel (x, y), if valid and (with IDs) on `id`.
    let back = |x: i64, y: i64, id: Option<u32>| -> Option<DVec2> {
        if x < 0 || y < 0 || x >= w || y >= h {
            return None;
        }
        let i = (y * w + x) as usize;
        if let (Some(id), Some((_, next_ids))) = (id, ids)
            && next_ids.get(i) != Some(&id)
        {
            return None;
        }
        let v = DVec2::new(f64::from(bx[i]), f64::from(by[i]));
        v.is_finite().then_some(v)
    };
    let width = file.sidecar.width as usize;
    let mut result = Disagreement::default();
    for (i, (&dx, &dy)) in fx.iter().zip(fy).enumerate() {
        let forward = DVec2::new(f64::from(dx), f64::from(dy));
        if !forward.is_finite() {
            result.skipped += 1;
            continue;
        }
        let (x, y) = ((i % width) as u32, (i / width) as u32);
        // Pixel centres at integers: the landing point and its four neighbours.
        let land = DVec2::new(f64::from(x), f64::from(y)) + forward;
        let (x0, y0) = (land.x.floor() as i64, land.y.floor() as i64);
        let (tx, ty) = (land.x - x0 as f64, land.y - y0 as f64);
        let id = ids.and_then(|(own, _)| own.get(i).copied());
        let corners = [
            back(x0, y0, id),
            back(x0 + 1, y0, id),
            back(x0, y0 + 1, id),
            back(x0 + 1, y0 + 1, id),
        ];
        let [Some(a), Some(b), Some(c), Some(d)] = corners else {
            result.skipped += 1;
            continue;
        };
        let lo = a.min(b).min(c).min(d);
        let hi = a.max(b).max(c).max(d);
        if (hi - lo).max_element() > SMOOTH_FLOW_SPREAD {
            result.skipped += 1;
            continue;
        }
        // Bilinear interpolation of a smooth field errs by at most |f''|/8 over a one-pixel
        // cell: estimate f'' by second differences across the cell (one pixel beyond it on
        // each side) and leave out cells where the field is not that smooth (a crease or a
        // self-occlusion edge inside the cell, where the interpolated flow is not the flow of
        // the landing point).
        let outside = [
            (back(x0 - 1, y0, id), a, b),
            (back(x0 + 2, y0, id), b, a),
            (back(x0 - 1, y0 + 1, id), c, d),
            (back(x0 + 2, y0 + 1, id), d, c),
            (back(x0, y0 - 1, id), a, c),
            (back(x0, y0 + 2, id), c, a),
            (back(x0 + 1, y0 - 1, id), b, d),
            (back(x0 + 1, y0 + 2, id), d, b),
        ];
        let curvature = outside
            .iter()
            .try_fold(0.0f64, |most, &(beyond, near, far)| {
                beyond.map(|beyond| most.max((beyond - 2.0 * near + far).length()))
            });
        match curvature {
            Some(c) if c / 8.0 <= MAX_INTERPOLATION_ERROR => {}
            _ => {
                result.skipped += 1;
                continue;
            }
        }
        let backward = (a * (1.0 - tx) + b * tx) * (1.0 - ty) + (c * (1.0 - tx) + d * tx) * ty;
        result.add((forward + backward).length(), (x, y));
    }
    Ok(result)
}
