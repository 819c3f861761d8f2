//! The seed corpus: small inputs per target, made here with the encoders glint's tests use
//! (the image and exr crates, meshoptimizer, Binomial's Basis Universal encoder, draco-core)
//! and written by `fuzz seeds` to `tests/fuzz-corpus/TARGET/`, where they are committed. Each
//! is a few hundred bytes to a few KiB: a small seed keeps an execution fast, and each covers
//! a feature of its format that mutation alone would rarely build.
//!
//! [`shared_extras`] adds, at run time, the shared assets small enough to be seeds.

use super::engine::bundle;
use super::targets::MESHOPT_HEADER;
use serde_json::{Value, json};
use std::path::Path;

/// Named seed files.
type Seeds = Vec<(String, Vec<u8>)>;

/// Writes every target's seeds under `dir` (replacing what is there); returns the count.
pub fn write_all(dir: &Path) -> Result<usize, String> {
    let sets: Vec<(&str, Seeds)> = vec![
        ("gltf", gltf_seeds()),
        ("ktx2", ktx2_seeds()),
        ("meshopt", meshopt_seeds()),
        ("image", image_seeds()),
        ("env", env_seeds()),
        ("jobs", text_seeds(JOBS)),
        ("lights", text_seeds(LIGHTS)),
        (
            "outputs",
            vec![
                ("distinct".into(), vec![0, 0, 7, 1, 5, 0]),
                ("dot-slash".into(), vec![0, 0, 1, 0]),
                ("png-exr-sidecars".into(), vec![0, 1, 4, 1]),
                ("sidecar-on-job-file".into(), vec![0, 1]),
            ],
        ),
        ("draco", draco_seeds()),
    ];
    let mut count = 0;
    for (target, seeds) in sets {
        let folder = dir.join(target);
        let _ = std::fs::remove_dir_all(&folder);
        std::fs::create_dir_all(&folder)
            .map_err(|e| format!("cannot create {}: {e}", folder.display()))?;
        for (name, bytes) in seeds {
            let path = folder.join(name);
            std::fs::write(&path, bytes).map_err(|e| format!("{}: {e}", path.display()))?;
            count += 1;
        }
    }
    Ok(count)
}

/// Shared assets used as extra seeds of `target` at run time (those no larger than `max_len`).
pub fn shared_extras(target: &str, max_len: usize) -> Vec<Vec<u8>> {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared");
    let mut out = Vec::new();
    match target {
        "gltf" => {
            // The Draco test files (Google's encoder).
            let draco = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/draco");
            collect(&draco, &["glb"], max_len, &mut out);
            for seed in super::mutate::seeds(
                &[shared.join("khronos"), shared.join("scenes")],
                max_len as u64,
            ) {
                if seed.name.ends_with(".glb") {
                    out.push(seed.bytes);
                    continue;
                }
                // A .gltf with its external files, as one bundle, if small enough.
                let Ok(json) = serde_json::from_slice::<Value>(&seed.bytes) else {
                    continue;
                };
                let mut files = Vec::new();
                for uri in ["buffers", "images"]
                    .iter()
                    .filter_map(|k| json.get(*k).and_then(Value::as_array))
                    .flatten()
                    .filter_map(|item| item.get("uri").and_then(Value::as_str))
                    .filter(|uri| !uri.starts_with("data:"))
                {
                    if let Ok(bytes) = std::fs::read(seed.dir.join(uri)) {
                        files.push((uri.to_string(), bytes));
                    }
                }
                let parts: Vec<(String, &[u8])> = files
                    .iter()
                    .map(|(n, b)| (n.clone(), b.as_slice()))
                    .collect();
                let joined = bundle::join(&seed.bytes, &parts);
                if joined.len() <= max_len {
                    out.push(joined);
                }
            }
        }
        "image" => {
            for dir in [shared.join("khronos"), shared.join("scenes")] {
                collect(&dir, &["png", "jpg", "jpeg", "webp"], max_len, &mut out);
            }
        }
        "env" => collect(&shared.join("env"), &["hdr", "exr"], max_len, &mut out),
        _ => {}
    }
    out
}

fn collect(dir: &Path, extensions: &[&str], max_len: usize, out: &mut Vec<Vec<u8>>) {
    let mut stack = vec![dir.to_path_buf()];
    let mut files = Vec::new();
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else if path
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| extensions.contains(&e))
                && entry.metadata().is_ok_and(|m| m.len() as usize <= max_len)
            {
                files.push(path);
            }
        }
    }
    files.sort();
    out.extend(files.iter().filter_map(|p| std::fs::read(p).ok()));
}

/// A GLB under construction: a BIN chunk and its views and accessors.
#[derive(Default)]
struct Glb {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Glb {
    /// Appends `bytes` as a buffer view (4-byte aligned); returns its index.
    fn view(&mut self, bytes: &[u8], stride: Option<usize>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut view =
            json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()});
        if let Some(stride) = stride {
            view["byteStride"] = stride.into();
        }
        self.bin.extend_from_slice(bytes);
        self.views.push(view);
        self.views.len() - 1
    }

    /// A float accessor of `values` (VEC2/VEC3/VEC4/SCALAR by `kind`); returns its index.
    fn floats(&mut self, values: &[f32], kind: &str) -> usize {
        let n = match kind {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" => 4,
            _ => 16,
        };
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, None);
        let mut accessor = json!({"bufferView": view, "componentType": 5126, "count": values.len() / n, "type": kind});
        if kind == "VEC3" {
            let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
            for v in values.chunks(3) {
                for i in 0..3 {
                    lo[i] = lo[i].min(v[i]);
                    hi[i] = hi[i].max(v[i]);
                }
            }
            accessor["min"] = json!(lo);
            accessor["max"] = json!(hi);
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// A u16 index accessor.
    fn indices(&mut self, values: &[u16]) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, None);
        self.accessors.push(json!({"bufferView": view, "componentType": 5123, "count": values.len(), "type": "SCALAR"}));
        self.accessors.len() - 1
    }

    /// The GLB of `json` with this BIN chunk and these views and accessors.
    fn finish(self, mut json: Value) -> Vec<u8> {
        json["asset"] = json!({"version": "2.0"});
        json["buffers"] = json!([{"byteLength": self.bin.len()}]);
        json["bufferViews"] = Value::Array(self.views);
        json["accessors"] = Value::Array(self.accessors);
        super::targets::glb(json.to_string().as_bytes(), &self.bin)
    }
}

const QUAD_POSITIONS: [f32; 12] = [-1., -1., 0., 1., -1., 0., 1., 1., 0., -1., 1., 0.];
const QUAD_NORMALS: [f32; 12] = [0., 0., 1., 0., 0., 1., 0., 0., 1., 0., 0., 1.];
const QUAD_UVS: [f32; 8] = [0., 1., 1., 1., 1., 0., 0., 0.];
const QUAD_INDICES: [u16; 6] = [0, 1, 2, 0, 2, 3];

/// A 4×4 RGBA test image: a gradient with a checker in blue.
fn rgba(size: u32, alpha: bool) -> Vec<u8> {
    let mut out = Vec::new();
    for y in 0..size {
        for x in 0..size {
            out.extend_from_slice(&[
                (x * 255 / size.max(1)) as u8,
                (y * 255 / size.max(1)) as u8,
                if (x + y) % 2 == 0 { 200 } else { 40 },
                if alpha {
                    (255 - x * 200 / size.max(1)) as u8
                } else {
                    255
                },
            ]);
        }
    }
    out
}

fn png(size: u32, alpha: bool) -> Vec<u8> {
    let mut out = Vec::new();
    let _ = image::RgbaImage::from_raw(size, size, rgba(size, alpha))
        .map(|img| img.write_to(&mut std::io::Cursor::new(&mut out), image::ImageFormat::Png));
    out
}

fn gltf_seeds() -> Vec<(String, Vec<u8>)> {
    let mut seeds = Vec::new();
    // 1. A textured, lit quad with a camera, a light and every material layer glint reads.
    let mut g = Glb::default();
    let pos = g.floats(&QUAD_POSITIONS, "VEC3");
    let nrm = g.floats(&QUAD_NORMALS, "VEC3");
    let uv = g.floats(&QUAD_UVS, "VEC2");
    let idx = g.indices(&QUAD_INDICES);
    let image = g.view(&png(4, true), None);
    seeds.push((
        "textured-quad.glb".to_string(),
        g.finish(json!({
            "extensionsUsed": ["KHR_lights_punctual", "KHR_texture_transform", "KHR_materials_clearcoat",
                "KHR_materials_sheen", "KHR_materials_transmission", "KHR_materials_volume",
                "KHR_materials_emissive_strength"],
            "scene": 0,
            "scenes": [{"nodes": [0, 1, 2]}],
            "nodes": [
                {"mesh": 0, "rotation": [0, 0, 0, 1], "scale": [1, 2, 1]},
                {"camera": 0, "translation": [0, 0, 3]},
                {"extensions": {"KHR_lights_punctual": {"light": 0}}, "translation": [0, 2, 2]}
            ],
            "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}],
            "extensions": {"KHR_lights_punctual": {"lights": [
                {"type": "spot", "intensity": 10, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}
            ]}},
            "meshes": [{"primitives": [{"attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv},
                "indices": idx, "material": 0}]}],
            "materials": [{
                "pbrMetallicRoughness": {"baseColorTexture": {"index": 0,
                    "extensions": {"KHR_texture_transform": {"scale": [2, 2], "rotation": 0.3}}},
                    "metallicFactor": 0.2, "roughnessFactor": 0.5},
                "normalTexture": {"index": 0, "scale": 0.5},
                "emissiveFactor": [1, 0.5, 0],
                "alphaMode": "MASK", "alphaCutoff": 0.4, "doubleSided": true,
                "extensions": {
                    "KHR_materials_clearcoat": {"clearcoatFactor": 0.5, "clearcoatRoughnessFactor": 0.1},
                    "KHR_materials_sheen": {"sheenColorFactor": [1, 0, 0], "sheenRoughnessFactor": 0.5},
                    "KHR_materials_transmission": {"transmissionFactor": 0.5},
                    "KHR_materials_volume": {"thicknessFactor": 0.1, "attenuationDistance": 2},
                    "KHR_materials_emissive_strength": {"emissiveStrength": 4}
                }
            }],
            "textures": [{"source": 0, "sampler": 0}],
            "samplers": [{"magFilter": 9728, "wrapS": 33648, "wrapT": 33071}],
            "images": [{"bufferView": image, "mimeType": "image/png"}]
        })),
    ));
    // 2. Animation (all three interpolations), morph targets and their weights.
    let mut g = Glb::default();
    let pos = g.floats(&QUAD_POSITIONS, "VEC3");
    let delta = g.floats(&[0., 0., 1., 0., 0., 1., 0., 0., 0., 0., 0., 0.], "VEC3");
    let idx = g.indices(&QUAD_INDICES);
    let times = g.floats(&[0., 1.], "SCALAR");
    let rot = g.floats(
        &[
            0.,
            0.,
            0.,
            1.,
            0.,
            std::f32::consts::FRAC_1_SQRT_2,
            0.,
            std::f32::consts::FRAC_1_SQRT_2,
        ],
        "VEC4",
    );
    let trans = g.floats(&[0., 0., 0., 1., 0., 0.], "VEC3");
    let cubic = g.floats(
        &[
            0., 0., 0., 1., 1., 1., 0., 0., 0., 0., 0., 0., 2., 2., 2., 0., 0., 0.,
        ],
        "VEC3",
    );
    let weights = g.floats(&[0., 1.], "SCALAR");
    seeds.push((
        "animated-morph.glb".to_string(),
        g.finish(json!({
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0, "children": [1]}, {"mesh": 0, "translation": [2, 0, 0]}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": pos}, "indices": idx,
                "targets": [{"POSITION": delta}]}], "weights": [0.5]}],
            "animations": [{"samplers": [
                {"input": times, "output": rot, "interpolation": "LINEAR"},
                {"input": times, "output": trans, "interpolation": "STEP"},
                {"input": times, "output": cubic, "interpolation": "CUBICSPLINE"},
                {"input": times, "output": weights}
            ], "channels": [
                {"sampler": 0, "target": {"node": 0, "path": "rotation"}},
                {"sampler": 1, "target": {"node": 1, "path": "translation"}},
                {"sampler": 2, "target": {"node": 0, "path": "scale"}},
                {"sampler": 3, "target": {"node": 0, "path": "weights"}}
            ]}]
        })),
    ));
    // 3. A skin with two joints, and instancing.
    let mut g = Glb::default();
    let pos = g.floats(&QUAD_POSITIONS, "VEC3");
    let idx = g.indices(&QUAD_INDICES);
    let joints_bytes: Vec<u8> = [0u8, 1, 0, 0].repeat(4);
    let jv = g.view(&joints_bytes, None);
    g.accessors
        .push(json!({"bufferView": jv, "componentType": 5121, "count": 4, "type": "VEC4"}));
    let joints = g.accessors.len() - 1;
    let wts = g.floats(&[0.5, 0.5, 0., 0.].repeat(4), "VEC4");
    let ibm = g.floats(
        &[
            1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1.,
        ]
        .repeat(2),
        "MAT4",
    );
    let inst = g.floats(&[0., 0., 0., 3., 0., 0.], "VEC3");
    seeds.push((
        "skin-instancing.glb".to_string(),
        g.finish(json!({
            "extensionsUsed": ["EXT_mesh_gpu_instancing"],
            "scenes": [{"nodes": [0, 1, 2, 3]}],
            "nodes": [
                {"mesh": 0, "skin": 0},
                {"translation": [0, 1, 0]},
                {"rotation": [0, 0, 0.3827, 0.9239]},
                {"mesh": 1, "extensions": {"EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": inst}}}}
            ],
            "skins": [{"joints": [1, 2], "inverseBindMatrices": ibm}],
            "meshes": [
                {"primitives": [{"attributes": {"POSITION": pos, "JOINTS_0": joints, "WEIGHTS_0": wts}, "indices": idx}]},
                {"primitives": [{"attributes": {"POSITION": pos}, "mode": 5}]}
            ]
        })),
    ));
    // 4. Sparse accessors, one without a buffer view, and a triangle fan.
    let mut g = Glb::default();
    let pos = g.floats(&QUAD_POSITIONS, "VEC3");
    let sparse_idx = g.view(&[1u8, 0, 2, 0], None);
    let sparse_val = g.view(
        &[0f32, 0., 2., 0., 0., 2.]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect::<Vec<_>>(),
        None,
    );
    g.accessors[pos]["sparse"] = json!({"count": 2, "indices": {"bufferView": sparse_idx, "componentType": 5123},
        "values": {"bufferView": sparse_val}});
    g.accessors
        .push(json!({"componentType": 5126, "count": 4, "type": "VEC3",
        "sparse": {"count": 2, "indices": {"bufferView": sparse_idx, "componentType": 5123},
        "values": {"bufferView": sparse_val}}}));
    let viewless = g.accessors.len() - 1;
    seeds.push((
        "sparse-fan.glb".to_string(),
        g.finish(json!({
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}],
            "meshes": [{"primitives": [
                {"attributes": {"POSITION": pos}, "mode": 6},
                {"attributes": {"POSITION": pos, "NORMAL": viewless}, "mode": 4}
            ]}]
        })),
    ));
    // 5. KHR_mesh_quantization: normalized short positions and byte texture coordinates.
    let mut g = Glb::default();
    let shorts: Vec<u8> = [0i16, 0, 0, 0, 32767, 0, 0, 0, 32767, 32767, 0, 0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let sv = g.view(&shorts, Some(8));
    g.accessors.push(
        json!({"bufferView": sv, "componentType": 5122, "normalized": true, "count": 3,
        "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}),
    );
    let bv = g.view(&[0u8, 0, 255, 0, 0, 255, 0, 0], Some(4));
    g.accessors.push(json!({"bufferView": bv, "componentType": 5121, "normalized": true, "count": 2, "type": "VEC2"}));
    seeds.push((
        "quantized.glb".to_string(),
        g.finish(json!({
            "extensionsUsed": ["KHR_mesh_quantization"],
            "extensionsRequired": ["KHR_mesh_quantization"],
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0, "scale": [2, 2, 2]}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}]
        })),
    ));
    // 6. A .gltf with an external buffer and image, as a bundle; and one with data URIs.
    let mut bin = Vec::new();
    for v in QUAD_POSITIONS.iter().chain(QUAD_UVS.iter()) {
        bin.extend_from_slice(&v.to_le_bytes());
    }
    for i in QUAD_INDICES {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    let doc = |buffer_uri: &str, image_uri: &str| {
        json!({
            "asset": {"version": "2.0"},
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
            "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
            "textures": [{"source": 0}],
            "images": [{"uri": image_uri}],
            "buffers": [{"uri": buffer_uri, "byteLength": 92}],
            "bufferViews": [
                {"buffer": 0, "byteOffset": 0, "byteLength": 48},
                {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                {"buffer": 0, "byteOffset": 80, "byteLength": 12}
            ],
            "accessors": [
                {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}
            ]
        })
        .to_string()
        .into_bytes()
    };
    let image = png(2, false);
    seeds.push((
        "external-files.bundle".to_string(),
        bundle::join(
            &doc("quad%20data.bin", "./tex.png"),
            &[
                ("quad data.bin".to_string(), &bin[..]),
                ("tex.png".to_string(), &image[..]),
            ],
        ),
    ));
    use base64::Engine as _;
    let b64 = |b: &[u8]| base64::engine::general_purpose::STANDARD.encode(b);
    seeds.push((
        "data-uris.gltf".to_string(),
        doc(
            &format!("data:application/octet-stream;base64,{}", b64(&bin)),
            &format!("data:image/png;base64,{}", b64(&image)),
        ),
    ));
    // 7. Textures in WebP and KTX2 (with PNG fallbacks), and a compressed mesh.
    let mut g = Glb::default();
    let pos = g.floats(&QUAD_POSITIONS, "VEC3");
    let uv = g.floats(&QUAD_UVS, "VEC2");
    let idx = g.indices(&QUAD_INDICES);
    let webp = g.view(&webp(4), None);
    let ktx = g.view(&ktx2(4, Codec::Uastc, true), None);
    let fallback = g.view(&png(2, false), None);
    seeds.push((
        "webp-ktx2.glb".to_string(),
        g.finish(json!({
            "extensionsUsed": ["EXT_texture_webp", "KHR_texture_basisu"],
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": pos, "TEXCOORD_0": uv}, "indices": idx, "material": 0}]}],
            "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                "metallicRoughnessTexture": {"index": 1}}, "emissiveTexture": {"index": 0}}],
            "textures": [
                {"source": 2, "extensions": {"EXT_texture_webp": {"source": 0}}},
                {"source": 2, "extensions": {"KHR_texture_basisu": {"source": 1}}}
            ],
            "images": [
                {"bufferView": webp, "mimeType": "image/webp"},
                {"bufferView": ktx, "mimeType": "image/ktx2"},
                {"bufferView": fallback, "mimeType": "image/png"}
            ]
        })),
    ));
    if let Some(glb) = meshopt_glb() {
        seeds.push(("meshopt.glb".to_string(), glb));
    }
    seeds
}

fn webp(size: u32) -> Vec<u8> {
    let mut out = Vec::new();
    let encoder = image::codecs::webp::WebPEncoder::new_lossless(&mut out);
    let _ = encoder.encode(
        &rgba(size, true),
        size,
        size,
        image::ExtendedColorType::Rgba8,
    );
    out
}

#[derive(Clone, Copy, PartialEq)]
enum Codec {
    Etc1s,
    Uastc,
    UastcZstd,
}

/// Binomial's encoder's KTX2 file of the `size`² test image.
fn ktx2(size: u32, codec: Codec, srgb: bool) -> Vec<u8> {
    use basisu_c_sys::BasisTextureFormat;
    use basisu_c_sys::common;
    use basisu_c_sys::extra::{
        BasisuEncoder, BasisuEncoderParams, SourceImage, SourceImageFormat, basisu_encoder_init,
        types::Extent3d,
    };
    basisu_encoder_init();
    let mut encoder = BasisuEncoder::new();
    let pixels = rgba(size, codec != Codec::Etc1s);
    if encoder
        .set_image(SourceImage {
            data: &pixels,
            format: SourceImageFormat::Rgba8,
            size: Extent3d {
                width: size,
                height: size,
                depth_or_array_layers: 1,
            },
        })
        .is_err()
    {
        return Vec::new();
    }
    let format = match codec {
        Codec::Etc1s => BasisTextureFormat::Etc1s,
        Codec::Uastc | Codec::UastcZstd => BasisTextureFormat::UastcLdr4x4,
    };
    let mut params = if srgb {
        BasisuEncoderParams::new_with_srgb_defaults(format)
    } else {
        BasisuEncoderParams::new_with_linear_defaults(format)
    }
    .with_removed_flags(common::BU_COMP_FLAGS_THREADED);
    if codec == Codec::Uastc {
        params = params.with_removed_flags(common::BU_COMP_FLAGS_KTX2_UASTC_ZSTD);
    }
    params.quality_level = 100;
    encoder.compress(params).unwrap_or_default()
}

fn ktx2_seeds() -> Vec<(String, Vec<u8>)> {
    vec![
        ("etc1s-8.ktx2".into(), ktx2(8, Codec::Etc1s, true)),
        ("uastc-4.ktx2".into(), ktx2(4, Codec::Uastc, false)),
        ("uastc-zstd-8.ktx2".into(), ktx2(8, Codec::UastcZstd, true)),
    ]
}

/// A meshopt target input: the 7-byte header, then the compressed bytes.
fn meshopt_input(mode: u8, filter: u8, stride: u8, count: u32, data: &[u8]) -> Vec<u8> {
    let mut out = vec![mode, filter, stride];
    out.extend_from_slice(&count.to_le_bytes());
    debug_assert_eq!(out.len(), MESHOPT_HEADER);
    out.extend_from_slice(data);
    out
}

#[cfg(feature = "meshopt")]
fn meshopt_seeds() -> Vec<(String, Vec<u8>)> {
    let positions: Vec<[f32; 3]> = QUAD_POSITIONS
        .chunks(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let indices: Vec<u32> = QUAD_INDICES.iter().map(|&i| u32::from(i)).collect();
    let mut seeds = Vec::new();
    if let Ok(data) = meshopt::encode_vertex_buffer(&positions) {
        seeds.push((
            "attributes-12.bin".into(),
            meshopt_input(0, 0, 12, 4, &data),
        ));
    }
    let unit: Vec<[f32; 4]> = vec![[0., 0., 1., 0.]; 4];
    let oct: Vec<[i8; 4]> = meshopt::encode_filter_oct(&unit, 8);
    if let Ok(data) = meshopt::encode_vertex_buffer(&oct) {
        seeds.push(("octahedral-4.bin".into(), meshopt_input(0, 1, 4, 4, &data)));
    }
    let quat: Vec<[i16; 4]> = meshopt::encode_filter_quat(&[[0., 0., 0., 1.]; 4], 12);
    if let Ok(data) = meshopt::encode_vertex_buffer(&quat) {
        seeds.push(("quaternion-8.bin".into(), meshopt_input(0, 2, 8, 4, &data)));
    }
    let exp: Vec<[u32; 3]> =
        meshopt::encode_filter_exp::<3>(&positions, 15, meshopt::EncodeExpMode::Separate);
    if let Ok(data) = meshopt::encode_vertex_buffer(&exp) {
        seeds.push((
            "exponential-12.bin".into(),
            meshopt_input(0, 3, 12, 4, &data),
        ));
    }
    if let Ok(data) = meshopt::encode_index_buffer(&indices, 4) {
        seeds.push(("triangles-4.bin".into(), meshopt_input(1, 0, 4, 6, &data)));
        seeds.push(("triangles-2.bin".into(), meshopt_input(1, 0, 2, 6, &data)));
    }
    if let Ok(data) = meshopt::encode_index_sequence(&indices, 4) {
        seeds.push(("indices-4.bin".into(), meshopt_input(2, 0, 4, 6, &data)));
    }
    seeds
}

#[cfg(not(feature = "meshopt"))]
fn meshopt_seeds() -> Vec<(String, Vec<u8>)> {
    Vec::new()
}

#[cfg(feature = "meshopt")]
fn meshopt_glb() -> Option<Vec<u8>> {
    let positions: Vec<[f32; 3]> = QUAD_POSITIONS
        .chunks(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let indices: Vec<u32> = QUAD_INDICES.iter().map(|&i| u32::from(i)).collect();
    let vertices = meshopt::encode_vertex_buffer(&positions).ok()?;
    let triangles = meshopt::encode_index_buffer(&indices, 4).ok()?;
    let mut g = Glb::default();
    let v = g.view(&vertices, None);
    let t = g.view(&triangles, None);
    // Offsets are those `view` gave; rebuild the views as compressed ones over buffer 0.
    let views = std::mem::take(&mut g.views);
    let compressed = |i: usize, stride: usize, count: usize, mode: &str| {
        let source = &views[i];
        let mut view = json!({"buffer": 1, "byteLength": count * stride,
            "extensions": {"EXT_meshopt_compression": {"buffer": 0,
                "byteOffset": source["byteOffset"], "byteLength": source["byteLength"],
                "byteStride": stride, "count": count, "mode": mode}}});
        if mode == "ATTRIBUTES" {
            view["byteStride"] = stride.into();
        }
        view
    };
    g.views = vec![
        compressed(v, 12, 4, "ATTRIBUTES"),
        compressed(t, 4, 6, "TRIANGLES"),
    ];
    g.accessors = vec![
        json!({"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]}),
        json!({"bufferView": 1, "componentType": 5125, "count": 6, "type": "SCALAR"}),
    ];
    let bin_len = g.bin.len();
    let mut glb = g.finish(json!({
        "extensionsUsed": ["EXT_meshopt_compression"],
        "extensionsRequired": ["EXT_meshopt_compression"],
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}]
    }));
    // `finish` wrote one buffer; add the fallback buffer by rewriting the JSON.
    let (json, bin) = split_glb(&glb)?;
    let mut json: Value = serde_json::from_slice(&json).ok()?;
    json["buffers"] = json!([{"byteLength": bin_len},
        {"byteLength": 72, "extensions": {"EXT_meshopt_compression": {"fallback": true}}}]);
    glb = super::targets::glb(json.to_string().as_bytes(), &bin);
    Some(glb)
}

#[cfg(not(feature = "meshopt"))]
fn meshopt_glb() -> Option<Vec<u8>> {
    None
}

/// The JSON and BIN chunks of a GLB that [`super::targets::glb`] made.
fn split_glb(glb: &[u8]) -> Option<(Vec<u8>, Vec<u8>)> {
    let word = |i: usize| -> Option<usize> {
        Some(u32::from_le_bytes(glb.get(i..i + 4)?.try_into().ok()?) as usize)
    };
    let json_len = word(12)?;
    let json = glb.get(20..20 + json_len)?.to_vec();
    let bin_len = word(20 + json_len)?;
    let bin = glb.get(28 + json_len..28 + json_len + bin_len)?.to_vec();
    Some((json, bin))
}

fn image_seeds() -> Vec<(String, Vec<u8>)> {
    let mut seeds = vec![
        ("rgba-4.png".to_string(), png(4, true)),
        ("webp-lossless-4.webp".into(), webp(4)),
    ];
    let encode = |img: image::DynamicImage, format| {
        let mut out = Vec::new();
        let _ = img.write_to(&mut std::io::Cursor::new(&mut out), format);
        out
    };
    let grey = image::DynamicImage::ImageLuma8(image::GrayImage::from_fn(3, 3, |x, y| {
        image::Luma([(x * 80 + y) as u8])
    }));
    seeds.push((
        "grey-3.png".into(),
        encode(grey.clone(), image::ImageFormat::Png),
    ));
    let rgb16 = image::DynamicImage::ImageRgb16(image::ImageBuffer::from_fn(2, 2, |x, y| {
        image::Rgb([(x * 30000) as u16, (y * 30000) as u16, 1000])
    }));
    seeds.push(("rgb16-2.png".into(), encode(rgb16, image::ImageFormat::Png)));
    let la = image::DynamicImage::ImageLumaA8(image::ImageBuffer::from_fn(2, 3, |x, y| {
        image::LumaA([(x * 100) as u8, (y * 100) as u8])
    }));
    seeds.push(("grey-alpha.png".into(), encode(la, image::ImageFormat::Png)));
    let rgb = image::DynamicImage::ImageRgb8(image::RgbImage::from_fn(16, 8, |x, y| {
        image::Rgb([(x * 16) as u8, (y * 32) as u8, 128])
    }));
    seeds.push(("rgb-16x8.jpg".into(), encode(rgb, image::ImageFormat::Jpeg)));
    seeds.push(("grey-3.jpg".into(), encode(grey, image::ImageFormat::Jpeg)));
    seeds
}

fn env_seeds() -> Vec<(String, Vec<u8>)> {
    let mut seeds = Vec::new();
    for (name, width, height) in [("flat-4x2.hdr", 4u32, 2u32), ("rle-16x4.hdr", 16, 4)] {
        let pixels: Vec<image::Rgb<f32>> = (0..width * height)
            .map(|i| image::Rgb([i as f32 * 0.25, 1.0, 100.0 / (1 + i) as f32]))
            .collect();
        let mut out = Vec::new();
        let _ = image::codecs::hdr::HdrEncoder::new(&mut out).encode(
            &pixels,
            width as usize,
            height as usize,
        );
        seeds.push((name.to_string(), out));
    }
    use exr::prelude::*;
    let compressions = [
        ("uncompressed", Compression::Uncompressed),
        ("rle", Compression::RLE),
        ("zip1", Compression::ZIP1),
        ("zip16", Compression::ZIP16),
        ("piz", Compression::PIZ),
        ("pxr24", Compression::PXR24),
        ("b44", Compression::B44),
    ];
    for (name, compression) in compressions {
        for tiled in [false, true] {
            if tiled && name != "zip16" && name != "uncompressed" {
                continue;
            }
            let size = Vec2(8, 4);
            let channels = SpecificChannels::rgba(|pos: Vec2<usize>| {
                (pos.0 as f32 * 0.5, pos.1 as f32, 2.0f32, 1.0f32)
            });
            let encoding = Encoding {
                compression,
                blocks: if tiled {
                    Blocks::Tiles(Vec2(4, 4))
                } else {
                    Blocks::ScanLines
                },
                line_order: LineOrder::Increasing,
            };
            let layer = Layer::new(size, LayerAttributes::named("rgba"), encoding, channels);
            let mut out = std::io::Cursor::new(Vec::new());
            if Image::from_layer(layer)
                .write()
                .to_buffered(&mut out)
                .is_ok()
            {
                let suffix = if tiled { "-tiled" } else { "" };
                seeds.push((format!("{name}{suffix}-8x4.exr"), out.into_inner()));
            }
        }
    }
    seeds
}

const JOBS: &[(&str, &str)] = &[
    (
        "jobs-and-sweeps.toml",
        r#"output_root = "."

[defaults]
scene = "demo.glb"
width = 32
height = 18
spp = 4

[[job]]
output = "out/still.png"

[[job]]
output = "out/placed.exr"
camera = { position = [3, 2, 4], look_at = [0, 0.5, 0], up = [0, 1, 0], yfov = 0.7 }
aov = ["albedo", "depth"]
max_depth = 2
light = ["point:position=1,2,3:intensity=50"]

[[sweep]]
output = "out/spp-{spp:03}-{seed}.png"
spp = [1, 4, 16, 64]
seed = [1, 2]
"#,
    ),
    (
        "orbit-frames.toml",
        r#"[[sweep]]
scene = "a.gltf"
output = "out/turn/frame-{frame:03}.png"
orbit = { frames = 24, center = [0, 0.5, 0], radius = 5, height = 1.5 }

[[sweep]]
scene = "animated.glb"
output = "out/anim/out_{frame:04}.exr"
frames = "0..120"
fps = 24
backend = "bvh"
"#,
    ),
    (
        "options.toml",
        r#"[[job]]
scene = "s.glb"
output = "o.exr"
scene_index = 1
time = 0.5
exposure = -1.5
photometric = true
sample_range = "0..8"
lights = "lights.toml"
env = "sky.hdr"
asset_root = "assets"
camera = 0
"#,
    ),
];

const LIGHTS: &[(&str, &str)] = &[
    (
        "lights.toml",
        r#"[[light]]
type = "point"
position = [1, 2, 3]
intensity = 50
color = [1, 0.9, 0.8]
range = 10

[[light]]
type = "spot"
position = [0, 4, 0]
direction = [0, -1, 0]
intensity = 80
inner = 20
outer = 30

[[light]]
type = "directional"
direction = [0, -1, 0]
irradiance = 3
"#,
    ),
    (
        "specs.txt",
        "point:position=1,2,3:intensity=50:color=1,0.9,0.8:range=10\nspot:position=0,4,0:direction=0,-1,0:intensity=80:inner=20:outer=30\ndirectional:direction=0,-1,0:irradiance=3\n",
    ),
];

fn text_seeds(texts: &[(&str, &str)]) -> Vec<(String, Vec<u8>)> {
    texts
        .iter()
        .map(|(name, text)| (name.to_string(), text.as_bytes().to_vec()))
        .collect()
}

/// Draco seeds: the first byte picks the attributes the glTF maps (see the `draco` target).
fn draco_seeds() -> Vec<(String, Vec<u8>)> {
    super::draco_seed::seeds()
}
