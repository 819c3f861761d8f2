//! `glint converge`: renders a scene at 1, 2, 4, … N samples per pixel for each compared
//! setting (backend × sampler × filter), measures the error against a reference and writes
//! `DIR/converge.csv`, `DIR/converge.png` (RMSE against time, log-log) and the fitted slope of
//! log RMSE against log spp per setting. `--env` lights the scene with an environment map (and
//! then adds no default light); `--denoise` adds, for each setting, the curve of the same renders
//! denoised with Open Image Denoise (time: render plus denoiser), against the same reference.

use super::CliError;
use crate::accel::{Accel, BackendKind, BuildOptions};
use crate::converge::{self, Measurement};
use crate::render::{
    self, AovSelection, FilterSpec, Image, PixelSampling, RenderInputs, RenderOutput,
    RenderSettings,
};
use crate::scene;
use crate::scene::SceneSource;
use glam::Vec3;
use std::path::PathBuf;

/// Arguments of `glint converge`.
#[derive(clap::Args, Debug, Clone)]
pub struct ConvergeArgs {
    /// Scene (.gltf or .glb); without it, the embedded demo scene.
    pub scene: Option<PathBuf>,
    /// Reference image (OpenEXR, same size). Without it, glint renders one first with
    /// --reference-spp samples (Sobol, another seed), one per filter compared.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Output folder for converge.csv and converge.png (created if missing).
    #[arg(long)]
    pub out: PathBuf,
    /// Largest sample count; renders use 1, 2, 4, … up to it.
    #[arg(long, default_value_t = 64)]
    pub max_spp: u32,
    /// Samples per pixel of a reference glint renders itself.
    #[arg(long, default_value_t = 4096)]
    pub reference_spp: u32,
    /// Image width.
    #[arg(long, default_value_t = 320)]
    pub width: u32,
    /// Image height.
    #[arg(long, default_value_t = 180)]
    pub height: u32,
    /// Backends compared (comma-separated).
    #[arg(long, value_delimiter = ',', default_value = "embree,bvh")]
    pub backends: Vec<BackendKind>,
    /// Samplers compared (comma-separated).
    #[arg(long, value_delimiter = ',', default_value = "sobol,independent")]
    pub samplers: Vec<PixelSampling>,
    /// Filters compared (comma-separated NAME[:RADIUS]).
    #[arg(long, value_delimiter = ',', default_value = "box")]
    pub filters: Vec<FilterSpec>,
    /// Seed of the measured renders.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads; 0 uses every core.
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Light transport measured: path or direct.
    #[arg(long, value_parser = super::values::integrator(), default_value_t = crate::render::RenderSettings::default().integrator)]
    pub integrator: crate::render::Integrator,
    /// Every file the glTF refers to must resolve inside this folder (as for glint render).
    #[arg(long, value_name = "DIR")]
    pub asset_root: Option<PathBuf>,
    /// Environment map (equirectangular .hdr or .exr) lighting every render and the
    /// reference; the scene then gets no default light.
    #[arg(long, value_name = "FILE")]
    pub env: Option<PathBuf>,
    /// Also measure each render denoised with Open Image Denoise (RT filter, albedo and normal
    /// AOVs), as the setting "... denoised"; its time is the render's plus the denoiser's.
    #[arg(long)]
    pub denoise: bool,
    /// Print nothing but errors and the slopes.
    #[arg(long, short)]
    pub quiet: bool,
}

/// Seed of a reference glint renders itself: far from any measured seed, so its samples are
/// independent of theirs.
const REFERENCE_SEED: u64 = 0x0005_EED0_F2EF;

/// Runs `glint converge`.
pub fn run(args: ConvergeArgs) -> Result<(), CliError> {
    if args.max_spp == 0 || args.reference_spp == 0 {
        return Err(CliError::Usage(
            "--max-spp and --reference-spp must be at least 1".into(),
        ));
    }
    if args.backends.is_empty() || args.samplers.is_empty() || args.filters.is_empty() {
        return Err(CliError::Usage(
            "give at least one --backends, --samplers and --filters value".into(),
        ));
    }
    let say = |line: String| {
        if !args.quiet {
            eprintln!("{line}");
        }
    };
    std::fs::create_dir_all(&args.out).map_err(|e| {
        CliError::Usage(format!(
            "cannot create the output folder {}: {e}; check the path and permissions",
            args.out.display()
        ))
    })?;
    let source = match &args.scene {
        Some(path) => SceneSource::File(path.clone()),
        None => SceneSource::Demo,
    };
    let label = source.label();
    let options = crate::scene::gltf::LoadOptions {
        asset_root: args.asset_root.clone(),
        ..Default::default()
    };
    let mut scene = source
        .load_with(&crate::scene::gltf::SceneSelection::default(), &options)
        .map_err(crate::job::JobError::from)?;
    if args.denoise && !crate::denoise::AVAILABLE {
        return Err(CliError::from_display(
            crate::denoise::DenoiseError::Unavailable,
        ));
    }
    let environment = match &args.env {
        Some(path) => Some(
            crate::light::environment::EnvironmentLight::from_file(path, 1.0, 0.0)
                .map_err(CliError::from_display)?,
        ),
        None => {
            for added in scene::defaults::complete(&mut scene) {
                say(added);
            }
            None
        }
    };
    let camera = scene
        .cameras
        .first()
        .cloned()
        .unwrap_or_else(|| scene::defaults::default_camera(&scene));
    let base = RenderSettings {
        width: args.width,
        height: args.height,
        threads: args.threads,
        integrator: args.integrator,
        ..RenderSettings::default()
    };

    let mut accels: Vec<(BackendKind, Box<dyn Accel>)> = Vec::new();
    for &backend in &args.backends {
        let accel = render::prepare(&scene, backend, BuildOptions::default())
            .map_err(|e| CliError::Usage(format!("{label}: {e}")))?;
        accels.push((backend, accel));
    }

    let given = match &args.reference {
        Some(path) => {
            let reference = converge::read_exr(path).map_err(CliError::from_display)?;
            if (reference.width, reference.height) != (args.width, args.height) {
                return Err(CliError::from_display(converge::ConvergeError::Size {
                    path: path.clone(),
                    found_w: reference.width,
                    found_h: reference.height,
                    width: args.width,
                    height: args.height,
                }));
            }
            say(format!("reference: {}", path.display()));
            Some(reference)
        }
        None => None,
    };

    let mut rows = Vec::new();
    for filter in &args.filters {
        let reference = match &given {
            Some(r) => r.clone(),
            None => {
                say(format!(
                    "no --reference: rendering one at {} spp (sobol, {filter}, seed {REFERENCE_SEED:#x}, {})",
                    args.reference_spp, accels[0].0
                ));
                let settings = RenderSettings {
                    spp: args.reference_spp,
                    seed: REFERENCE_SEED,
                    sampling: PixelSampling::Sobol,
                    filter: *filter,
                    ..base
                };
                let inputs = RenderInputs {
                    environment: environment.as_ref(),
                    ..RenderInputs::of_scene(&scene, accels[0].1.as_ref(), &camera)
                };
                let out = render_once(&inputs, &settings)
                    .map_err(|e| CliError::Usage(format!("{label}: {e}")))?;
                say(format!(
                    "reference rendered in {:.1} s",
                    out.stats.elapsed.as_secs_f64()
                ));
                out.image
            }
        };
        for (backend, accel) in &accels {
            for &sampler in &args.samplers {
                let setting = format!("{backend} {sampler} {filter}");
                let inputs = RenderInputs {
                    environment: environment.as_ref(),
                    ..RenderInputs::of_scene(&scene, accel.as_ref(), &camera)
                };
                rows.extend(
                    measure(
                        &inputs,
                        &RenderSettings {
                            sampling: sampler,
                            filter: *filter,
                            seed: args.seed,
                            ..base
                        },
                        &reference,
                        &setting,
                        args.max_spp,
                        args.denoise,
                    )
                    .map_err(|e| CliError::Usage(format!("{label}: {e}")))?,
                );
            }
        }
    }

    let csv = args.out.join("converge.csv");
    let png = args.out.join("converge.png");
    converge::write_csv(&csv, &rows).map_err(CliError::from_display)?;
    let title = format!(
        "{} — {}×{}, RMSE vs time",
        args.scene
            .as_ref()
            .and_then(|p| p.file_stem())
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "demo".into()),
        args.width,
        args.height
    );
    converge::write_plot(&png, &title, &rows).map_err(CliError::from_display)?;
    for line in slope_lines(&rows) {
        println!("{line}");
    }
    say(format!("wrote {} and {}", csv.display(), png.display()));
    Ok(())
}

/// Renders `inputs` with `settings` and resolves the film.
fn render_once(
    inputs: &RenderInputs<'_>,
    settings: &RenderSettings,
) -> Result<RenderOutput, render::RenderError> {
    let (film, stats) = render::render_film(inputs, settings, 0..settings.spp, None)?;
    let (image, aovs) = film.resolve();
    Ok(RenderOutput { image, aovs, stats })
}

/// Why a measurement failed: the render or the denoiser.
#[derive(Debug, thiserror::Error)]
pub enum MeasureError {
    /// The render failed.
    #[error(transparent)]
    Render(#[from] render::RenderError),
    /// The denoiser failed.
    #[error(transparent)]
    Denoise(#[from] crate::denoise::DenoiseError),
}

/// Renders at 1, 2, 4, … `max_spp` samples (and `max_spp` itself) and measures each; with
/// `denoise`, also each render denoised (setting "`setting` denoised", the denoiser's time
/// added to the render's).
pub fn measure(
    inputs: &RenderInputs<'_>,
    settings: &RenderSettings,
    reference: &Image<Vec3>,
    setting: &str,
    max_spp: u32,
    denoise: bool,
) -> Result<Vec<Measurement>, MeasureError> {
    let mut counts: Vec<u32> = std::iter::successors(Some(1u32), |&n| n.checked_mul(2))
        .take_while(|&n| n <= max_spp)
        .collect();
    if counts.last() != Some(&max_spp) {
        counts.push(max_spp);
    }
    let mut rows = Vec::new();
    let mut denoised = Vec::new();
    let aovs = AovSelection {
        albedo: settings.aovs.albedo || denoise,
        normal: settings.aovs.normal || denoise,
        ..settings.aovs
    };
    for spp in counts {
        let out = render_once(
            inputs,
            &RenderSettings {
                spp,
                aovs,
                ..*settings
            },
        )?;
        let seconds = out.stats.elapsed.as_secs_f64();
        rows.push(Measurement {
            setting: setting.to_string(),
            spp,
            seconds,
            rays: out.stats.rays.traced(),
            metrics: converge::metrics(&out.image, reference),
        });
        if let (true, Some(albedo), Some(normal)) = (denoise, &out.aovs.albedo, &out.aovs.normal) {
            let start = std::time::Instant::now();
            let image = crate::denoise::denoise(
                &out.image,
                Some(crate::denoise::Auxiliary { albedo, normal }),
                settings.threads,
            )?;
            denoised.push(Measurement {
                setting: format!("{setting} denoised"),
                spp,
                seconds: seconds + start.elapsed().as_secs_f64(),
                rays: out.stats.rays.traced(),
                metrics: converge::metrics(&image, reference),
            });
        }
    }
    rows.extend(denoised);
    Ok(rows)
}

/// One line per setting: the fitted slope of log RMSE against log spp.
pub fn slope_lines(rows: &[Measurement]) -> Vec<String> {
    let mut settings: Vec<&str> = Vec::new();
    for m in rows {
        if !settings.contains(&m.setting.as_str()) {
            settings.push(&m.setting);
        }
    }
    settings
        .into_iter()
        .map(|setting| {
            let points: Vec<(f64, f64)> = rows
                .iter()
                .filter(|m| m.setting == setting)
                .map(|m| (m.spp as f64, m.metrics.rmse))
                .collect();
            match converge::fit_log_slope(&points) {
                Some(slope) => {
                    format!("{setting}: RMSE ∝ spp^{slope:.3} (−0.5 is plain Monte Carlo)")
                }
                None => format!("{setting}: too few sample counts to fit a slope"),
            }
        })
        .collect()
}
