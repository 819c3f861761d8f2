//! The options of one render as `glint render` and the keys of batch job files spell them
//! (one clap definition for both), and their translation into a [`Job`]
//! ([`RenderArgs::to_job`]). Plain data; the command line in `cli/` only parses and prints.

use crate::accel::BackendKind;
use crate::light::LightUnits;
use crate::render::job::{CameraChoice, LightSource, OutputSpec, Samples, SceneSource};
use crate::render::{self, AovSelection, Job, JobError, RenderSettings};
use std::path::PathBuf;
use std::time::Duration;

/// Output file of `glint render` without a scene.
pub const DEMO_OUTPUT: &str = "glint-demo.png";

/// An auxiliary image for `--aov`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum AovName {
    /// Reflectance at the first hit.
    Albedo,
    /// World-space shading normal at the first hit.
    Normal,
    /// Distance to the first hit.
    Depth,
}

/// Arguments of `glint render`.
#[derive(clap::Args, Debug, Clone)]
pub struct RenderArgs {
    /// Scene to render (.gltf or .glb). Without it, glint renders its embedded demo scene.
    pub scene: Option<PathBuf>,
    /// Output image, .png or .exr [default: glint-demo.png for the demo, else the scene's
    /// name with .png, in the current folder].
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Image width in pixels [default: 1280, or from --height and the camera's aspect ratio].
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels [default: from the width and the camera's aspect ratio, 16:9 if
    /// the camera has none].
    #[arg(long)]
    pub height: Option<u32>,
    /// Samples per pixel.
    #[arg(long, default_value_t = 16)]
    pub spp: u32,
    /// Ray-query backend: embree or bvh.
    #[arg(long, default_value_t = BackendKind::default())]
    pub backend: BackendKind,
    /// Which of the scene's cameras to use (index, from 0) [default: the first, or a default
    /// camera framing the scene if it has none].
    #[arg(long)]
    pub camera: Option<usize>,
    /// Worker threads; 0 uses every core.
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Seed of the sample positions.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Maximum number of mirror bounces.
    #[arg(long, default_value_t = 8)]
    pub max_depth: u32,
    /// Exposure in stops for PNG output (radiance × 2^EV).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// Add a light (repeatable; format in the README).
    #[arg(long = "light", value_name = "SPEC")]
    pub light: Vec<String>,
    /// Add the lights of a lights file.
    #[arg(long = "lights", value_name = "FILE")]
    pub lights_file: Option<PathBuf>,
    /// Light intensities are photometric (cd, lx): divide them by 683 lm/W.
    #[arg(long)]
    pub photometric: bool,
    /// Auxiliary images to add to an EXR output (comma-separated).
    #[arg(long, value_delimiter = ',', value_name = "albedo,normal,depth")]
    pub aov: Vec<AovName>,
    /// Texture filter, overriding the glTF samplers (for experiments): nearest, bilinear and
    /// bicubic read the full-resolution image only; trilinear and anisotropic use MIP maps and
    /// ray differentials.
    #[arg(long, value_enum, default_value_t = crate::texture::TextureFilter::Anisotropic)]
    pub texture_filter: crate::texture::TextureFilter,
    /// Write 16 bits per channel to PNG.
    #[arg(long)]
    pub png16: bool,
    /// Print nothing but errors.
    #[arg(long, short)]
    pub quiet: bool,
    /// Render only the samples START..END (end exclusive) of the --spp samples and write a
    /// partial EXR of sample sums and weights, for `glint merge`.
    #[arg(long, value_name = "START..END", conflicts_with = "shard")]
    pub sample_range: Option<String>,
    /// Render shard I of N of the samples (a balanced split of 0..spp) as a partial EXR, for
    /// `glint merge`; I counts from 0.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<crate::batch::Shard>,
    /// Pixel filter, NAME[:RADIUS_PX]: box (0.5), tent (1), gaussian (1.5), mitchell (2),
    /// blackman-harris (2).
    #[arg(long, default_value = "box")]
    pub filter: render::FilterSpec,
    /// Sample sequence: sobol, stratified, independent or center.
    #[arg(long, default_value = "sobol")]
    pub sampler: render::PixelSampling,
    /// Render passes until this many seconds of rendering are spent (progressive; --spp is
    /// then ignored).
    #[arg(long, value_name = "SECONDS")]
    pub time_budget: Option<f64>,
    /// Render passes until the estimated relative RMS error falls to E (e.g. 0.02), or the
    /// time budget or --max-spp is reached.
    #[arg(long, value_name = "E")]
    pub target_error: Option<f64>,
    /// Sample cap of a progressive render.
    #[arg(long, default_value_t = render::progressive::DEFAULT_MAX_SPP)]
    pub max_spp: u32,
}

impl RenderArgs {
    /// The library job these arguments stand for (the command line's spelling of a
    /// [`Job`]). Fails on a malformed `--sample-range` or progressive option.
    pub fn to_job(&self) -> Result<Job, JobError> {
        let samples = match (&self.sample_range, self.shard) {
            (Some(text), _) => Samples::Range(
                render::partial::parse_sample_range(text)
                    .map_err(|e| JobError::Options(format!("--sample-range: {e}")))?,
            ),
            (None, Some(shard)) => Samples::Shard {
                index: shard.index,
                count: shard.count,
            },
            (None, None) if self.time_budget.is_some() || self.target_error.is_some() => {
                Samples::Progressive(stop_rule(self)?)
            }
            (None, None) => Samples::All,
        };
        let mut lights: Vec<LightSource> =
            self.light.iter().cloned().map(LightSource::Spec).collect();
        lights.extend(self.lights_file.clone().map(LightSource::File));
        Ok(Job {
            scene: match &self.scene {
                Some(path) => SceneSource::File(path.clone()),
                None => SceneSource::Demo,
            },
            backend: self.backend,
            camera: match self.camera {
                Some(i) => CameraChoice::Index(i),
                None => CameraChoice::First,
            },
            lights,
            light_units: if self.photometric {
                LightUnits::Photometric
            } else {
                LightUnits::Radiometric
            },
            width: self.width,
            height: self.height,
            settings: RenderSettings {
                spp: self.spp,
                seed: self.seed,
                max_depth: self.max_depth,
                threads: self.threads,
                aovs: aov_selection(&self.aov),
                texture_filter: self.texture_filter,
                filter: self.filter,
                sampling: self.sampler,
                ..RenderSettings::default()
            },
            samples,
            output: Some(OutputSpec {
                path: output_path(self),
                exposure_ev: self.exposure,
                png16: self.png16,
            }),
        })
    }
}

/// The progressive stop rule from `--time-budget`, `--target-error` and `--max-spp`.
fn stop_rule(args: &RenderArgs) -> Result<render::StopRule, JobError> {
    let time_budget = match args.time_budget {
        Some(t) if t > 0.0 && t.is_finite() && t < 1e9 => Some(Duration::from_secs_f64(t)),
        Some(t) => {
            return Err(JobError::Options(format!(
                "--time-budget {t}: give a positive number of seconds"
            )));
        }
        None => None,
    };
    if let Some(e) = args.target_error
        && !(e > 0.0 && e.is_finite())
    {
        return Err(JobError::Options(format!(
            "--target-error {e}: give a positive relative error, e.g. 0.02 for 2%"
        )));
    }
    Ok(render::StopRule {
        time_budget,
        target_error: args.target_error,
        max_spp: args.max_spp,
    })
}

/// The output path: `-o`, or a default from the scene's name.
pub fn output_path(args: &RenderArgs) -> PathBuf {
    match (&args.output, &args.scene) {
        (Some(path), _) => path.clone(),
        (None, None) => PathBuf::from(DEMO_OUTPUT),
        (None, Some(scene)) => {
            let stem = scene.file_stem().unwrap_or_default().to_string_lossy();
            PathBuf::from(format!("{stem}.png"))
        }
    }
}

fn aov_selection(names: &[AovName]) -> AovSelection {
    AovSelection {
        albedo: names.contains(&AovName::Albedo),
        normal: names.contains(&AovName::Normal),
        depth: names.contains(&AovName::Depth),
    }
}
