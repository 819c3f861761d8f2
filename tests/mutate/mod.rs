//! Structure-aware mutation of glTF and GLB files, shared by the mutation test
//! (`tests/hostile/hostile_mutation.rs`) and the fuzz loop (`examples/fuzz_loader.rs`).
//!
//! Mutants are byte flips, truncations, splices and, most of the time, edits of one JSON value
//! of the `.gltf` text or the `.glb` JSON chunk (the GLB is rebuilt with correct chunk lengths
//! so that the edit reaches the loader rather than the header check): numbers set to hostile
//! magnitudes (1e39, 1e30, -1, 2^32), strings set to hostile URIs (/dev/zero, ../ paths,
//! percent-escaped traversal), members removed, arrays emptied or duplicated, types changed.

#![allow(dead_code)] // Each user needs a different subset.

use rand::{Rng, RngCore};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// A seed file: its bytes, its name, and the folder its relative URIs resolve against.
pub struct Seed {
    pub name: String,
    pub bytes: Vec<u8>,
    pub dir: PathBuf,
}

/// Every `.gltf` and `.glb` under `roots` no larger than `max_bytes`, sorted by path (so that
/// a seeded run is reproducible).
pub fn seeds(roots: &[PathBuf], max_bytes: u64) -> Vec<Seed> {
    let mut files = Vec::new();
    let mut stack: Vec<PathBuf> = roots.to_vec();
    while let Some(dir) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            let Ok(meta) = entry.metadata() else { continue };
            if meta.is_dir() {
                stack.push(path);
            } else if matches!(
                path.extension().and_then(|e| e.to_str()),
                Some("gltf" | "glb")
            ) && meta.len() <= max_bytes
            {
                files.push(path);
            }
        }
    }
    files.sort();
    files
        .into_iter()
        .filter_map(|path| {
            let bytes = std::fs::read(&path).ok()?;
            Some(Seed {
                name: path.display().to_string(),
                dir: path.parent().unwrap_or(Path::new(".")).to_path_buf(),
                bytes,
            })
        })
        .collect()
}

/// The JSON of a `.gltf` or `.glb`, and the GLB's BIN chunk if any.
fn split(bytes: &[u8]) -> Option<(Value, Option<Vec<u8>>)> {
    if bytes.starts_with(b"glTF") {
        let word = |i: usize| -> Option<usize> {
            Some(u32::from_le_bytes(bytes.get(i..i + 4)?.try_into().ok()?) as usize)
        };
        let json_len = word(12)?;
        let json = bytes.get(20..20 + json_len)?;
        let bin = word(20 + json_len).and_then(|len| {
            bytes
                .get(28 + json_len..28 + json_len + len)
                .map(<[u8]>::to_vec)
        });
        Some((serde_json::from_slice(json).ok()?, bin))
    } else {
        Some((serde_json::from_slice(bytes).ok()?, None))
    }
}

/// A GLB of `json` and `bin`, with the chunk lengths and padding glTF requires.
pub fn glb(json: &[u8], bin: Option<&[u8]>) -> Vec<u8> {
    let mut json = json.to_vec();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut chunks = Vec::new();
    chunks.extend_from_slice(&(json.len() as u32).to_le_bytes());
    chunks.extend_from_slice(b"JSON");
    chunks.extend_from_slice(&json);
    if let Some(bin) = bin {
        let mut bin = bin.to_vec();
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        chunks.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        chunks.extend_from_slice(b"BIN\0");
        chunks.extend_from_slice(&bin);
    }
    let mut out = Vec::with_capacity(12 + chunks.len());
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&((12 + chunks.len()) as u32).to_le_bytes());
    out.extend_from_slice(&chunks);
    out
}

const NUMBERS: &[f64] = &[
    0.0,
    -0.0,
    -1.0,
    1.0,
    2.0,
    3.0,
    1e39,
    -1e39,
    1e30,
    -1e30,
    1e-30,
    1e19,
    4294967295.0,
    4294967296.0,
    65535.0,
    65536.0,
    2147483647.0,
    5120.0,
    5121.0,
    5123.0,
    5125.0,
    5126.0,
    0.5,
];
const STRINGS: &[&str] = &[
    "/dev/zero",
    "/etc/passwd",
    "../../../../etc/passwd",
    "..%2F..%2F..%2Fetc%2Fpasswd",
    "missing.bin",
    "data:application/octet-stream;base64,AAAA",
    "data:image/png;base64,iVBORw0KGgo=",
    "data:,",
    "",
    "image/png",
    "image/jpeg",
    "perspective",
    "orthographic",
    "spot",
    "VEC3",
    "SCALAR",
    "MAT4",
    "KHR_texture_transform",
    "KHR_draco_mesh_compression",
    "\u{0}",
];

/// Paths to every value in `v` (object keys and array indices).
fn paths(v: &Value, prefix: &mut Vec<PathStep>, out: &mut Vec<Vec<PathStep>>) {
    out.push(prefix.clone());
    match v {
        Value::Object(map) => {
            for (k, child) in map {
                prefix.push(PathStep::Key(k.clone()));
                paths(child, prefix, out);
                prefix.pop();
            }
        }
        Value::Array(items) => {
            for (i, child) in items.iter().enumerate() {
                prefix.push(PathStep::Index(i));
                paths(child, prefix, out);
                prefix.pop();
            }
        }
        _ => {}
    }
}

#[derive(Clone)]
enum PathStep {
    Key(String),
    Index(usize),
}

fn at<'v>(v: &'v mut Value, path: &[PathStep]) -> Option<&'v mut Value> {
    let mut v = v;
    for step in path {
        v = match step {
            PathStep::Key(k) => v.get_mut(k)?,
            PathStep::Index(i) => v.get_mut(*i)?,
        };
    }
    Some(v)
}

/// One edit of one value of `json`.
fn mutate_json(json: &mut Value, rng: &mut impl RngCore) {
    let mut all = Vec::new();
    paths(json, &mut Vec::new(), &mut all);
    if all.is_empty() {
        return;
    }
    let path = all[rng.random_range(0..all.len())].clone();
    // Removing a member needs the parent.
    if rng.random_bool(0.15)
        && let Some((last, parent_path)) = path.split_last()
        && let Some(parent) = at(json, parent_path)
    {
        match (parent, last) {
            (Value::Object(map), PathStep::Key(k)) => {
                map.remove(k);
            }
            (Value::Array(items), PathStep::Index(i)) if *i < items.len() => {
                items.remove(*i);
            }
            _ => {}
        }
        return;
    }
    let Some(target) = at(json, &path) else {
        return;
    };
    *target = match target {
        Value::Number(n) => {
            let x = n.as_f64().unwrap_or(0.0);
            match rng.random_range(0..4) {
                0 => Value::from(NUMBERS[rng.random_range(0..NUMBERS.len())]),
                1 => Value::from(x + f64::from(rng.random_range(-3i32..=3))),
                2 => Value::from(x * 1e30),
                _ => Value::from(rng.random_range(0u64..1 << 33)),
            }
        }
        Value::String(_) => Value::from(STRINGS[rng.random_range(0..STRINGS.len())]),
        Value::Array(items) => match rng.random_range(0..3) {
            0 => Value::Array(Vec::new()),
            1 if !items.is_empty() => {
                let mut items = items.clone();
                items.push(items[rng.random_range(0..items.len())].clone());
                Value::Array(items)
            }
            _ => Value::from(NUMBERS[rng.random_range(0..NUMBERS.len())]),
        },
        Value::Object(_) if rng.random_bool(0.5) => Value::Object(Default::default()),
        Value::Bool(b) => Value::Bool(!*b),
        _ => match rng.random_range(0..3) {
            0 => Value::Null,
            1 => Value::from(STRINGS[rng.random_range(0..STRINGS.len())]),
            _ => Value::from(NUMBERS[rng.random_range(0..NUMBERS.len())]),
        },
    };
}

/// One mutant of `seed`: 1–3 JSON edits most of the time, else byte-level damage.
pub fn mutate(seed: &[u8], rng: &mut impl RngCore) -> Vec<u8> {
    if rng.random_bool(0.7)
        && let Some((mut json, bin)) = split(seed)
    {
        for _ in 0..rng.random_range(1..=3) {
            mutate_json(&mut json, rng);
        }
        let text = serde_json::to_vec(&json).unwrap_or_default();
        return if seed.starts_with(b"glTF") {
            glb(&text, bin.as_deref())
        } else {
            text
        };
    }
    let mut bytes = seed.to_vec();
    if bytes.is_empty() {
        return bytes;
    }
    match rng.random_range(0..4) {
        0 => bytes.truncate(rng.random_range(0..bytes.len())),
        1 => {
            // Splice a copy of one range over another.
            let a = rng.random_range(0..bytes.len());
            let b = rng.random_range(0..bytes.len());
            let n = rng.random_range(1..=64).min(bytes.len() - a.max(b));
            let chunk = bytes[a..a + n].to_vec();
            bytes[b..b + n].copy_from_slice(&chunk);
        }
        _ => {
            for _ in 0..rng.random_range(1..8) {
                // Aim most flips at the structure (headers and JSON come first).
                let limit = if rng.random_bool(0.8) {
                    4096.min(bytes.len())
                } else {
                    bytes.len()
                };
                let at = rng.random_range(0..limit);
                bytes[at] = rng.random();
            }
        }
    }
    bytes
}

/// What one execution gave.
pub enum Outcome {
    /// Loaded and prepared.
    Rendered,
    /// Refused with a one-line error naming the file.
    Refused,
    /// A contract breach: a panic, or a malformed error (described).
    Crash(String),
}

/// Loads `bytes` as the loader would a file named `label` in `dir`, builds the obvhs BVH (and
/// Embree's, when built in) over the result, and classifies what happened. Panics are
/// caught; the error must be one line that starts with the label.
pub fn execute(bytes: &[u8], label: &str, dir: &Path) -> Outcome {
    let run = || -> Result<(), String> {
        let loaded = glint::scene::gltf::load_slice_with_warnings(bytes, label, Some(dir))
            .map_err(|e| {
                let message = e.to_string();
                if message.starts_with(label) {
                    message
                } else {
                    format!("an error that does not name the file\n{message}")
                }
            })?;
        let meshes = loaded.scene.triangle_meshes();
        for &kind in glint::accel::BackendKind::available() {
            glint::accel::build(kind, &meshes, Default::default()).map_err(|e| e.to_string())?;
        }
        Ok(())
    };
    match std::panic::catch_unwind(run) {
        Ok(Ok(())) => Outcome::Rendered,
        Ok(Err(message)) => {
            if message.contains('\n') {
                Outcome::Crash(format!("a multi-line error: {message}"))
            } else {
                Outcome::Refused
            }
        }
        Err(payload) => {
            let text = payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            Outcome::Crash(format!("panic: {text}"))
        }
    }
}
