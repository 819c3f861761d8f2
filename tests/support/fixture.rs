//! Helpers shared by the loader tests: hand-built glTF documents with their data in base64
//! data URIs, temporary folders, and the shared sample scenes.

#![allow(dead_code)] // Each test file uses a different subset.

use base64::Engine as _;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The shared, read-only sample scenes (beside the repository).
pub fn scenes_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes");
    assert!(dir.is_dir(), "shared scenes not found at {}", dir.display());
    dir
}

/// A glTF document under construction: one binary buffer, its views and accessors.
#[derive(Default)]
pub struct Fixture {
    pub bin: Vec<u8>,
    pub views: Vec<Value>,
    pub accessors: Vec<Value>,
}

impl Fixture {
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends raw bytes as a buffer view; returns the view index.
    pub fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()}));
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }

    /// Adds an accessor; returns its index.
    pub fn accessor(&mut self, accessor: Value) -> usize {
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// Float data of the given glTF type ("VEC3", ...); `components` per element.
    pub fn floats(&mut self, data: &[f32], type_: &str, components: usize) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|x| x.to_le_bytes()).collect();
        let view = self.view(&bytes);
        self.accessor(json!({"bufferView": view, "componentType": 5126, "count": data.len() / components, "type": type_}))
    }

    /// POSITION data, with the min / max glTF requires.
    pub fn positions(&mut self, points: &[[f32; 3]]) -> usize {
        let flat: Vec<f32> = points.iter().flatten().copied().collect();
        let index = self.floats(&flat, "VEC3", 3);
        let lo = (0..3)
            .map(|i| points.iter().map(|p| p[i]).fold(f32::INFINITY, f32::min))
            .collect::<Vec<_>>();
        let hi = (0..3)
            .map(|i| {
                points
                    .iter()
                    .map(|p| p[i])
                    .fold(f32::NEG_INFINITY, f32::max)
            })
            .collect::<Vec<_>>();
        self.accessors[index]["min"] = json!(lo);
        self.accessors[index]["max"] = json!(hi);
        index
    }

    /// Unsigned 16-bit indices.
    pub fn indices_u16(&mut self, indices: &[u16]) -> usize {
        let bytes: Vec<u8> = indices.iter().flat_map(|x| x.to_le_bytes()).collect();
        let view = self.view(&bytes);
        self.accessor(json!({"bufferView": view, "componentType": 5123, "count": indices.len(), "type": "SCALAR"}))
    }

    /// The document: `rest` (nodes, meshes, ...) plus asset, buffer, views and accessors,
    /// with the buffer as a base64 data URI.
    pub fn document(&self, rest: Value) -> Value {
        let mut doc = rest;
        doc["asset"] = json!({"version": "2.0"});
        doc["buffers"] = json!([{"byteLength": self.bin.len(), "uri": data_uri("application/octet-stream", &self.bin)}]);
        doc["bufferViews"] = json!(self.views);
        doc["accessors"] = json!(self.accessors);
        doc
    }

    /// The document as `.gltf` text.
    pub fn gltf_text(&self, rest: Value) -> String {
        serde_json::to_string(&self.document(rest)).expect("serialize")
    }

    /// Loads the document from memory; errors and warnings name `fixture.gltf`.
    pub fn load(
        &self,
        rest: Value,
    ) -> Result<glint::scene::gltf::Loaded, glint::scene::gltf::LoadError> {
        glint::scene::gltf::load_slice_with_warnings(
            self.gltf_text(rest).as_bytes(),
            "fixture.gltf",
            None,
        )
    }
}

/// A base64 data URI.
pub fn data_uri(media_type: &str, bytes: &[u8]) -> String {
    format!(
        "data:{media_type};base64,{}",
        base64::engine::general_purpose::STANDARD.encode(bytes)
    )
}

/// A PNG of the given RGBA8 texels.
pub fn png(width: u32, height: u32, rgba: &[u8]) -> Vec<u8> {
    let image = image::RgbaImage::from_raw(width, height, rgba.to_vec()).expect("texel count");
    let mut bytes = Vec::new();
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .expect("encode PNG");
    bytes
}

/// A folder under the system temporary directory, removed when dropped.
pub struct TempDir(pub PathBuf);

impl TempDir {
    pub fn new(name: &str) -> Self {
        static NEXT: AtomicUsize = AtomicUsize::new(0);
        let dir = std::env::temp_dir().join(format!(
            "glint-test-{}-{}-{name}",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir_all(&dir).expect("create temp dir");
        TempDir(dir)
    }

    pub fn path(&self) -> &Path {
        &self.0
    }

    /// Writes a file into the folder; returns its path.
    pub fn write(&self, name: &str, bytes: &[u8]) -> PathBuf {
        let path = self.0.join(name);
        std::fs::write(&path, bytes).expect("write fixture file");
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// One triangle's geometric normal, (v1 − v0) × (v2 − v0).
pub fn triangle_normal(mesh: &glint::scene::Mesh, triangle: usize) -> glam::Vec3 {
    let [a, b, c] = mesh.indices[triangle].map(|i| mesh.positions[i as usize]);
    (b - a).cross(c - a)
}
