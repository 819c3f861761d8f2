//! The path tracer against the Cycles goldens of `../shared/khronos` (Blender Cycles 5.0.1,
//! studio.exr at strength 1, 8 bounces, 256 spp; settings in that folder's README).
//!
//! glint renders each model with the same environment, camera rule, image size and bounce
//! limit at 32 spp, and its image is compared with the golden on 8×8 block means, which
//! average away most of both renders' noise:
//! - the image mean within [`MEAN_TOLERANCE`] of the golden's;
//! - the mean absolute difference of the block means within [`BLOCK_TOLERANCE`] of the
//!   golden's mean.
//!
//! At 64 spp these models measured 0.2–0.8 % on the block error and 0.0–0.6 % on the mean
//! (README fidelity table); the tolerances leave room for 32 spp's noise but not for a wrong
//! BSDF, a wrong environment mapping or a missing bounce, each of which moves these figures
//! by several percent. Only models whose features glint renders as the glTF spec says (no
//! alpha, normal maps or vertex-colour differences, or whose differences stay inside the
//! tolerance: ClearCoatTest and GlassVaseFlowers, see their entries) are held to it here.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Largest relative difference of image means.
const MEAN_TOLERANCE: f64 = 0.015;
/// Largest mean absolute difference of 8×8 block means, relative to the golden's mean.
const BLOCK_TOLERANCE: f64 = 0.025;

/// Models compared, with their file under `../shared/khronos/NAME/`.
const MODELS: &[(&str, &str)] = &[
    ("Box", "glTF-Binary/Box.glb"),
    (
        "MetalRoughSpheresNoTextures",
        "glTF-Binary/MetalRoughSpheresNoTextures.glb",
    ),
    (
        "EmissiveStrengthTest",
        "glTF-Binary/EmissiveStrengthTest.glb",
    ),
    ("Duck", "glTF-Binary/Duck.glb"),
    ("CesiumMan", "glTF-Binary/CesiumMan.glb"),
    // Single-sided culling (camera rays) in the top row, which Cycles does not cull: a small
    // region, 0.45 % mean and 0.54 % blocks over the whole image (issue 14).
    ("TextureSettingsTest", "glTF-Binary/TextureSettingsTest.glb"),
    // Normal maps (generated and supplied tangents) and metallic-roughness textures.
    ("NormalTangentTest", "glTF-Binary/NormalTangentTest.glb"),
    (
        "NormalTangentMirrorTest",
        "glTF-Binary/NormalTangentMirrorTest.glb",
    ),
    ("TwoSidedPlane", "glTF/TwoSidedPlane.gltf"),
    // KHR_materials_clearcoat (its textures and coat normals are not applied yet, and the
    // alpha-blended labels render opaque: together 0.15 % on the block error at 32 spp).
    ("ClearCoatTest", "glTF-Binary/ClearCoatTest.glb"),
    // KHR_materials_transmission + KHR_materials_volume (refracting glass; the second vase's
    // alpha blend renders opaque): 0.9 % on the block error, 0.1 % on the mean at 32 spp.
    ("GlassVaseFlowers", "glTF-Binary/GlassVaseFlowers.glb"),
];

fn khronos(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/khronos")
        .join(rel)
}

/// RGB pixels and (width, height) of an EXR's first layer.
fn read_rgb(path: &Path) -> (Vec<[f32; 3]>, usize, usize) {
    let image = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |size, _| {
            (
                vec![[0.0f32; 3]; size.width() * size.height()],
                size.width(),
            )
        },
        |(pixels, width), pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            pixels[pos.y() * *width + pos.x()] = [r, g, b];
        },
    )
    .unwrap_or_else(|e| panic!("read {}: {e}", path.display()));
    let size = image.layer_data.size;
    (
        image.layer_data.channel_data.pixels.0,
        size.width(),
        size.height(),
    )
}

/// 8×8 block means of the summed channels.
fn blocks(pixels: &[[f32; 3]], w: usize, h: usize) -> Vec<f64> {
    let (bw, bh) = (w / 8, h / 8);
    let mut out = vec![0.0; bw * bh];
    for by in 0..bh {
        for bx in 0..bw {
            let mut sum = 0.0;
            for y in by * 8..by * 8 + 8 {
                for x in bx * 8..bx * 8 + 8 {
                    sum += pixels[y * w + x].iter().map(|&c| c as f64).sum::<f64>();
                }
            }
            out[by * bw + bx] = sum / (64.0 * 3.0);
        }
    }
    out
}

#[test]
fn path_traced_models_match_the_cycles_goldens() {
    let dir = tempfile::tempdir().unwrap();
    let env = khronos("../env/studio.exr");
    let mut report = Vec::new();
    for (name, file) in MODELS {
        let golden = khronos(&format!("{name}/cycles.exr"));
        let (reference, w, h) = read_rgb(&golden);
        let out = dir.path().join(format!("{name}.exr"));
        let status = Command::new(env!("CARGO_BIN_EXE_glint"))
            .args([
                "render",
                khronos(&format!("{name}/{file}")).to_str().unwrap(),
            ])
            .args(["-o", out.to_str().unwrap(), "--quiet", "--threads", "2"])
            .args(["--env", env.to_str().unwrap(), "--max-depth", "8"])
            .args(["--spp", "32", "--seed", "1"])
            .args(["--width", &w.to_string(), "--height", &h.to_string()])
            .output()
            .unwrap();
        assert!(
            status.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&status.stderr)
        );
        let (ours, ow, oh) = read_rgb(&out);
        assert_eq!((ow, oh), (w, h), "{name}: image size");
        let (a, b) = (blocks(&ours, w, h), blocks(&reference, w, h));
        let mean_b = b.iter().sum::<f64>() / b.len() as f64;
        let mean_a = a.iter().sum::<f64>() / a.len() as f64;
        let block =
            a.iter().zip(&b).map(|(x, y)| (x - y).abs()).sum::<f64>() / b.len() as f64 / mean_b;
        let mean = (mean_a / mean_b - 1.0).abs();
        report.push(format!("{name}: mean {mean:.4}, blocks {block:.4}"));
        assert!(
            mean <= MEAN_TOLERANCE && block <= BLOCK_TOLERANCE,
            "{name}: mean off by {mean:.4} (≤ {MEAN_TOLERANCE}), block error {block:.4} (≤ \
             {BLOCK_TOLERANCE})\n{}",
            report.join("\n")
        );
    }
    println!("{}", report.join("\n"));
}
