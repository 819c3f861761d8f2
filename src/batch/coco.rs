//! The COCO detection file of a batch (`glint batch --coco FILE.json`): every job's
//! per-instance annotations ([`crate::output::instances`]) gathered into one file that
//! pycocotools loads.
//!
//! - `images`: one per job whose annotations exist, in job order, `id` from 1, `file_name` the
//!   image's path relative to the COCO file's folder (absolute when it lies elsewhere).
//! - `categories`: every category met, sorted by name, `id` from 1.
//! - `annotations`: one per instance with a non-empty visible mask: `segmentation` (COCO's
//!   compressed RLE), `bbox` (`[x, y, width, height]`, the mask's tight box), `area` (the
//!   exact visible area: the sum of fractional coverage, not the mask's pixel count),
//!   `iscrowd` 0, and the extras `amodal_segmentation`, `amodal_bbox`, `amodal_area`,
//!   `visible_fraction` and `instance_id` (the glTF node).
//!
//! Annotations are read back from the camera sidecars (`OUT.json`) the jobs wrote, so a resumed batch (whose
//! skipped jobs were rendered by an earlier run) gathers them all the same.

use crate::output::OutputError;
use crate::output::rle::Rle;
use crate::output::sidecar::{Sidecar, read_sidecar, sidecar_path};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Why the COCO file could not be made.
#[derive(Debug, thiserror::Error)]
pub enum CocoError {
    /// A job's annotation file is missing or unreadable.
    #[error(
        "{path}: cannot read the sidecar's annotations ({message}); render the job with --annotations \
         (glint batch --coco turns it on; add --force to re-render outputs from earlier runs)"
    )]
    Read {
        /// The annotation file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// The COCO file could not be written.
    #[error(transparent)]
    Write(#[from] OutputError),
}

/// A COCO detection file.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Coco {
    /// What made it.
    pub info: CocoInfo,
    /// The images.
    pub images: Vec<CocoImage>,
    /// The categories.
    pub categories: Vec<CocoCategory>,
    /// The instances.
    pub annotations: Vec<CocoAnnotation>,
}

/// COCO's `info`.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct CocoInfo {
    /// A description.
    pub description: String,
    /// glint's version.
    pub version: String,
}

/// One image.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct CocoImage {
    /// From 1.
    pub id: u64,
    /// The image's path (see the module documentation).
    pub file_name: String,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

/// One category.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct CocoCategory {
    /// From 1.
    pub id: u64,
    /// Its name.
    pub name: String,
    /// Empty: glint has no hierarchy of categories.
    pub supercategory: String,
}

/// One instance in one image.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct CocoAnnotation {
    /// From 1.
    pub id: u64,
    /// Its image's `id`.
    pub image_id: u64,
    /// Its category's `id`.
    pub category_id: u64,
    /// The visible mask.
    pub segmentation: Rle,
    /// The exact visible area, pixels.
    pub area: f64,
    /// The visible mask's box.
    pub bbox: [f64; 4],
    /// Always 0: every annotation is one instance.
    pub iscrowd: u8,
    /// The amodal mask.
    pub amodal_segmentation: Rle,
    /// The amodal mask's box.
    pub amodal_bbox: [f64; 4],
    /// The exact amodal area, pixels.
    pub amodal_area: f64,
    /// Visible area / amodal area.
    pub visible_fraction: f64,
    /// The glTF node index.
    pub instance_id: u32,
}

/// Gathers the annotations of the images `images` (in order) into one COCO file to be written
/// at `coco_path` (whose folder the image paths are made relative to).
pub fn gather(images: &[PathBuf], coco_path: &Path) -> Result<Coco, CocoError> {
    let mut files: Vec<(&PathBuf, Sidecar)> = Vec::with_capacity(images.len());
    for image in images {
        let path = sidecar_path(image);
        match read_sidecar(&path).map_err(|e| e.to_string()) {
            Ok(file) if !file.annotated => {
                return Err(CocoError::Read {
                    path,
                    message: "it was written without --annotations".into(),
                });
            }
            Ok(file) => files.push((image, file)),
            Err(message) => return Err(CocoError::Read { path, message }),
        }
    }
    let mut names: BTreeMap<String, u64> = BTreeMap::new();
    for (_, file) in &files {
        for instance in &file.instances {
            names.entry(instance.category.clone()).or_insert(0);
        }
    }
    for (k, id) in names.values_mut().enumerate() {
        *id = k as u64 + 1;
    }
    let folder = coco_path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let mut coco = Coco {
        info: CocoInfo {
            description: "glint: exact per-instance ground truth".into(),
            version: env!("CARGO_PKG_VERSION").into(),
        },
        categories: names
            .iter()
            .map(|(name, &id)| CocoCategory {
                id,
                name: name.clone(),
                supercategory: String::new(),
            })
            .collect(),
        ..Coco::default()
    };
    for (index, (image, file)) in files.iter().enumerate() {
        let image_id = index as u64 + 1;
        coco.images.push(CocoImage {
            id: image_id,
            file_name: relative_to(image, folder),
            width: file.width,
            height: file.height,
        });
        for instance in &file.instances {
            let Some(bbox) = instance.visible.bbox else {
                continue;
            };
            coco.annotations.push(CocoAnnotation {
                id: coco.annotations.len() as u64 + 1,
                image_id,
                category_id: names.get(&instance.category).copied().unwrap_or(0),
                segmentation: instance.visible.mask.clone(),
                area: instance.visible.area,
                bbox,
                iscrowd: 0,
                amodal_segmentation: instance.amodal.mask.clone(),
                amodal_bbox: instance.amodal.bbox.unwrap_or(bbox),
                amodal_area: instance.amodal.area,
                visible_fraction: instance.visible_fraction,
                instance_id: instance.id,
            });
        }
    }
    Ok(coco)
}

/// How long `glint batch --coco` waits for jobs another batch claimed: 24 hours.
pub const COCO_WAIT: std::time::Duration = std::time::Duration::from_secs(24 * 3600);

/// Waits until every job of `jobs` (claimed by another batch when this one looked) is free
/// and complete, polling its claim every half second, for at most `timeout`. Fails, naming
/// the job, when a job's claim is released while its outputs are incomplete (the other batch
/// failed it, or was killed), or when `timeout` passes.
pub fn wait_for_others(
    jobs: &[&super::Job],
    claims: &super::claim::ClaimPolicy,
    timeout: std::time::Duration,
) -> Result<(), String> {
    let start = std::time::Instant::now();
    for job in jobs {
        loop {
            match super::claim::try_claim_with(job.output(), claims) {
                Ok(Some(held)) => {
                    held.release();
                    if super::runner::output_is_complete(job) {
                        break;
                    }
                    return Err(format!(
                        "job {} ({}): another glint batch claimed it but left {} incomplete; \
                         run the batch again to render it, then gather --coco",
                        job.index,
                        job.origin,
                        job.output().display()
                    ));
                }
                Ok(None) if start.elapsed() < timeout => {
                    std::thread::sleep(std::time::Duration::from_millis(500));
                }
                Ok(None) => {
                    return Err(format!(
                        "job {} ({}): still claimed by another glint batch after {} s; gather \
                         --coco once it has finished (run the batch again with --coco)",
                        job.index,
                        job.origin,
                        timeout.as_secs()
                    ));
                }
                Err(e) => {
                    return Err(format!(
                        "job {} ({}): cannot check its claim: {e}",
                        job.index, job.origin
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Writes `coco` as JSON to `path`, atomically.
pub fn write_coco(path: &Path, coco: &Coco) -> Result<(), CocoError> {
    use std::io::Write;
    let text = serde_json::to_string(coco).map_err(|e| OutputError::Encode {
        path: path.to_path_buf(),
        format: "JSON",
        message: e.to_string(),
    })?;
    crate::output::write_atomically(path, |writer| {
        writer
            .write_all(text.as_bytes())
            .and_then(|()| writer.write_all(b"\n"))
            .map_err(|source| OutputError::Io {
                path: path.to_path_buf(),
                source,
            })
    })?;
    Ok(())
}

/// `path` relative to `folder` when it lies inside it, else as given.
fn relative_to(path: &Path, folder: &Path) -> String {
    let absolute = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let (p, f) = (absolute(path), absolute(folder));
    p.strip_prefix(&f)
        .map_or(p.as_path(), |r| r)
        .to_string_lossy()
        .into_owned()
}
