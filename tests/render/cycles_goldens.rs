//! The path tracer against the Cycles goldens of `../shared/khronos` (Blender Cycles 5.0.1,
//! studio.exr at strength 1, 8 bounces, 256 spp; settings in that folder's README), scored
//! as `../shared/fidelity/score.py` scores them: on the pixels the model covers (glint's
//! coverage alpha > 0.5), since the studio seen directly agrees trivially and would hide a
//! wrong material.
//!
//! Per model, glint renders twice at [`SPP`] with seeds 1 and 2 (the golden's size, camera
//! rule, environment and bounce limit), and on the object pixels of their average:
//! - `mean` = glint's mean radiance / Cycles' mean must be within [`MEAN_TOLERANCE`] of 1;
//! - `block` = the relative RMSE of 8×8 block means (blocks at least half covered), minus
//!   the part both renderers' noise explains, must be at most [`BLOCK_TOLERANCE`].
//!
//! The noise is measured, not assumed: `σ` = RMSE(render₁ − render₂)/√2 is one render's
//! block noise; the average of the two carries `σ²/2`, and the golden is taken to carry
//! what glint would at its 256 spp, `σ² · SPP/256` (an assumption: Cycles' own seed-to-seed
//! figures in `../shared/khronos/README.md` are of that order on the glossy models). With
//! `SPP` = 64 that is `σ²/4`, so the test holds
//! `√max(0, block² − σ²/2 − σ²·SPP/256)`, the systematic part, to the same 0.10 as score.py. Without the
//! noise term, glossy models (mirror spheres reflecting the studio's lamps) miss at 64 spp
//! on noise alone: NormalTangentMirrorTest scores block 0.122 at 64 spp, 0.077 at 1024 spp,
//! and two 64-spp glint seeds differ by 0.132 (docs/materials.md).
//!
//! The models held are those within tolerance in docs/materials.md's table; the three
//! outside have stated causes there (golden settings that differ from the glTF
//! specification: single-sided culling, supplied tangents; and GlassVaseFlowers, whose block
//! error is noise both renderers carry, caustic-lit flowers behind thick glass, plus the
//! left vase's culled back faces: at this test's 64 spp one render's block noise is 0.505,
//! which leaves nothing to test, and the mean of seeds 1 and 2 is 0.948, at the bound).

use std::path::{Path, PathBuf};
use std::process::Command;

/// Samples per pixel of each of the two renders.
const SPP: u32 = 64;
/// Largest |glint's object mean / Cycles' − 1| (score.py's bound).
const MEAN_TOLERANCE: f64 = 0.05;
/// Largest systematic 8×8-block relative RMSE (score.py's bound, after the noise).
const BLOCK_TOLERANCE: f64 = 0.10;

/// Models compared, with their file under `../shared/khronos/NAME/`.
const MODELS: &[(&str, &str)] = &[
    ("AlphaBlendModeTest", "glTF-Binary/AlphaBlendModeTest.glb"),
    ("Box", "glTF-Binary/Box.glb"),
    ("BoxVertexColors", "glTF-Binary/BoxVertexColors.glb"),
    ("CesiumMan", "glTF-Binary/CesiumMan.glb"),
    ("ClearCoatTest", "glTF-Binary/ClearCoatTest.glb"),
    ("Duck", "glTF-Binary/Duck.glb"),
    (
        "EmissiveStrengthTest",
        "glTF-Binary/EmissiveStrengthTest.glb",
    ),
    ("InterpolationTest", "glTF-Binary/InterpolationTest.glb"),
    (
        "MetalRoughSpheresNoTextures",
        "glTF-Binary/MetalRoughSpheresNoTextures.glb",
    ),
    ("MultiUVTest", "glTF-Binary/MultiUVTest.glb"),
    ("MultipleScenes", "glTF/MultipleScenes.gltf"),
    (
        "NormalTangentMirrorTest",
        "glTF-Binary/NormalTangentMirrorTest.glb",
    ),
    ("NormalTangentTest", "glTF-Binary/NormalTangentTest.glb"),
    ("OrientationTest", "glTF-Binary/OrientationTest.glb"),
    ("SimpleInstancing", "glTF-Binary/SimpleInstancing.glb"),
    ("SimpleMorph", "glTF/SimpleMorph.gltf"),
    ("SimpleSkin", "glTF/SimpleSkin.gltf"),
    ("SimpleSparseAccessor", "glTF/SimpleSparseAccessor.gltf"),
    (
        "TextureCoordinateTest",
        "glTF-Binary/TextureCoordinateTest.glb",
    ),
    ("TextureEncodingTest", "glTF-Binary/TextureEncodingTest.glb"),
    (
        "TextureLinearInterpolationTest",
        "glTF-Binary/TextureLinearInterpolationTest.glb",
    ),
    ("TextureTransformTest", "glTF/TextureTransformTest.gltf"),
    ("VertexColorTest", "glTF-Binary/VertexColorTest.glb"),
];

fn khronos(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/khronos")
        .join(rel)
}

/// An EXR's first layer: RGBA pixels and (width, height).
fn read_rgba(path: &Path) -> (Vec<[f32; 4]>, usize, usize) {
    let image = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |size, _| {
            (
                vec![[0.0f32; 4]; size.width() * size.height()],
                size.width(),
            )
        },
        |(pixels, width), pos, (r, g, b, a): (f32, f32, f32, f32)| {
            pixels[pos.y() * *width + pos.x()] = [r, g, b, a];
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

fn render(name: &str, file: &str, seed: u32, size: (usize, usize), dir: &Path) -> Vec<[f32; 4]> {
    let out = dir.join(format!("{name}-{seed}.exr"));
    let env = khronos("../env/studio.exr");
    let status = Command::new(env!("CARGO_BIN_EXE_glint"))
        .args([
            "render",
            khronos(&format!("{name}/{file}")).to_str().unwrap(),
        ])
        .args(["-o", out.to_str().unwrap(), "--quiet", "--threads", "2"])
        .args(["--integrator", "path", "--max-depth", "8"])
        .args(["--env", env.to_str().unwrap(), "--env-strength", "1"])
        .args(["--spp", &SPP.to_string(), "--seed", &seed.to_string()])
        .args([
            "--width",
            &size.0.to_string(),
            "--height",
            &size.1.to_string(),
        ])
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&status.stderr)
    );
    let (pixels, w, h) = read_rgba(&out);
    assert_eq!((w, h), size, "{name}: image size");
    pixels
}

/// Per-channel 8×8 block means over the blocks whose coverage (by `mask`) is at least half.
fn blocks(pixels: &[[f32; 3]], mask: &[bool], w: usize, h: usize) -> Vec<f64> {
    let mut out = Vec::new();
    for by in 0..h / 8 {
        for bx in 0..w / 8 {
            let (mut sum, mut covered) = ([0.0f64; 3], 0usize);
            for y in by * 8..by * 8 + 8 {
                for x in bx * 8..bx * 8 + 8 {
                    let p = pixels[y * w + x];
                    for c in 0..3 {
                        sum[c] += f64::from(p[c]);
                    }
                    covered += usize::from(mask[y * w + x]);
                }
            }
            if covered * 2 >= 64 {
                out.extend(sum.map(|s| s / 64.0));
            }
        }
    }
    out
}

fn rms(a: &[f64], b: &[f64]) -> f64 {
    (a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / a.len().max(1) as f64).sqrt()
}

#[test]
fn path_traced_models_match_the_cycles_goldens_on_object_pixels() {
    let dir = tempfile::tempdir().unwrap();
    let mut report = Vec::new();
    let mut failures = Vec::new();
    for (name, file) in MODELS {
        let (golden, w, h) = read_rgba(&khronos(&format!("{name}/cycles.exr")));
        let one = render(name, file, 1, (w, h), dir.path());
        let two = render(name, file, 2, (w, h), dir.path());
        let rgb = |p: &[[f32; 4]]| p.iter().map(|q| [q[0], q[1], q[2]]).collect::<Vec<_>>();
        let average: Vec<[f32; 4]> = one
            .iter()
            .zip(&two)
            .map(|(a, b)| std::array::from_fn(|c| 0.5 * (a[c] + b[c])))
            .collect();
        let mask: Vec<bool> = average.iter().map(|p| p[3] > 0.5).collect();
        let object_mean = |p: &[[f32; 4]]| {
            let (sum, n) = p
                .iter()
                .zip(&mask)
                .filter(|(_, m)| **m)
                .fold((0.0f64, 0usize), |(s, n), (q, _)| {
                    (s + f64::from(q[0] + q[1] + q[2]), n + 1)
                });
            sum / n.max(1) as f64
        };
        let mean = object_mean(&average) / object_mean(&golden).max(1e-12);
        let (b1, b2) = (
            blocks(&rgb(&one), &mask, w, h),
            blocks(&rgb(&two), &mask, w, h),
        );
        let (ba, bg) = (
            blocks(&rgb(&average), &mask, w, h),
            blocks(&rgb(&golden), &mask, w, h),
        );
        let scale = (bg.iter().sum::<f64>() / bg.len().max(1) as f64).max(1e-12);
        let block = rms(&ba, &bg) / scale;
        let sigma = rms(&b1, &b2) / std::f64::consts::SQRT_2 / scale;
        let golden_noise = sigma * sigma * f64::from(SPP) / 256.0;
        let systematic = (block * block - 0.5 * sigma * sigma - golden_noise)
            .max(0.0)
            .sqrt();
        let line = format!(
            "{name}: mean {mean:.3}, block {block:.3} (one render's noise {sigma:.3}; systematic {systematic:.3})"
        );
        eprintln!("{line}");
        if (mean - 1.0).abs() > MEAN_TOLERANCE || systematic > BLOCK_TOLERANCE {
            failures.push(line.clone());
        }
        report.push(line);
    }
    assert!(
        failures.is_empty(),
        "outside |mean − 1| ≤ {MEAN_TOLERANCE}, systematic block ≤ {BLOCK_TOLERANCE}:\n{}\n\nall:\n{}",
        failures.join("\n"),
        report.join("\n")
    );
}
