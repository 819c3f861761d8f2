//! Scene fingerprints: what a partial EXR was rendered from, so that `glint merge` refuses
//! to add parts of different renders (another scene file, another frame, another camera,
//! another texture) whose spp and seed happen to match.
//!
//! The fingerprint is the 128-bit XXH3 hash (a fixed, specified algorithm, so it is the same
//! on every machine and glint build) of, in order: a format tag; the scene file's bytes (the
//! `.gltf` or `.glb` itself); each external file the scene reads, in the order of its
//! `buffers` then its `images` (the URI, then the file's length and bytes; the file resolved
//! as the loader resolves it, [`crate::scene::gltf::external_path`]; data URIs and GLB chunks
//! are in the scene file's bytes already); the scene index (`--scene`) and animation time
//! (`--time`); the image size; and the camera actually rendered through (its
//! world-from-camera matrix and projection, as f32 bits). Parts whose fingerprints differ are
//! from different renders. Every file is read streamed, 1 MiB at a time.
//!
//! Not covered: an environment map or light file given to the render (`--environment`,
//! `--lights`), which are not part of the scene.

use crate::scene::gltf::SceneSelection;
use crate::scene::{Camera, Projection, SceneSource};
use std::io::Read;
use std::path::{Path, PathBuf};
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
    /// The metallic-roughness model that rendered the part (`compensated` or `spec`,
    /// [`crate::bsdf::BrdfModel::name`]), when known. Not part of the fingerprint (the scene is
    /// the same), but `glint merge` refuses parts of different models by it.
    pub brdf: Option<String>,
}

/// Changes whenever the hashed inputs change meaning.
const FORMAT: &[u8] = b"glint scene fingerprint 2\0";

/// The bytes read from a file at a time while hashing it.
const CHUNK_BYTES: usize = 1 << 20;

/// The GLB magic, "glTF".
const GLB_MAGIC: &[u8; 4] = b"glTF";

/// The type of a GLB chunk holding JSON, "JSON" as a little-endian u32.
const GLB_JSON_CHUNK: u32 = 0x4E4F_534A;

/// GLB header (magic, version, length) plus the first chunk's header (length, type), bytes.
const GLB_HEADERS_BYTES: usize = 20;

impl SceneTag {
    /// The tag of the scene `source` (the scene and time `selection` names) rendered through
    /// `camera` at `width`×`height`. Reads the scene file and every external file it names
    /// again (streamed); an error names the file.
    pub fn of(
        source: &SceneSource,
        selection: &SceneSelection,
        camera: &Camera,
        width: u32,
        height: u32,
    ) -> std::io::Result<Self> {
        let mut hash = Xxh3::new();
        hash.update(FORMAT);
        match source {
            SceneSource::Demo => hash.update(b"demo\0"),
            SceneSource::File(path) => hash_scene_files(&mut hash, path)?,
        }
        hash.update(&selection.scene.map_or(u64::MAX, |s| s as u64).to_le_bytes());
        hash.update(&selection.time.map_or(u32::MAX, f32::to_bits).to_le_bytes());
        // Only when named, so that the tags of files rendered without one do not change.
        if let Some(variant) = &selection.variant {
            hash.update(b"variant\0");
            hash.update(variant.as_bytes());
            hash.update(b"\0");
        }
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
            scene: source.label(),
            fingerprint: format!("{:032x}", hash.digest128()),
            kernels: None,
            brdf: None,
        })
    }
}

/// Hashes the scene file at `path`, then each external file it names ([`external_files`]),
/// each preceded by its URI.
fn hash_scene_files(hash: &mut Xxh3, path: &Path) -> std::io::Result<()> {
    hash_file(hash, path).map_err(|e| unreadable(&format!("the scene {}", path.display()), e))?;
    for file in external_files(path)? {
        hash.update(file.uri.as_bytes());
        hash.update(b"\0");
        hash_file(hash, &file.path).map_err(|e| {
            unreadable(
                &format!(
                    "{} (\"{}\", {} of the scene {})",
                    file.path.display(),
                    file.uri,
                    file.what,
                    path.display()
                ),
                e,
            )
        })?;
    }
    Ok(())
}

/// An external file a scene reads.
pub(crate) struct ExternalFile {
    /// "buffer 0", "image 3".
    pub(crate) what: String,
    /// The URI as the scene spells it.
    pub(crate) uri: String,
    /// Where the loader reads it.
    pub(crate) path: PathBuf,
}

/// The external files the scene at `path` names in its `buffers` and `images`, in that
/// order. A JSON that does not parse names none (such a scene does not load, so no part of it
/// is ever rendered).
pub(crate) fn external_files(path: &Path) -> std::io::Result<Vec<ExternalFile>> {
    let json =
        scene_json(path).map_err(|e| unreadable(&format!("the scene {}", path.display()), e))?;
    let Ok(root) = serde_json::from_slice::<serde_json::Value>(&json) else {
        return Ok(Vec::new());
    };
    let base_dir = crate::scene::gltf::base_dir(path);
    let mut files = Vec::new();
    for (key, noun) in [("buffers", "buffer"), ("images", "image")] {
        let items = root.get(key).and_then(|v| v.as_array());
        for (index, item) in items.into_iter().flatten().enumerate() {
            let Some(uri) = item.get("uri").and_then(|u| u.as_str()) else {
                continue;
            };
            if let Some(path) = crate::scene::gltf::external_path(uri, base_dir) {
                files.push(ExternalFile {
                    what: format!("{noun} {index}"),
                    uri: uri.to_string(),
                    path,
                });
            }
        }
    }
    Ok(files)
}

/// The scene a glTF file renders when none is asked for: its `scene` property, else its first
/// scene (as the loader picks); `None` when the file has no scene or cannot be read.
pub fn default_scene_index(path: &Path) -> Option<usize> {
    let json = scene_json(path).ok()?;
    let root = serde_json::from_slice::<serde_json::Value>(&json).ok()?;
    let scenes = root.get("scenes").and_then(|s| s.as_array())?.len();
    match root.get("scene").and_then(|s| s.as_u64()) {
        Some(i) if (i as usize) < scenes => Some(i as usize),
        _ => (scenes > 0).then_some(0),
    }
}

/// The JSON of the scene file at `path`: the whole file, or a GLB's JSON chunk (empty when the
/// GLB's first chunk is not JSON or is cut short).
fn scene_json(path: &Path) -> std::io::Result<Vec<u8>> {
    let mut file = std::fs::File::open(path)?;
    let mut headers = Vec::with_capacity(GLB_HEADERS_BYTES);
    (&mut file)
        .take(GLB_HEADERS_BYTES as u64)
        .read_to_end(&mut headers)?;
    if !headers.starts_with(GLB_MAGIC) {
        let mut json = headers;
        file.read_to_end(&mut json)?;
        return Ok(json);
    }
    let word = |at: usize| {
        headers
            .get(at..at + 4)
            .and_then(|b| b.try_into().ok())
            .map(u32::from_le_bytes)
    };
    let (Some(length), Some(GLB_JSON_CHUNK)) = (word(12), word(16)) else {
        return Ok(Vec::new());
    };
    let mut json = Vec::new();
    // `take` bounds the read by the chunk's declared length, the file's length bounds memory.
    file.take(u64::from(length)).read_to_end(&mut json)?;
    Ok(json)
}

/// Hashes the length and bytes of the file at `path`, 1 MiB at a time.
fn hash_file(hash: &mut Xxh3, path: &Path) -> std::io::Result<()> {
    // Checked before opening: opening a FIFO would block until a writer appears.
    if !std::fs::metadata(path)?.is_file() {
        return Err(std::io::Error::other("it is not a regular file"));
    }
    let mut file = std::fs::File::open(path)?;
    let mut buffer = vec![0u8; CHUNK_BYTES];
    let mut length: u64 = 0;
    loop {
        let n = file.read(&mut buffer)?;
        if n == 0 {
            break;
        }
        hash.update(&buffer[..n]);
        length += n as u64;
    }
    hash.update(&length.to_le_bytes());
    Ok(())
}

/// An I/O error while fingerprinting, naming `what` was being read.
fn unreadable(what: &str, e: std::io::Error) -> std::io::Error {
    std::io::Error::new(
        e.kind(),
        format!("cannot read {what} to fingerprint it: {e}"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;

    fn camera(x: f32) -> Camera {
        Camera {
            name: "c".into(),
            node: None,
            znear: None,
            zfar: None,
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
        let job = |path: &std::path::Path, time: Option<f32>| {
            let source = SceneSource::File(path.to_path_buf());
            (
                source,
                SceneSelection {
                    scene: None,
                    time,
                    variant: None,
                },
            )
        };
        let tag = |(s, t): &(SceneSource, SceneSelection), c: &Camera, w| {
            SceneTag::of(s, t, c, w, 10).unwrap().fingerprint
        };
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
        let (gone, at_rest) = job(&dir.path().join("gone.glb"), None);
        let missing = SceneTag::of(&gone, &at_rest, &camera(0.0), 1, 1);
        assert!(missing.unwrap_err().to_string().contains("gone.glb"));
    }

    #[test]
    fn an_external_buffer_or_image_changes_the_fingerprint() {
        let dir = tempfile::tempdir().unwrap();
        let scene = dir.path().join("s.gltf");
        std::fs::write(
            &scene,
            br#"{"asset":{"version":"2.0"},"buffers":[{"uri":"a%20b.bin","byteLength":4},
                {"uri":"data:application/octet-stream;base64,AAAA","byteLength":3}],
                "images":[{"uri":"sub/t.png"}]}"#,
        )
        .unwrap();
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        let source = SceneSource::File(scene.clone());
        let at_rest = SceneSelection::default();
        let tag = || SceneTag::of(&source, &at_rest, &camera(0.0), 4, 4).map(|t| t.fingerprint);
        std::fs::write(dir.path().join("a b.bin"), [1u8, 2, 3, 4]).unwrap();
        let missing = tag().unwrap_err().to_string();
        assert!(
            missing.contains("sub/t.png")
                && missing.contains("image 0")
                && missing.contains("s.gltf"),
            "{missing}"
        );
        std::fs::write(dir.path().join("sub/t.png"), b"png one").unwrap();
        let first = tag().unwrap();
        assert_eq!(first, tag().unwrap());
        std::fs::write(dir.path().join("sub/t.png"), b"png two").unwrap();
        let second = tag().unwrap();
        assert_ne!(first, second, "the image changed");
        std::fs::write(dir.path().join("a b.bin"), [1u8, 2, 3, 5]).unwrap();
        assert_ne!(second, tag().unwrap(), "the buffer changed");
    }
}
