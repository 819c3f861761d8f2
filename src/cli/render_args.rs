//! The options of one render as `glint render` spells them, and their translation into a
//! library [`Job`] ([`RenderArgs::to_job`]). Batch job files are spelled with the same clap
//! definition: [`super::job_options`] hands it to `glint batch` (which, below the command line,
//! knows no clap) through [`crate::batch::jobs::OptionParser`].

use crate::accel::BackendKind;
use crate::job::{
    CameraChoice, EnvironmentSource, Job, JobError, LightSource, OutputSpec, Samples, SceneSource,
};
use crate::light::LightUnits;
use crate::render::{self, AovSelection, BrdfModel, Integrator, RenderSettings};
use crate::texture::TextureFilter;
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
    /// glTF node index of the instance at the pixel centre (uint32).
    #[value(name = "instance_id", alias = "instance-id")]
    InstanceId,
    /// Material index at the pixel centre (uint32).
    #[value(name = "material_id", alias = "material-id")]
    MaterialId,
    /// Up to 4 instance IDs per pixel with the fraction of its samples each covers.
    Coverage,
    /// Depth along the optical axis at the pixel centre (docs/ground-truth.md).
    Z,
    /// World-space position at the pixel centre.
    Position,
    /// TEXCOORD_0 at the pixel centre.
    Uv,
    /// Optical flow to --time + --flow-dt, pixels (x right, y down).
    Flow,
    /// Optical flow to --time − --flow-dt.
    #[value(name = "flow_backward", alias = "flow-backward")]
    FlowBackward,
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
    #[arg(long, default_value_t = Job::default().settings.spp)]
    pub spp: u32,
    /// Ray-query backend: embree or bvh.
    #[arg(long, default_value_t = BackendKind::default())]
    pub backend: BackendKind,
    /// Which of the file's scenes to render (glTF `scenes` index, from 0) [default: the
    /// file's default scene].
    #[arg(long = "scene", value_name = "N")]
    pub scene_index: Option<usize>,
    /// Sample every animation at this time in seconds [default: none; the rest pose].
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    pub time: Option<f32>,
    /// Render the materials of this KHR_materials_variants variant (`glint info FILE` lists
    /// them) [default: every primitive's default material].
    #[arg(long, value_name = "NAME")]
    pub variant: Option<String>,
    /// Which of the scene's cameras to use (index, from 0) [default: the first, or a default
    /// camera framing the scene if it has none].
    #[arg(long)]
    pub camera: Option<usize>,
    /// Worker threads; 0 uses every core (at most 1024).
    #[arg(long, default_value_t = 0, value_parser = super::values::threads)]
    pub threads: usize,
    /// Seed of the sample positions.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Maximum number of mirror bounces.
    #[arg(long, default_value_t = Job::default().settings.max_depth)]
    pub max_depth: u32,
    /// Maximum number of transmission bounces (refractions, and reflections inside glass),
    /// counted apart from --max-depth.
    #[arg(long, default_value_t = Job::default().settings.max_transmission_depth)]
    pub max_transmission_depth: u32,
    /// Exposure in stops for PNG output (radiance × 2^EV).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// Add a light (repeatable; format in docs/render.md, "Scenes without a camera or lights").
    #[arg(long = "light", value_name = "SPEC")]
    pub light: Vec<String>,
    /// Add the lights of a lights file.
    #[arg(long = "lights", value_name = "FILE")]
    pub lights_file: Option<PathBuf>,
    /// Light intensities are photometric (cd, lx): divide them by 683 lm/W.
    #[arg(long)]
    pub photometric: bool,
    /// Auxiliary images to add to an EXR output (comma-separated).
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "albedo,normal,depth,instance_id,material_id,coverage,z,position,uv,flow,flow_backward"
    )]
    pub aov: Vec<AovName>,
    /// Write the camera sidecar OUT.json beside the image: intrinsics, pose, projection,
    /// time (docs/ground-truth.md).
    #[arg(long)]
    pub sidecar: bool,
    /// Time step of the flow AOVs in seconds: flow goes to --time + DT, flow_backward to
    /// --time − DT [default: 1/24; in a batch animation sweep, the frame interval].
    #[arg(long, value_name = "DT")]
    pub flow_dt: Option<f32>,
    /// Per-instance annotations (visible and amodal masks as COCO RLE, exact areas, visible
    /// fractions, 2D and 3D boxes) in the camera sidecar OUT.json (written with them); costs one any-hit walk per
    /// camera sample. See docs/ground-truth.md.
    #[arg(long)]
    pub annotations: bool,
    /// A category for the annotations of the instances whose node or mesh is named NAME
    /// (repeatable; before the node's extras.category and the mesh's name).
    #[arg(long = "category", value_name = "NAME=CATEGORY", value_parser = parse_category)]
    pub category: Vec<(String, String)>,
    /// Texture filter, overriding the glTF samplers (for experiments): nearest, bilinear and
    /// bicubic read the full-resolution image only; trilinear and anisotropic use MIP maps and
    /// ray differentials.
    #[arg(
        long,
        value_parser = super::values::texture_filter(),
        default_value_t = Job::default().settings.texture_filter
    )]
    pub texture_filter: TextureFilter,
    /// Write 16 bits per channel to PNG.
    #[arg(long)]
    pub png16: bool,
    /// Denoise the finished image with Intel Open Image Denoise (RT filter, with the albedo and
    /// normal AOVs; a biased estimate): PNG gets the denoised image, EXR the denoised one with
    /// the noisy radiance as layer noisy.R/G/B. Needs a build with `--features denoise`.
    #[arg(long)]
    pub denoise: bool,
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
    /// Adaptive sampling: pixels whose estimated relative error is below T stop taking samples
    /// (by Russian roulette, so the image stays unbiased); 0 turns it off [default: off, or
    /// the --target-error E when one is given].
    #[arg(long, value_name = "T")]
    pub adaptive: Option<f32>,
    /// Biased, off by default: clamp each indirect light contribution (after the first
    /// bounce) to at most X in its largest channel, W/(m²·sr) (Blender's default is 10).
    /// Removes fireflies and the energy they carry.
    #[arg(long, value_name = "X")]
    pub clamp_indirect: Option<f32>,
    /// Turn MIS compensation off: environment samples then follow the whole map even where
    /// BSDF samples share the work (for comparisons; unbiased either way).
    #[arg(long)]
    pub no_mis_compensation: bool,
    /// Path guiding (path tracer only, unbiased): learn where light comes from in the first
    /// quarter of the samples, then draw half of each rough vertex's continuations from it.
    /// Finds glossy caustics light sampling cannot (see docs/speed.md for what it buys).
    #[arg(long)]
    pub guiding: bool,
    /// Sample cap of a progressive render.
    #[arg(long, default_value_t = render::progressive::DEFAULT_MAX_SPP)]
    pub max_spp: u32,
    /// Light transport: path (path tracing with next-event estimation and MIS) or direct
    /// (direct light and specular chains only, same BSDF).
    #[arg(
        long,
        value_parser = super::values::integrator(),
        default_value_t = Job::default().settings.integrator
    )]
    pub integrator: Integrator,
    /// Metallic-roughness model: compensated (energy-conserving: multiple-scattering GGX and
    /// a diffuse base that receives what the specular lobe does not reflect, as Cycles,
    /// three.js and Filament render glTF) or spec (the glTF specification's Appendix B exactly,
    /// single-scatter: rough metal loses up to two thirds of its light).
    #[arg(
        long,
        value_parser = super::values::brdf(),
        default_value_t = Job::default().settings.brdf
    )]
    pub brdf: BrdfModel,
    /// Environment map: an equirectangular .hdr or .exr.
    #[arg(long, value_name = "FILE", conflicts_with = "background")]
    pub env: Option<PathBuf>,
    /// Radiance multiplier of --env.
    #[arg(long, default_value_t = 1.0, value_name = "S")]
    pub env_strength: f32,
    /// Rotation of --env about +Y, degrees (right-handed).
    #[arg(
        long,
        default_value_t = 0.0,
        value_name = "DEG",
        allow_negative_numbers = true
    )]
    pub env_rotation: f32,
    /// A uniform environment of radiance R,G,B (W/(m²·sr)).
    #[arg(long, value_name = "R,G,B", value_delimiter = ',', num_args = 1)]
    pub background: Option<Vec<f32>>,
    /// Camera rays that miss show black instead of the environment (alpha is coverage either
    /// way).
    #[arg(long)]
    pub env_hidden: bool,
    /// Every file the glTF refers to must resolve inside this folder (symbolic links
    /// followed), or the load fails naming the URI.
    #[arg(long, value_name = "DIR")]
    pub asset_root: Option<PathBuf>,
    /// Most texels one texture image may have (checked from its header before decoding); all
    /// of a scene's textures together may have four times as many.
    #[arg(long, value_name = "N", default_value_t = crate::scene::gltf::DEFAULT_MAX_TEXTURE_PIXELS)]
    pub max_texture_pixels: u64,
    /// Most bytes of geometry a scene may decode and build (compressed meshopt views and
    /// Draco primitives, and every primitive's vertices and indices), checked from the
    /// declared counts before allocating.
    #[arg(long, value_name = "BYTES", default_value_t = crate::scene::gltf::DEFAULT_MAX_GEOMETRY_BYTES)]
    pub max_geometry_bytes: u64,
    /// Most memory the render's own buffers (film, AOVs, denoiser) may take, estimated
    /// before they are allocated: bytes, or 8G, 512M [default: half of physical memory].
    #[arg(long, value_name = "BYTES", value_parser = super::values::bytes)]
    pub max_memory: Option<u64>,
}

impl RenderArgs {
    /// The loader options these arguments ask for.
    pub fn load_options(&self) -> crate::scene::gltf::LoadOptions {
        crate::scene::gltf::LoadOptions {
            asset_root: self.asset_root.clone(),
            max_texture_pixels: self.max_texture_pixels,
            max_geometry_bytes: self.max_geometry_bytes,
        }
    }

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
        let environment = match (&self.env, &self.background) {
            (Some(path), _) => Some(EnvironmentSource::File {
                path: path.clone(),
                strength: self.env_strength,
                rotation_deg: self.env_rotation,
            }),
            (None, Some(rgb)) => match rgb.as_slice() {
                &[r, g, b] if [r, g, b].iter().all(|c| c.is_finite() && *c >= 0.0) => {
                    Some(EnvironmentSource::Constant(glam::Vec3::new(r, g, b)))
                }
                _ => {
                    return Err(JobError::Options(format!(
                        "--background {rgb:?}: give three non-negative numbers R,G,B"
                    )));
                }
            },
            (None, None) => None,
        };
        if !(self.env_strength.is_finite()
            && self.env_strength >= 0.0
            && self.env_rotation.is_finite())
        {
            return Err(JobError::Options(format!(
                "--env-strength {} / --env-rotation {}: give finite numbers (strength ≥ 0)",
                self.env_strength, self.env_rotation
            )));
        }
        Ok(Job {
            scene: match &self.scene {
                Some(path) => SceneSource::File(path.clone()),
                None => SceneSource::Demo,
            },
            selection: crate::scene::gltf::SceneSelection {
                scene: self.scene_index,
                time: self.time,
                variant: self.variant.clone(),
            },
            load_options: self.load_options(),
            backend: self.backend,
            camera: match self.camera {
                Some(i) => CameraChoice::Index(i),
                None => CameraChoice::First,
            },
            lights,
            environment,
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
                max_transmission_depth: self.max_transmission_depth,
                threads: self.threads,
                aovs: AovSelection {
                    annotations: self.annotations,
                    ..aov_selection(&self.aov)
                },
                texture_filter: self.texture_filter,
                filter: self.filter,
                sampling: self.sampler,
                integrator: self.integrator,
                brdf: self.brdf,
                environment_visible: !self.env_hidden,
                adaptive: render::adaptive::threshold_for(self.adaptive, self.target_error)
                    .map_err(|e| JobError::Options(format!("--adaptive: {e}")))?,
                clamp_indirect: match self.clamp_indirect {
                    Some(x) if !(x > 0.0 && x.is_finite()) => {
                        return Err(JobError::Options(format!(
                            "--clamp-indirect {x}: give a positive radiance, e.g. 10"
                        )));
                    }
                    x => x,
                },
                mis_compensation: !self.no_mis_compensation,
                guiding: self.guiding,
                ..RenderSettings::default()
            },
            samples,
            output: Some(OutputSpec {
                path: output_path(self),
                exposure_ev: self.exposure,
                png16: self.png16,
                sidecar: self.sidecar,
            }),
            flow_dt: self.flow_dt,
            categories: self.category.clone(),
            denoise: self.denoise,
            max_memory: self.max_memory,
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
    use clap::ValueEnum;
    let mut selection = AovSelection::default();
    for name in names {
        // Every `AovName`'s value name is one of `AovSelection::NAMES` (tested below), so
        // each sets a flag.
        if let Some(value) = name.to_possible_value()
            && let Some(flag) = selection.flag_mut(value.get_name())
        {
            *flag = true;
        }
    }
    selection
}

/// `--category NAME=CATEGORY`.
fn parse_category(text: &str) -> Result<(String, String), String> {
    match text.split_once('=') {
        Some((name, category)) if !name.is_empty() && !category.is_empty() => {
            Ok((name.to_string(), category.to_string()))
        }
        _ => Err(format!(
            "'{text}': give NAME=CATEGORY (a node or mesh name, then its category)"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::ValueEnum;

    /// `--aov` takes exactly the names of `AovSelection::NAMES`, and each selects its own AOV.
    #[test]
    fn aov_names_are_the_one_list() {
        let names: Vec<String> = AovName::value_variants()
            .iter()
            .filter_map(|v| v.to_possible_value())
            .map(|v| v.get_name().to_string())
            .collect();
        assert_eq!(names, AovSelection::NAMES);
        for (variant, name) in AovName::value_variants().iter().zip(AovSelection::NAMES) {
            let selection = aov_selection(&[*variant]);
            let mut expected = AovSelection::default();
            *expected.flag_mut(name).unwrap() = true;
            assert_eq!(selection, expected, "{name}");
        }
    }
}
