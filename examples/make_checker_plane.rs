//! Writes `scenes/checker-plane.gltf`, the texture-filtering test scene: a ground plane
//! receding to the horizon, its left half an image checkerboard and its right half the same
//! checkerboard as a procedural texture, seen by a low camera under one directional light.
//!
//! ```text
//! cargo run --example make_checker_plane
//! ```
//!
//! Metres, +Y up. Both halves map uv = (x, z) / 8 m; the image is 256 × 256 texels of 8-texel
//! cells (32 cells per uv unit) and the procedural checker has frequency 32 per uv unit, so
//! both show 0.25 m squares. The image is embedded as a data URI, so the scene is one file.

use base64::Engine;
use serde_json::json;
use std::io::Write;
use std::path::Path;

const OUTPUT: &str = "scenes/checker-plane.gltf";
/// Texture side in texels and texels per checker cell.
const TEXELS: u32 = 256;
const CELL_TEXELS: u32 = 8;
/// Metres per uv unit.
const UV_METRES: f32 = 8.0;
/// The plane: x in [−HALF_WIDTH, HALF_WIDTH], z in [−FAR, NEAR].
const HALF_WIDTH: f32 = 60.0;
const NEAR: f32 = 4.0;
const FAR: f32 = 300.0;
/// Linear reflectances of the two cells.
const DARK: f32 = 0.05;
const LIGHT: f32 = 0.8;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = root.join(OUTPUT);
    let text = serde_json::to_string_pretty(&scene()?)?;
    glint::output::atomic::write_atomically(&path, |w| {
        w.write_all(text.as_bytes())
            .map_err(|source| glint::output::OutputError::Io {
                path: path.clone(),
                source,
            })
    })?;
    println!("wrote {}", path.display());
    Ok(())
}

/// The checker image as an sRGB PNG whose cells decode to DARK and LIGHT.
fn checker_png() -> Result<Vec<u8>, image::ImageError> {
    let code = |linear: f32| glint::output::png::srgb8(linear);
    let image = image::RgbImage::from_fn(TEXELS, TEXELS, |x, y| {
        let odd = (x / CELL_TEXELS + y / CELL_TEXELS) % 2 == 1;
        let c = code(if odd { LIGHT } else { DARK });
        image::Rgb([c, c, c])
    });
    let mut png = Vec::new();
    image.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)?;
    Ok(png)
}

fn scene() -> Result<serde_json::Value, Box<dyn std::error::Error>> {
    // Two quads (left: image, right: procedural), 4 vertices each, facing +Y.
    let quad = |x0: f32, x1: f32| {
        let corners = [(x0, NEAR), (x1, NEAR), (x1, -FAR), (x0, -FAR)];
        let positions: Vec<[f32; 3]> = corners.iter().map(|&(x, z)| [x, 0.0, z]).collect();
        let uvs: Vec<[f32; 2]> = corners
            .iter()
            .map(|&(x, z)| [x / UV_METRES, z / UV_METRES])
            .collect();
        (positions, uvs)
    };
    let (left_p, left_uv) = quad(-HALF_WIDTH, 0.0);
    let (right_p, right_uv) = quad(0.0, HALF_WIDTH);
    let indices: [u16; 6] = [0, 2, 1, 0, 3, 2];
    let mut bin = Vec::new();
    let mut views = Vec::new();
    let mut push = |bytes: &[u8], target: u32| {
        let offset = bin.len();
        bin.extend_from_slice(bytes);
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
        views.push(
            json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len(), "target": target}),
        );
        views.len() - 1
    };
    let f32s = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let idx_bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
    let mut accessors = Vec::new();
    let mut meshes = Vec::new();
    for (material, (p, uv)) in [(left_p, left_uv), (right_p, right_uv)]
        .into_iter()
        .enumerate()
    {
        let flat: Vec<f32> = p.iter().flatten().copied().collect();
        let (lo, hi) = flat
            .chunks(3)
            .fold(([f32::MAX; 3], [f32::MIN; 3]), |(lo, hi), c| {
                (
                    [lo[0].min(c[0]), lo[1].min(c[1]), lo[2].min(c[2])],
                    [hi[0].max(c[0]), hi[1].max(c[1]), hi[2].max(c[2])],
                )
            });
        let pv = push(&f32s(&flat), 34962);
        let uvv = push(
            &f32s(&uv.iter().flatten().copied().collect::<Vec<_>>()),
            34962,
        );
        let iv = push(&idx_bytes, 34963);
        let base = accessors.len();
        accessors.push(json!({"bufferView": pv, "componentType": 5126, "count": 4, "type": "VEC3", "min": lo, "max": hi}));
        accessors
            .push(json!({"bufferView": uvv, "componentType": 5126, "count": 4, "type": "VEC2"}));
        accessors
            .push(json!({"bufferView": iv, "componentType": 5123, "count": 6, "type": "SCALAR"}));
        meshes.push(
            json!({"name": if material == 0 { "image half" } else { "procedural half" },
            "primitives": [{"attributes": {"POSITION": base, "TEXCOORD_0": base + 1},
                            "indices": base + 2, "material": material}]}),
        );
    }
    let b64 = base64::engine::general_purpose::STANDARD;
    let png = checker_png()?;
    Ok(json!({
        "asset": {"version": "2.0", "generator": "glint examples/make_checker_plane.rs"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "directional", "name": "sun", "color": [1.0, 1.0, 1.0], "intensity": 3.0}
        ]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"name": "image plane", "mesh": 0},
            {"name": "procedural plane", "mesh": 1},
            // Camera 1 m up at z = 3, pitched down 8° (a rotation of −8° about +X).
            {"name": "camera", "camera": 0, "translation": [0.0, 1.0, 3.0],
             "rotation": [(-4.0f32).to_radians().sin(), 0.0, 0.0, (-4.0f32).to_radians().cos()]},
            // Sun from above and behind the camera: its direction −Z turned 60° down about +X.
            {"name": "sun", "extensions": {"KHR_lights_punctual": {"light": 0}},
             "rotation": [(-30.0f32).to_radians().sin(), 0.0, 0.0, (-30.0f32).to_radians().cos()]}
        ],
        "cameras": [{"type": "perspective", "name": "low",
                     "perspective": {"yfov": 0.7, "aspectRatio": 16.0 / 9.0, "znear": 0.05}}],
        "meshes": meshes,
        "materials": [
            {"name": "image checker", "doubleSided": true,
             "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0, "roughnessFactor": 1.0}},
            {"name": "procedural checker", "doubleSided": true,
             "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 1.0},
             "extras": {"glint_procedural": {"pattern": "checker", "frequency": (TEXELS / CELL_TEXELS) as f32,
                                              "domain": "uv0", "colors": [[DARK, DARK, DARK], [LIGHT, LIGHT, LIGHT]]}}}
        ],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
        "images": [{"name": "checker", "uri": format!("data:image/png;base64,{}", b64.encode(&png))}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": bin.len(), "uri": format!("data:application/octet-stream;base64,{}", b64.encode(&bin))}]
    }))
}
