//! Running a job: [`run`] completes the scene for it, renders it and writes its output.

use super::complete::environment_for;
use super::{Job, JobError, PreparedScene, Samples, fixed_aspect, image_size};
use crate::accel::BuildOptions;
use crate::light::LightUnits;
use crate::output::fingerprint::SceneTag;
use crate::output::instances::annotate;
use crate::output::sidecar::{Sidecar, sidecar_path, write_sidecar};
use crate::output::{OutputError, OutputFormat, PngDepth, PngOptions, write_exr_layers, write_png};
use crate::render::ground_truth::{self, OtherTime};
use crate::render::projection::FilmProjection;
use crate::render::{
    Aovs, Image, Progress, RenderError, RenderInputs, RenderSettings, RenderStats, partial,
    progressive,
};
use crate::scene::defaults::{self, Completed};
use crate::scene::gltf::SceneSelection;
use crate::scene::{Camera, Light};
use glam::Vec3;
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

/// How [`run`] runs a job, besides the job itself. `Default`: a pool of the job's own, no
/// progress report, notes dropped, not cancellable.
#[derive(Clone, Copy, Default)]
pub struct RunOptions<'a> {
    /// A pool shared with other jobs (`glint batch`, the Python package's `render_batch`);
    /// `None` starts one of the job's `settings.threads` threads.
    pub pool: Option<&'a rayon::ThreadPool>,
    /// Called from worker threads as tiles finish.
    pub progress: Option<Progress<'a>>,
    /// Receives notes for the user (a default camera, lights or environment added, a
    /// stretched aspect ratio, options without effect); `None` drops them.
    pub say: Option<&'a dyn Fn(String)>,
    /// Setting it stops the render at the next tile, and the job fails with
    /// [`crate::render::RenderError::Cancelled`], writing nothing (the Python package's
    /// Ctrl-C). `None`: not cancellable.
    pub cancel: Option<&'a AtomicBool>,
}

/// What [`run`] rendered (and wrote, if the job has an output).
#[derive(Clone, Debug)]
pub struct JobOutput {
    /// The file written, if any.
    pub output: Option<PathBuf>,
    /// Image size in pixels.
    pub width: u32,
    /// Image size in pixels.
    pub height: u32,
    /// The samples rendered (all of 0..spp unless partial or progressive).
    pub samples: Range<u32>,
    /// What the render traced.
    pub stats: RenderStats,
    /// How the samples were chosen, for a summary line: a partial range, or why a
    /// progressive render stopped ("" for a plain render).
    pub note: String,
    /// The resolved images, for callers that keep them in memory (the Python package);
    /// `None` for a partial job, whose output is sums, not an image.
    pub images: Option<JobImages>,
    /// What the camera sidecar says about the image (written beside it with
    /// [`super::OutputSpec::sidecar`]); `None` for a partial job.
    pub sidecar: Option<Sidecar>,
    /// Seconds the denoiser took, for a denoised job ([`Job::denoise`]).
    pub denoise_seconds: Option<f64>,
}

/// Resolved images of a job ([`JobOutput::images`]).
#[derive(Clone, Debug)]
pub struct JobImages {
    /// Radiance, W/(m²·sr).
    pub image: Image<Vec3>,
    /// The selected AOVs.
    pub aovs: Aovs,
    /// The camera sidecar of the image (also [`JobOutput::sidecar`]).
    pub sidecar: Sidecar,
    /// For a denoised job, the radiance before denoising (`image` is then the denoised one).
    pub noisy: Option<Image<Vec3>>,
}

/// Runs `job` on `prepared` (which must come from the job's scene and backend): checks the
/// job, completes the camera, lights and environment, renders the samples and writes the
/// output. Every error names the scene.
pub fn run(
    job: &Job,
    prepared: &PreparedScene,
    options: RunOptions<'_>,
) -> Result<JobOutput, JobError> {
    run_in_scene(job, prepared, options).map_err(|e| e.in_scene(&prepared.label))
}

/// The scene as one job renders it: the camera, the lights and the environment, with the
/// settings their completion implies.
struct Completion {
    camera: Camera,
    lights: Vec<Light>,
    environment: Option<Arc<crate::light::environment::EnvironmentLight>>,
    settings: RenderSettings,
}

fn run_in_scene(
    job: &Job,
    prepared: &PreparedScene,
    options: RunOptions<'_>,
) -> Result<JobOutput, JobError> {
    let say = |note: String| {
        if let Some(say) = options.say {
            say(note);
        }
    };
    job.check()?;
    let completion = complete(job, prepared, &say)?;
    let Completion {
        camera,
        lights,
        environment,
        settings,
    } = &completion;
    // The render's buffers against the memory budget, before they are allocated.
    job.check_memory(settings.width, settings.height)?;
    let inputs = RenderInputs {
        scene: &prepared.scene,
        lights,
        accel: prepared.accel.as_ref(),
        camera,
        pool: options.pool,
        mipmaps: Some(&prepared.mipmaps),
        environment: environment.as_deref(),
        area_lights: Some(&prepared.area_lights),
        cancel: options.cancel,
    };
    // Test-only (debug builds): a forced panic where the render starts, for tests/hostile/panics.rs.
    crate::panics::test_panic_point("render", &prepared.label);
    let output = job.output.as_ref();
    let done = |samples, stats, note, images, sidecar, denoise_seconds| JobOutput {
        output: output.map(|o| o.path.clone()),
        width: settings.width,
        height: settings.height,
        samples,
        stats,
        note,
        images,
        sidecar,
        denoise_seconds,
    };
    if let Some(samples) = job.partial_samples()? {
        let (part, stats) =
            partial::render_partial(&inputs, settings, samples.clone(), options.progress)?;
        if let Some(out) = output {
            // What the part was rendered from, so that `glint merge` refuses foreign parts.
            let mut tag = SceneTag::of(
                &job.scene,
                &job.selection,
                camera,
                settings.width,
                settings.height,
            )
            .map_err(|source| OutputError::Io {
                path: out.path.clone(),
                source,
            })?;
            tag.kernels = Some(prepared.accel.kernels());
            tag.brdf = Some(settings.brdf.name().to_string());
            crate::output::partial::write_partial_exr_tagged(&out.path, &part, Some(&tag))?;
        }
        let note = format!(", samples {}..{} (partial)", samples.start, samples.end);
        return Ok(done(samples, stats, note, None, None, None));
    }
    let (image, mut aovs, stats, samples, note) = match &job.samples {
        Samples::Progressive(rule) => {
            let p =
                progressive::render_progressive_with(&inputs, settings, rule, options.progress)?;
            let note = format!(
                "; stopped after {} passes ({:?}), estimated relative error {:.4}",
                p.passes, p.reason, p.relative_error
            );
            let o = p.output;
            (o.image, o.aovs, o.stats, 0..p.spp, note)
        }
        _ => {
            let o = crate::render::render_with(&inputs, settings, options.progress)?;
            let note = match &o.aovs.samples {
                Some(counts) => format!(
                    "; adaptive: {:.1} samples per pixel on average",
                    counts.pixels.iter().map(|&n| n as f64).sum::<f64>()
                        / counts.pixels.len().max(1) as f64
                ),
                None => String::new(),
            };
            (o.image, o.aovs, o.stats, 0..settings.spp, note)
        }
    };
    let projection =
        FilmProjection::new(camera, settings.width, settings.height).map_err(|reason| {
            RenderError::Camera {
                name: camera.name.clone(),
                reason,
            }
        })?;
    if settings.aovs.any_geometric() {
        geometric_aovs(job, prepared, &projection, &mut aovs)?;
    }
    let flows = settings.aovs.flow || settings.aovs.flow_backward;
    let image_name = output
        .and_then(|o| o.path.file_name())
        .map_or(String::new(), |n| n.to_string_lossy().into_owned());
    let mut sidecar = Sidecar::new(
        &image_name,
        &projection,
        job.selection.time,
        // The scene rendered: the one asked for, else the file's default scene.
        job.selection.scene.or_else(|| match &job.scene {
            crate::scene::SceneSource::File(path) => {
                crate::output::fingerprint::default_scene_index(path)
            }
            crate::scene::SceneSource::Demo => None,
        }),
        flows.then(|| job.flow_dt.unwrap_or(super::DEFAULT_FLOW_DT)),
        ground_truth_channels(&aovs),
    );
    // Per-instance annotations go into the sidecar, which they make written.
    sidecar.annotated = settings.aovs.annotations;
    if let Some(counts) = &aovs.instance_samples {
        let categories: BTreeMap<String, String> = job.categories.iter().cloned().collect();
        sidecar.instances = annotate(&prepared.scene, counts, &categories);
    }
    let (image, aovs, noisy, denoise_seconds) = if job.denoise {
        let denoised = denoise_job(job, &image, aovs)?;
        (denoised.0, denoised.1, Some(image), Some(denoised.2))
    } else {
        (image, aovs, None, None)
    };
    if let Some(out) = output {
        // One unit: the sidecar first, the image last, renamed only when both are complete
        // (a present image means the job's every output is present).
        crate::output::atomic::write_together(|| {
            if job.writes_sidecar() {
                write_sidecar(&sidecar_path(&out.path), &sidecar)?;
            }
            match OutputFormat::from_path(&out.path)? {
                OutputFormat::Png => write_png(
                    &out.path,
                    &image,
                    PngOptions {
                        exposure_ev: out.exposure_ev,
                        depth: if out.png16 {
                            PngDepth::Sixteen
                        } else {
                            PngDepth::Eight
                        },
                    },
                ),
                OutputFormat::Exr => {
                    // One text attribute only: the exr crate keeps them in a hash map, so two
                    // would be written in an order that changes from run to run. A `noisy`
                    // layer is what marks a denoised file.
                    let attributes = [("glint.brdf", settings.brdf.name())];
                    let layers: Vec<(&str, &Image<Vec3>)> =
                        noisy.iter().map(|noisy| ("noisy", noisy)).collect();
                    write_exr_layers(&out.path, &image, &aovs, &layers, &attributes)
                }
            }
        })?;
    }
    Ok(done(
        samples,
        stats,
        note,
        Some(JobImages {
            image,
            aovs,
            sidecar: sidecar.clone(),
            noisy,
        }),
        Some(sidecar),
        denoise_seconds,
    ))
}

/// The EXR channels of the geometric AOVs `aovs` holds, for the sidecar.
fn ground_truth_channels(aovs: &Aovs) -> Vec<String> {
    let mut names = Vec::new();
    let mut add = |present: bool, list: &[&str]| {
        if present {
            names.extend(list.iter().map(|s| s.to_string()));
        }
    };
    add(aovs.z.is_some(), &["z"]);
    add(
        aovs.position.is_some(),
        &["position.X", "position.Y", "position.Z"],
    );
    add(aovs.uv.is_some(), &["uv.U", "uv.V"]);
    add(aovs.flow.is_some(), &["flow.X", "flow.Y"]);
    add(
        aovs.flow_backward.is_some(),
        &["flow_backward.X", "flow_backward.Y"],
    );
    names
}

/// Fills the geometric AOVs ([`ground_truth`]) from the render's centre hits, loading the
/// scene at `time ± Δ` (its own ray queries, for occlusion) for the flows selected. The
/// camera there is the job's camera choice in that scene (a camera glint made or was given
/// stays where it is).
fn geometric_aovs(
    job: &Job,
    prepared: &PreparedScene,
    projection: &FilmProjection,
    aovs: &mut Aovs,
) -> Result<(), JobError> {
    let selection = job.settings.aovs.geometric();
    let dt = job.flow_dt.unwrap_or(super::DEFAULT_FLOW_DT);
    let other = |sign: f32, wanted: bool| -> Result<Option<Posed>, JobError> {
        let Some(time) = job.selection.time.filter(|_| wanted) else {
            return Ok(None);
        };
        let at = SceneSelection {
            time: Some(time + sign * dt),
            ..job.selection.clone()
        };
        // The same file at another time: its warnings were printed with the render's load.
        let scene = job.scene.load_quietly(&at, &job.load_options)?;
        let accel = crate::render::prepare(&scene, job.backend, BuildOptions::default())?;
        let camera = if prepared.scene.cameras.is_empty() {
            projection.camera().clone()
        } else {
            job.camera(&scene)?.value
        };
        let (w, h) = projection.size;
        let moved = FilmProjection::new(&camera, w, h).map_err(|reason| RenderError::Camera {
            name: camera.name.clone(),
            reason,
        })?;
        Ok(Some(Posed {
            scene,
            accel,
            projection: moved,
        }))
    };
    let forward = other(1.0, selection.flow)?;
    let backward = other(-1.0, selection.flow_backward)?;
    fn view(p: &Option<Posed>) -> Option<OtherTime<'_>> {
        p.as_ref().map(|p| OtherTime {
            scene: &p.scene,
            accel: p.accel.as_ref(),
            projection: &p.projection,
        })
    }
    let (forward, backward) = (view(&forward), view(&backward));
    ground_truth::resolve(
        aovs,
        selection,
        &prepared.scene,
        projection,
        forward.as_ref(),
        backward.as_ref(),
    );
    Ok(())
}

/// The scene posed at another time, owned, for [`OtherTime`].
struct Posed {
    scene: crate::scene::Scene,
    accel: Box<dyn crate::accel::Accel>,
    projection: FilmProjection,
}

/// Denoises a job's resolved `image` with its albedo and normal AOVs (which [`complete`]
/// turned on for it) and its thread count. Returns the denoised image, the AOVs the job asked
/// for (the auxiliary images it did not ask for are dropped) and the denoiser's seconds.
fn denoise_job(
    job: &Job,
    image: &Image<Vec3>,
    mut aovs: Aovs,
) -> Result<(Image<Vec3>, Aovs, f64), JobError> {
    let start = std::time::Instant::now();
    let aux = match (&aovs.albedo, &aovs.normal) {
        (Some(albedo), Some(normal)) => Some(crate::denoise::Auxiliary { albedo, normal }),
        _ => None,
    };
    let denoised = crate::denoise::denoise(image, aux, job.settings.threads)?;
    let seconds = start.elapsed().as_secs_f64();
    if !job.settings.aovs.albedo {
        aovs.albedo = None;
    }
    if !job.settings.aovs.normal {
        aovs.normal = None;
    }
    Ok((denoised, aovs, seconds))
}

/// Completes the scene for `job`: its camera (asked for, first, or default), its environment
/// ([`environment_for`]), its lights (the scene's and the job's, or the default lights when
/// neither they nor an environment light it) and its image size, announcing what was added.
fn complete(
    job: &Job,
    prepared: &PreparedScene,
    say: &dyn Fn(String),
) -> Result<Completion, JobError> {
    let scene = &prepared.scene;
    let camera = job.camera(scene)?;
    if let Some(note) = camera.added {
        say(note);
    }
    let camera = camera.value;
    let given = job
        .environment
        .as_ref()
        .map(|e| prepared.environment(e))
        .transpose()?;
    let extra = job.extra_lights()?;
    let environment = environment_for(scene, &extra, given, job.settings.integrator)?;
    if let Some(note) = environment.added {
        say(note);
    }
    let environment = environment.value;
    let lights = if environment.is_some() {
        // An environment lights the scene: no default sun on top of it.
        Completed {
            value: scene.lights.iter().cloned().chain(extra).collect(),
            added: None,
        }
    } else {
        defaults::lights_for(scene, extra, &camera)
    };
    // Default lights are radiometric: only lights from the scene or the job are in the job's
    // units.
    let light_units = match lights.added {
        Some(note) => {
            say(note);
            LightUnits::Radiometric
        }
        None => job.light_units,
    };
    let (width, height) = image_size(job.width, job.height, &camera);
    if let (Some(_), Some(_), Some(fixed)) = (job.width, job.height, fixed_aspect(&camera))
        && ((width as f32 / height as f32) / fixed - 1.0).abs() > 0.01
    {
        say(format!(
            "note: {width}×{height} differs from camera \"{}\"'s aspect ratio {fixed:.4}: the \
             image is stretched (give only --width or --height to keep it)",
            camera.name
        ));
    }
    Ok(Completion {
        camera,
        lights: lights.value,
        environment,
        settings: RenderSettings {
            width,
            height,
            light_units,
            aovs: crate::render::AovSelection {
                // The denoiser's auxiliary images (dropped again after it ran when the job
                // did not ask for them).
                albedo: job.settings.aovs.albedo || job.denoise,
                normal: job.settings.aovs.normal || job.denoise,
                ..job.settings.aovs
            },
            ..job.settings
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::BackendKind;
    use crate::job::OutputSpec;

    #[test]
    fn a_cancelled_job_fails_and_writes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.exr");
        let job = Job {
            width: Some(8),
            height: Some(6),
            backend: BackendKind::Bvh,
            output: Some(OutputSpec {
                path: path.clone(),
                ..OutputSpec::default()
            }),
            ..Job::default()
        };
        let prepared =
            PreparedScene::load(&job.scene, &job.selection, &job.load_options, job.backend)
                .unwrap();
        let cancel = AtomicBool::new(true);
        let options = RunOptions {
            cancel: Some(&cancel),
            ..RunOptions::default()
        };
        let err = run(&job, &prepared, options).unwrap_err();
        assert!(err.to_string().contains("cancelled"), "{err}");
        assert!(!path.exists());
        // The same job, not cancelled, renders.
        cancel.store(false, std::sync::atomic::Ordering::Relaxed);
        assert!(run(&job, &prepared, options).is_ok());
        assert!(path.exists());
    }

    #[test]
    fn a_job_renders_without_an_output_and_keeps_its_images() {
        let job = Job {
            width: Some(8),
            height: Some(6),
            settings: RenderSettings {
                spp: 1,
                threads: 1,
                ..Job::default().settings
            },
            backend: BackendKind::Bvh,
            ..Job::default()
        };
        let prepared =
            PreparedScene::load(&job.scene, &job.selection, &job.load_options, job.backend)
                .unwrap();
        let notes = std::sync::Mutex::new(Vec::new());
        let say = |n: String| notes.lock().unwrap().push(n);
        let options = RunOptions {
            say: Some(&say),
            ..RunOptions::default()
        };
        let done = run(&job, &prepared, options).unwrap();
        assert_eq!((done.width, done.height, done.samples), (8, 6, 0..1));
        assert!(done.output.is_none());
        assert!(done.stats.rays.camera == 48, "{:?}", done.stats.rays);
        let images = done.images.expect("a whole render keeps its images");
        assert_eq!((images.image.width, images.image.height), (8, 6));
    }
}
