//! Scene fingerprints: what a partial EXR was rendered from, so that `glint merge` refuses
//! to add parts of different renders (another scene file, another frame, another camera)
//! whose spp and seed happen to match.
//!
//! The fingerprint is the 128-bit XXH3 hash (a fixed, specified algorithm, so it is the same
//! on every machine and glint build) of, in order: a format tag; the scene file's bytes (the
//! `.gltf` or `.glb` itself, not the buffers or images a `.gltf` refers to); the scene index
//! (`--scene`) and animation time (`--time`); the image size; and the camera actually
//! rendered through (its world-from-camera matrix and projection, as f32 bits). Parts whose
//! fingerprints differ are from different renders; equal fingerprints with different
//! external `.bin` or texture files are not detected (re-export as `.glb` to include them).

use crate::render::job::{Job, SceneSource};
use crate::scene::{Camera, Projection};
use std::io::Read;
use xxhash_rust::xxh3::Xxh3;

/// The scene a partial render comes from: its name (for messages) and its fingerprint.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneTag {
    /// The scene's label: the file's path as given, or "demo scene".
    pub scene: String,
    /// 32 hex digits (see the module documentation).
    pub fingerprint: String,
    /// The ray-query code that rendered the part ([`crate::accel::Accel::kernels`]: backend,
    /// Embree version and kernels), when known. Not part of the fingerprint: parts rendered
    /// by different kernels still merge, but not bit for bit as one machine would have.
    pub kernels: Option<String>,
}

/// Changes whenever the hashed inputs change meaning.
const FORMAT: &[u8] = b"glint scene fingerprint 1\0";

impl SceneTag {
    /// The tag of `job` rendered through `camera` at `width`×`height`. Reads the scene file
    /// again (streamed, 1 MiB at a time); the error names it.
    pub fn of(job: &Job, camera: &Camera, width: u32, height: u32) -> std::io::Result<Self> {
        let mut hash = Xxh3::new();
        hash.update(FORMAT);
        match &job.scene {
            SceneSource::Demo => hash.update(b"demo\0"),
            SceneSource::File(path) => {
                let mut file = std::fs::File::open(path).map_err(|e| named(path, e))?;
                let mut buffer = vec![0u8; 1 << 20];
                loop {
                    let n = file.read(&mut buffer).map_err(|e| named(path, e))?;
                    if n == 0 {
                        break;
                    }
                    hash.update(&buffer[..n]);
                }
            }
        }
        let selection = &job.selection;
        hash.update(&selection.scene.map_or(u64::MAX, |s| s as u64).to_le_bytes());
        hash.update(&selection.time.map_or(u32::MAX, f32::to_bits).to_le_bytes());
        hash.update(&width.to_le_bytes());
        hash.update(&height.to_le_bytes());
        for x in camera.world_from_camera.to_cols_array() {
            hash.update(&x.to_bits().to_le_bytes());
        }
        let projection: [f32; 3] = match camera.projection {
            Projection::Perspective { yfov, aspect_ratio } => {
                [0.0, yfov, aspect_ratio.unwrap_or(-1.0)]
            }
            Projection::Orthographic { xmag, ymag } => [1.0, xmag, ymag],
        };
        for x in projection {
            hash.update(&x.to_bits().to_le_bytes());
        }
        Ok(SceneTag {
            scene: job.scene.label(),
            fingerprint: format!("{:032x}", hash.digest128()),
            kernels: None,
        })
    }
}

fn named(path: &std::path::Path, e: std::io::Error) -> std::io::Error {
    std::io::Error::new(
        e.kind(),
        format!(
            "cannot read the scene {} to fingerprint it: {e}",
            path.display()
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;

    fn camera(x: f32) -> Camera {
        Camera {
            name: "c".into(),
            world_from_camera: Mat4::from_translation(glam::Vec3::new(x, 0.0, 0.0)),
            projection: Projection::Perspective {
                yfov: 0.8,
                aspect_ratio: None,
            },
        }
    }

    #[test]
    fn every_input_changes_the_fingerprint() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.gltf");
        let b = dir.path().join("b.gltf");
        std::fs::write(&a, b"{\"asset\":{\"version\":\"2.0\"}}").unwrap();
        std::fs::write(&b, b"{\"asset\":{\"version\":\"2.0\"} }").unwrap();
        let job = |path: &std::path::Path, time: Option<f32>| Job {
            scene: SceneSource::File(path.to_path_buf()),
            selection: crate::scene::gltf::SceneSelection { scene: None, time },
            ..Job::default()
        };
        let tag = |j: &Job, c: &Camera, w| SceneTag::of(j, c, w, 10).unwrap().fingerprint;
        let base = tag(&job(&a, None), &camera(0.0), 10);
        assert_eq!(base.len(), 32);
        assert_eq!(base, tag(&job(&a, None), &camera(0.0), 10), "deterministic");
        for other in [
            tag(&job(&b, None), &camera(0.0), 10),
            tag(&job(&a, Some(0.5)), &camera(0.0), 10),
            tag(&job(&a, None), &camera(1.0), 10),
            tag(&job(&a, None), &camera(0.0), 11),
        ] {
            assert_ne!(base, other);
        }
        let missing = SceneTag::of(&job(&dir.path().join("gone.glb"), None), &camera(0.0), 1, 1);
        assert!(missing.unwrap_err().to_string().contains("gone.glb"));
    }
}
