//! Measures the texture-filtering trade on `scenes/checker-plane.gltf` and writes the image
//! strip `docs/texture-filters.png` (reference, then each filter at 1 spp).
//!
//! ```text
//! cargo run --release --example texture_trade [-- RUNS REFERENCE_SPP]
//! ```
//!
//! The reference is bilinear (no MIP maps, so the texture itself, not a prefiltered version)
//! at REFERENCE_SPP samples per pixel, box-filtered over the pixel: the pixel's true average.
//! Every 1-spp render's relative RMSE is `sqrt(Σ|x − r|² / Σ|r|²)` over all pixels and
//! channels; times are medians of RUNS renders. Prints a Markdown table.

use glam::Vec3;
use glint::accel::{BackendKind, BuildOptions};
use glint::render::{self, Image, RenderSettings};
use glint::texture::TextureFilter;
use std::path::Path;
use std::time::Duration;

const WIDTH: u32 = 320;
const HEIGHT: u32 = 180;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let runs: usize = args.get(1).map_or(Ok(5), |s| s.parse())?;
    let reference_spp: u32 = args.get(2).map_or(Ok(1024), |s| s.parse())?;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = glint::scene::gltf::load(&root.join("scenes/checker-plane.gltf"))?;
    let camera = scene
        .cameras
        .first()
        .ok_or("the scene has no camera")?
        .clone();
    let accel = render::prepare(&scene, BackendKind::default(), BuildOptions::default())?;
    let settings = |filter: TextureFilter, spp: u32| RenderSettings {
        integrator: glint::render::Integrator::Direct,
        width: WIDTH,
        height: HEIGHT,
        spp,
        texture_filter: filter,
        threads: 2,
        seed: 1,
        ..RenderSettings::default()
    };
    let render = |filter, spp| -> Result<(Image<Vec3>, Duration), render::RenderError> {
        let mut times = Vec::new();
        let mut image = None;
        for _ in 0..runs {
            let out = render::render(
                &scene,
                accel.as_ref(),
                &camera,
                &settings(filter, spp),
                None,
            )?;
            times.push(out.stats.elapsed);
            image = Some(out.image);
        }
        times.sort();
        Ok((
            image.unwrap_or_else(|| Image::filled(WIDTH, HEIGHT, Vec3::ZERO)),
            times[times.len() / 2],
        ))
    };
    let reference = render::render(
        &scene,
        accel.as_ref(),
        &camera,
        &settings(TextureFilter::Bilinear, reference_spp),
        None,
    )?
    .image;
    println!(
        "reference: bilinear, {reference_spp} spp, {WIDTH}×{HEIGHT}; medians of {runs} runs\n"
    );
    println!("| filter (1 spp) | relative RMSE | render time (ms) | time vs nearest |");
    println!("|---|---|---|---|");
    let mut strip = vec![reference.clone()];
    let mut results = Vec::new();
    for filter in [
        TextureFilter::Nearest,
        TextureFilter::Bilinear,
        TextureFilter::Bicubic,
        TextureFilter::Trilinear,
        TextureFilter::Anisotropic,
    ] {
        let (image, time) = render(filter, 1)?;
        let error = relative_rmse(&image, &reference);
        results.push((filter, error, time));
        if filter != TextureFilter::Bicubic {
            strip.push(image);
        }
    }
    let nearest_time = results[0].2.as_secs_f64();
    for (filter, error, time) in &results {
        println!(
            "| {} | {error:.4} | {:.1} | {:.2}× |",
            filter.name(),
            time.as_secs_f64() * 1e3,
            time.as_secs_f64() / nearest_time
        );
    }
    let (_, aniso_error, aniso_time) = results[4];
    println!("\n| bilinear spp | relative RMSE | render time (ms) | time vs anisotropic 1 spp |");
    println!("|---|---|---|---|");
    let mut spp = 1;
    while spp <= 256 {
        let (image, time) = render(TextureFilter::Bilinear, spp)?;
        let error = relative_rmse(&image, &reference);
        println!(
            "| {spp} | {error:.4} | {:.1} | {:.1}× |",
            time.as_secs_f64() * 1e3,
            time.as_secs_f64() / aniso_time.as_secs_f64()
        );
        if error <= aniso_error {
            break;
        }
        spp *= 2;
    }
    write_strip(&root.join("docs/texture-filters.png"), &strip)?;
    Ok(())
}

/// `sqrt(Σ|x − r|² / Σ|r|²)` over every pixel and channel.
fn relative_rmse(image: &Image<Vec3>, reference: &Image<Vec3>) -> f64 {
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for (x, r) in image.pixels.iter().zip(&reference.pixels) {
        num += f64::from((*x - *r).length_squared());
        den += f64::from(r.length_squared());
    }
    (num / den.max(f64::MIN_POSITIVE)).sqrt()
}

/// The images side by side, sRGB-encoded, written atomically.
fn write_strip(path: &Path, images: &[Image<Vec3>]) -> Result<(), Box<dyn std::error::Error>> {
    let gap = 4;
    let width = images.len() as u32 * (WIDTH + gap) - gap;
    let mut strip = Image::filled(width, HEIGHT, Vec3::ONE);
    for (k, image) in images.iter().enumerate() {
        let x0 = k as u32 * (WIDTH + gap);
        for y in 0..HEIGHT {
            for x in 0..WIDTH {
                strip.pixels[(y * width + x0 + x) as usize] =
                    image.pixels[(y * WIDTH + x) as usize];
            }
        }
    }
    glint::output::write_png(path, &strip, glint::output::PngOptions::default())?;
    Ok(())
}
