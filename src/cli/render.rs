//! `glint render`: load a scene (or the embedded demo), complete it with a default camera and
//! lights where it has none, render it and write a PNG or EXR atomically.

use super::CliError;
use crate::accel::{Accel, BackendKind, BuildOptions};
use crate::light::LightUnits;
use crate::output::{OutputFormat, PngDepth, PngOptions, write_exr, write_png};
use crate::render::{self, AovSelection, Progress, RenderInputs, RenderSettings, RenderStats};
use crate::scene::{self, Camera, Light, Projection, Scene};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Image width when neither --width nor --height is given.
pub const DEFAULT_WIDTH: u32 = 1280;
/// Aspect ratio (width / height) for cameras that do not fix one: 16:9.
pub const DEFAULT_ASPECT: f32 = 16.0 / 9.0;
/// Output file of `glint render` without a scene.
pub const DEMO_OUTPUT: &str = "glint-demo.png";
/// Renders shorter than this show no progress bar.
const PROGRESS_DELAY: Duration = Duration::from_secs(1);

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
    /// Every file the glTF refers to must resolve inside this folder (symbolic links
    /// followed), or the load fails naming the URI.
    #[arg(long, value_name = "DIR")]
    pub asset_root: Option<PathBuf>,
    /// Most texels one texture image may have (checked from its header before decoding); all
    /// of a scene's textures together may have four times as many.
    #[arg(long, value_name = "N", default_value_t = scene::gltf::DEFAULT_MAX_TEXTURE_PIXELS)]
    pub max_texture_pixels: u64,
}

/// Most samples per pixel `--spp` accepts (2^24): beyond it f32 sample sums stop resolving a
/// single sample's contribution.
pub const MAX_SPP: u32 = 1 << 24;
/// Most pixels per side `--width` / `--height` accept.
pub const MAX_IMAGE_SIDE: u32 = 1 << 16;
/// Most pixels an image may have (2^28, 256 Mpx: 4 GiB of RGBA f32 film).
pub const MAX_IMAGE_PIXELS: u64 = 1 << 28;

impl RenderArgs {
    /// The loader options these arguments ask for.
    pub fn load_options(&self) -> scene::gltf::LoadOptions {
        scene::gltf::LoadOptions {
            asset_root: self.asset_root.clone(),
            max_texture_pixels: self.max_texture_pixels,
        }
    }
}

/// A loaded scene and its ray-query structure, shared by the renders of `glint batch`.
#[derive(Clone, Copy)]
pub struct Prepared<'a> {
    /// The scene as loaded (its own lights; job lights are added per render).
    pub scene: &'a Scene,
    /// Its ray-query structure.
    pub accel: &'a dyn Accel,
    /// Its MIP chains ([`render::build_mipmaps`]), shared by every render of the scene.
    pub mipmaps: &'a [crate::texture::MipMap],
}

/// What [`render_prepared`] rendered and wrote.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The file written.
    pub output: PathBuf,
    /// Image size in pixels.
    pub width: u32,
    /// Image size in pixels.
    pub height: u32,
    /// The samples rendered (all of 0..spp unless a partial render).
    pub samples: std::ops::Range<u32>,
    /// What the render traced.
    pub stats: RenderStats,
    /// How the samples were chosen, for the summary line: a partial range, or why a
    /// progressive render stopped ("" for a plain render).
    pub note: String,
}

/// Runs `glint render`.
pub fn run(args: RenderArgs) -> Result<(), CliError> {
    let output = output_path(&args);
    let format = OutputFormat::from_path(&output).map_err(CliError::from_display)?;
    check_options(&args, &output, format)?;
    let say = |line: String| {
        if !args.quiet {
            eprintln!("{line}");
        }
    };

    let (scene, label) = load_scene_with_options(args.scene.as_deref(), &args.load_options())?;
    // Checked before the (possibly long) build of the ray-query structure.
    choose_camera(&scene, args.camera, &|_| {})?;
    let accel = render::prepare(&scene, args.backend, BuildOptions::default())
        .map_err(|e| CliError(format!("{label}: {e}")))?;

    let bar = DelayedProgress::new(args.quiet);
    let report = |done: usize, total: usize| bar.update(done, total);
    let mipmaps = render::build_mipmaps(&scene);
    let prepared = Prepared {
        scene: &scene,
        accel: accel.as_ref(),
        mipmaps: &mipmaps,
    };
    let result = render_prepared(&args, prepared, None, None, Some(&report), &say);
    bar.finish();
    let done = result.map_err(|e| CliError(format!("{label}: {e}")))?;
    say(format!(
        "wrote {} ({}×{}, {} spp, {}, {} sampler, {} filter): {}{}",
        done.output.display(),
        done.width,
        done.height,
        done.samples.len(),
        args.backend,
        args.sampler,
        args.filter,
        done.stats.summary(),
        done.note
    ));
    Ok(())
}

/// Loads `path`, or the embedded demo scene without one, with the label that names it in
/// messages.
pub fn load_scene(path: Option<&std::path::Path>) -> Result<(Scene, String), CliError> {
    load_scene_with_options(path, &scene::gltf::LoadOptions::default())
}

/// Like [`load_scene`], with an asset root and texture budget.
pub fn load_scene_with_options(
    path: Option<&std::path::Path>,
    options: &scene::gltf::LoadOptions,
) -> Result<(Scene, String), CliError> {
    let scene = match path {
        Some(path) => scene::gltf::load_with_options(path, options).map(|loaded| {
            for warning in &loaded.warnings {
                eprintln!("glint: warning: {warning}");
            }
            loaded.scene
        }),
        None => scene::demo::demo_scene(),
    }
    .map_err(CliError::from_display)?;
    let label = path.map_or_else(|| "demo scene".to_string(), |p| p.display().to_string());
    Ok((scene, label))
}

/// Renders a prepared scene as `args` asks and writes the output (path from
/// [`output_path`]): the camera (`camera`, else `--camera`, else a default one), the lights
/// (the scene's, `--light`/`--lights`, else defaults), the image size and settings, and the
/// samples (all, or a `--sample-range`/`--shard` partial EXR). `glint render` and each job of
/// `glint batch` go through here. `pool`: see [`RenderInputs::pool`].
pub fn render_prepared(
    args: &RenderArgs,
    prepared: Prepared<'_>,
    camera: Option<Camera>,
    pool: Option<&rayon::ThreadPool>,
    progress: Option<Progress<'_>>,
    say: &dyn Fn(String),
) -> Result<Rendered, CliError> {
    let output = output_path(args);
    let format = OutputFormat::from_path(&output).map_err(CliError::from_display)?;
    check_options(args, &output, format)?;
    let scene = prepared.scene;
    let camera = match camera {
        Some(camera) => camera,
        None => choose_camera(scene, args.camera, say)?,
    };
    let lights = job_lights(scene, args, &camera, say)?;
    let (width, height) = image_size(args.width, args.height, &camera);
    if let (Some(_), Some(_), Some(fixed)) = (args.width, args.height, fixed_aspect(&camera))
        && ((width as f32 / height as f32) / fixed - 1.0).abs() > 0.01
    {
        say(format!(
            "note: {width}×{height} differs from camera \"{}\"'s aspect ratio {fixed:.4}: the \
             image is stretched (give only --width or --height to keep it)",
            camera.name
        ));
    }
    let settings = render_settings(args, width, height);
    let inputs = RenderInputs {
        scene,
        lights: &lights,
        accel: prepared.accel,
        camera: &camera,
        pool,
        mipmaps: Some(prepared.mipmaps),
    };
    if let Some(samples) = partial_samples(args)? {
        let (part, stats) =
            render::partial::render_partial(&inputs, &settings, samples.clone(), progress)
                .map_err(CliError::from_display)?;
        crate::batch::parts::write_partial_exr(&output, &part).map_err(CliError::from_display)?;
        let note = format!(", samples {}..{} (partial)", samples.start, samples.end);
        return Ok(Rendered {
            output,
            width,
            height,
            samples,
            stats,
            note,
        });
    }
    let (image, aovs, stats, samples, note) = if args.time_budget.is_some()
        || args.target_error.is_some()
    {
        let rule = stop_rule(args)?;
        let p = render::progressive::render_progressive_with(&inputs, &settings, &rule, progress)
            .map_err(CliError::from_display)?;
        let note = format!(
            "; stopped after {} passes ({:?}), estimated relative error {:.4}",
            p.passes, p.reason, p.relative_error
        );
        (
            p.output.image,
            p.output.aovs,
            p.output.stats,
            0..p.spp,
            note,
        )
    } else {
        let (film, stats) = render::render_film(&inputs, &settings, 0..settings.spp, progress)
            .map_err(CliError::from_display)?;
        let (image, aovs) = film.resolve();
        (image, aovs, stats, 0..settings.spp, String::new())
    };
    match format {
        OutputFormat::Png => write_png(
            &output,
            &image,
            PngOptions {
                exposure_ev: args.exposure,
                depth: if args.png16 {
                    PngDepth::Sixteen
                } else {
                    PngDepth::Eight
                },
            },
        ),
        OutputFormat::Exr => write_exr(&output, &image, &aovs),
    }
    .map_err(CliError::from_display)?;
    Ok(Rendered {
        output,
        width,
        height,
        samples,
        stats,
        note,
    })
}

/// The render settings `args` asks for, at the given image size.
pub fn render_settings(args: &RenderArgs, width: u32, height: u32) -> RenderSettings {
    RenderSettings {
        width,
        height,
        spp: args.spp,
        seed: args.seed,
        max_depth: args.max_depth,
        threads: args.threads,
        aovs: aov_selection(&args.aov),
        // job_lights already converted photometric lights (and only those: glint's default
        // lights are radiometric).
        light_units: LightUnits::Radiometric,
        texture_filter: args.texture_filter,
        filter: args.filter,
        sampling: args.sampler,
        ..RenderSettings::default()
    }
}

/// The samples of a partial render (`--sample-range` or `--shard`), or `None` for a full one.
pub fn partial_samples(args: &RenderArgs) -> Result<Option<std::ops::Range<u32>>, CliError> {
    let samples = match (&args.sample_range, args.shard) {
        (Some(text), _) => render::partial::parse_sample_range(text)
            .map_err(|e| CliError(format!("--sample-range: {e}")))?,
        (None, Some(shard)) => render::partial::shard_samples(args.spp, shard.index, shard.count),
        (None, None) => return Ok(None),
    };
    if samples.is_empty() || samples.end > args.spp {
        return Err(CliError(format!(
            "samples {}..{} are not a non-empty part of the {} samples per pixel; pick a range \
             within 0..{} (or fewer shards than samples)",
            samples.start, samples.end, args.spp, args.spp
        )));
    }
    Ok(Some(samples))
}

/// The progressive stop rule from `--time-budget`, `--target-error` and `--max-spp`.
fn stop_rule(args: &RenderArgs) -> Result<render::StopRule, CliError> {
    let time_budget = match args.time_budget {
        Some(t) if t > 0.0 && t.is_finite() && t < 1e9 => Some(Duration::from_secs_f64(t)),
        Some(t) => {
            return Err(CliError(format!(
                "--time-budget {t}: give a positive number of seconds"
            )));
        }
        None => None,
    };
    if let Some(e) = args.target_error
        && !(e > 0.0 && e.is_finite())
    {
        return Err(CliError(format!(
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

/// Rejects option combinations that cannot be honoured, before any work is done.
pub fn check_options(
    args: &RenderArgs,
    output: &Path,
    format: OutputFormat,
) -> Result<(), CliError> {
    if format == OutputFormat::Png && !args.aov.is_empty() {
        return Err(CliError(format!(
            "{}: --aov needs an EXR output (AOVs are linear data); use -o NAME.exr",
            output.display()
        )));
    }
    if format == OutputFormat::Png && (args.sample_range.is_some() || args.shard.is_some()) {
        return Err(CliError(format!(
            "{}: a partial render (--sample-range, --shard) writes sample sums to EXR; use -o \
             NAME.exr and combine the parts with glint merge",
            output.display()
        )));
    }
    if format == OutputFormat::Exr && args.png16 {
        return Err(CliError(format!(
            "{}: --png16 applies to PNG output; EXR is always 32-bit float",
            output.display()
        )));
    }
    if format == OutputFormat::Exr && args.exposure != 0.0 && !args.quiet {
        eprintln!("note: --exposure applies to PNG only; the EXR holds linear radiance");
    }
    if !args.exposure.is_finite() {
        return Err(CliError(format!(
            "--exposure {} is not a number",
            args.exposure
        )));
    }
    if args.spp == 0 {
        return Err(CliError("--spp must be at least 1".into()));
    }
    if args.spp > MAX_SPP {
        return Err(CliError(format!(
            "--spp {} is above the limit of {MAX_SPP}; render shards (--shard) and merge them for more",
            args.spp
        )));
    }
    if args.width == Some(0) || args.height == Some(0) {
        return Err(CliError("--width and --height must be at least 1".into()));
    }
    let side = args.width.max(args.height).unwrap_or(0);
    let pixels = u64::from(args.width.unwrap_or(1)) * u64::from(args.height.unwrap_or(1));
    if side > MAX_IMAGE_SIDE || pixels > MAX_IMAGE_PIXELS {
        return Err(CliError(format!(
            "--width/--height {}×{} exceed the limits of {MAX_IMAGE_SIDE} per side and {MAX_IMAGE_PIXELS} pixels",
            args.width.map_or("auto".to_string(), |w| w.to_string()),
            args.height.map_or("auto".to_string(), |h| h.to_string()),
        )));
    }
    let folder = match output.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !folder.is_dir() {
        return Err(CliError(format!(
            "cannot write {}: the folder {} does not exist; create it first",
            output.display(),
            folder.display()
        )));
    }
    Ok(())
}

/// The camera to render through, announcing a default one.
pub fn choose_camera(
    scene: &Scene,
    index: Option<usize>,
    say: &dyn Fn(String),
) -> Result<Camera, CliError> {
    match index {
        Some(i) => scene.cameras.get(i).cloned().ok_or_else(|| {
            CliError(format!(
                "--camera {i}: the scene has {} camera(s){}",
                scene.cameras.len(),
                if scene.cameras.is_empty() {
                    "; leave out --camera to use a default one".to_string()
                } else {
                    format!("; use 0 to {}", scene.cameras.len() - 1)
                }
            ))
        }),
        None => match scene.cameras.first() {
            Some(camera) => Ok(camera.clone()),
            None => {
                let camera = scene::defaults::default_camera(scene);
                say(scene::defaults::describe_camera(&camera));
                Ok(camera)
            }
        },
    }
}

/// The lights to render with: the scene's plus `--light` and `--lights` lights, converted to
/// radiometric units with `--photometric`; a scene left without any light gets the default
/// lights (radiometric already), placed relative to `camera`.
pub fn job_lights(
    scene: &Scene,
    args: &RenderArgs,
    camera: &Camera,
    say: &dyn Fn(String),
) -> Result<Vec<Light>, CliError> {
    let mut lights = scene.lights.clone();
    let mut extra = Vec::new();
    for spec in &args.light {
        extra.push(
            scene::light_spec::parse_light(spec)
                .map_err(|e| CliError(format!("--light '{spec}': {e}")))?,
        );
    }
    if let Some(file) = &args.lights_file {
        extra.extend(scene::light_spec::load_lights_file(file).map_err(CliError::from_display)?);
    }
    if args.photometric {
        let factor = LightUnits::Photometric.to_radiometric();
        for light in lights.iter_mut().chain(extra.iter_mut()) {
            *light = crate::light::scaled(light, factor);
        }
    }
    if lights.is_empty() && extra.is_empty() {
        let defaults = scene::defaults::default_lights(scene, camera);
        say(scene::defaults::describe_lights(&defaults));
        extra = defaults;
    }
    lights.extend(extra);
    Ok(lights)
}

/// The aspect ratio (width / height) the camera fixes, if any.
pub fn fixed_aspect(camera: &Camera) -> Option<f32> {
    let aspect = match camera.projection {
        Projection::Perspective { aspect_ratio, .. } => aspect_ratio?,
        Projection::Orthographic { xmag, ymag } => (xmag / ymag).abs(),
    };
    (aspect.is_finite() && aspect > 0.0).then_some(aspect)
}

/// Image size from the options: both given are used as they are; one given derives the
/// other from the camera's aspect ratio (16:9 if it fixes none); none gives 1280 wide.
pub fn image_size(width: Option<u32>, height: Option<u32>, camera: &Camera) -> (u32, u32) {
    let aspect = fixed_aspect(camera).unwrap_or(DEFAULT_ASPECT);
    let derive = |v: f32| (v.round() as u32).max(1);
    match (width, height) {
        (Some(w), Some(h)) => (w, h),
        (Some(w), None) => (w, derive(w as f32 / aspect)),
        (None, Some(h)) => (derive(h as f32 * aspect), h),
        (None, None) => (DEFAULT_WIDTH, derive(DEFAULT_WIDTH as f32 / aspect)),
    }
}

fn aov_selection(names: &[AovName]) -> AovSelection {
    AovSelection {
        albedo: names.contains(&AovName::Albedo),
        normal: names.contains(&AovName::Normal),
        depth: names.contains(&AovName::Depth),
    }
}

/// An indicatif bar that appears only once a render has run for [`PROGRESS_DELAY`].
struct DelayedProgress {
    bar: Option<ProgressBar>,
    start: Instant,
    shown: AtomicBool,
}

impl DelayedProgress {
    fn new(quiet: bool) -> Self {
        let bar = (!quiet).then(|| {
            let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden());
            if let Ok(style) =
                ProgressStyle::with_template("{elapsed} [{bar:40}] {pos}/{len} tiles, eta {eta}")
            {
                bar.set_style(style.progress_chars("=> "));
            }
            bar
        });
        Self {
            bar,
            start: Instant::now(),
            shown: AtomicBool::new(false),
        }
    }

    fn update(&self, done: usize, total: usize) {
        let Some(bar) = &self.bar else { return };
        if self.start.elapsed() >= PROGRESS_DELAY && !self.shown.swap(true, Ordering::Relaxed) {
            bar.set_length(total as u64);
            bar.set_draw_target(ProgressDrawTarget::stderr());
        }
        bar.set_position(done as u64);
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;

    fn camera(projection: Projection) -> Camera {
        Camera {
            name: "c".into(),
            world_from_camera: Mat4::IDENTITY,
            projection,
        }
    }

    #[test]
    fn size_follows_the_camera_aspect() {
        let free = camera(Projection::Perspective {
            yfov: 1.0,
            aspect_ratio: None,
        });
        assert_eq!(image_size(None, None, &free), (1280, 720));
        assert_eq!(image_size(Some(640), None, &free), (640, 360));
        let square = camera(Projection::Perspective {
            yfov: 1.0,
            aspect_ratio: Some(1.0),
        });
        assert_eq!(image_size(Some(300), None, &square), (300, 300));
        assert_eq!(image_size(None, Some(200), &square), (200, 200));
        let ortho = camera(Projection::Orthographic {
            xmag: 2.0,
            ymag: 1.0,
        });
        assert_eq!(image_size(Some(100), None, &ortho), (100, 50));
        assert_eq!(image_size(Some(7), Some(9), &ortho), (7, 9));
    }
}
