//! Runs the jobs of one shard.
//!
//! Jobs are grouped by (canonical scene path, backend, scene index, time, load options). Each
//! group's scene is loaded and its ray-query structure built once, then all its jobs render
//! concurrently on one rayon pool, whose workers also share the tiles of every job: small
//! jobs run side by side, a large job spreads over all cores, and no core idles while work is
//! left in the group. Groups run one after the other, so one scene is in memory at a time.
//! (Loading inside the concurrent part would need a lock held across rayon work, which can
//! deadlock when a waiting worker steals a job that waits for the same lock.)
//!
//! Before anything renders, every job's output must resolve inside the output root
//! ([`super::paths::confine`]) and every output folder must pass a write probe
//! ([`super::paths::probe_writable`]); a job failing either is reported and not rendered.
//!
//! Resume: a job whose every declared output exists and is complete is skipped. glint writes
//! a job's outputs as one unit (each to a temporary file, then renamed with the image last:
//! [`crate::output::atomic::write_together`]), so an image present under the output's name
//! was written complete, with its sidecar. The sidecar must exist where the job writes one,
//! name the image, and hold annotations where the job asks for them. The runner still decodes the whole file and checks the image size against the
//! job's `width`/`height` (where the job gives them), so a file glint did not write (copied
//! in, truncated by hand) or a stale one of another size is rendered again; decoding a small
//! image costs far less than rendering it. An EXR whose `glint.brdf` header names another
//! metallic-roughness model than the job's (`brdf = "spec"` against the default) is stale
//! too; a PNG carries no such header, so changing the model of PNG jobs needs `--force`.
//!
//! Concurrent batches: a job renders only under its claim ([`super::claim`]), taken just
//! before the job starts, so two processes on one job file share its jobs and never render
//! one twice; a job claimed by another live process is reported `busy`. Holding the claim,
//! the runner removes the temporary files that killed runs left for the job's output.
//!
//! Isolation: a failing job (bad scene, bad path, even a panic in its render or in its
//! scene's load and preparation) is reported and the others go on. A panic is caught by
//! [`panics::catch`] and reported as one "internal error while …" line with the message and
//! location the quiet hook recorded.

use super::claim;
use super::jobs::Job;
use super::paths;
use super::report::{BatchReport, JobReport, JobStatus};
use super::shard::Shard;
use crate::accel::BackendKind;
use crate::job::{DEFAULT_ASPECT, DEFAULT_WIDTH, PreparedScene, RunOptions};
use crate::panics;
use crate::render::{self, RenderError};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::time::{Instant, SystemTime};

/// How to run a batch.
#[derive(Clone, Debug)]
pub struct BatchOptions {
    /// The folder every output must resolve inside; `None`: the job file's folder.
    pub output_root: Option<PathBuf>,
    /// Which jobs to run.
    pub shard: Shard,
    /// Render jobs whose output already exists, unless another batch wrote it while this one
    /// ran (then it is that batch's fresh work).
    pub force: bool,
    /// Claims of other batches this one may take over (see [`claim`]'s stale-claim rule).
    pub claims: claim::ClaimPolicy,
    /// Worker threads shared by all jobs; 0 uses every core.
    pub threads: usize,
    /// No progress bar and no per-job lines (errors still print).
    pub quiet: bool,
}

/// Loads and prepares the scene of a group's jobs (all share it); the error is one line.
pub type SceneLoader<'a> = dyn Fn(&Job) -> Result<PreparedScene, String> + Sync + 'a;

/// Runs the jobs of `options.shard` out of `jobs` (all the jobs of `job_file`). Fails only
/// when the thread pool cannot start; job failures are in the report.
pub fn run(
    jobs: &[Job],
    job_file: &Path,
    options: &BatchOptions,
) -> Result<BatchReport, RenderError> {
    run_with_loader(jobs, job_file, options, &load_scene)
}

/// The scene loader of [`run`]: the job's file, selection and load options, prepared for
/// its backend.
pub fn load_scene(job: &Job) -> Result<PreparedScene, String> {
    let render = &job.render;
    PreparedScene::load(
        &render.scene,
        &render.selection,
        &render.load_options,
        render.backend,
    )
    .map_err(|e| e.to_string())
}

/// [`run`] with another scene loader (tests use one that fails or panics on purpose).
pub fn run_with_loader(
    jobs: &[Job],
    job_file: &Path,
    options: &BatchOptions,
    load: &SceneLoader<'_>,
) -> Result<BatchReport, RenderError> {
    let start = Instant::now();
    // With --force, outputs written after this moment are another batch's work. The process's
    // own start, not this call's: two batches started side by side begin their processes
    // together, but the later one may reach this line after the earlier one wrote a job.
    let started = claim::this_process_started().unwrap_or_else(std::time::SystemTime::now);
    let mut reports: Vec<JobReport> = Vec::new();
    let fail =
        |job: &Job, message: String| report(job, JobStatus::Failed, 0.0, None, Some(message));
    // Failures found before any render are printed at once (with -q too, as all failures).
    let fail_early = |job: &Job, message: String| {
        eprintln!("job {} ({}) failed: {message}", job.index, job.origin);
        fail(job, message)
    };
    let root = match &options.output_root {
        Some(root) => root.clone(),
        None => match job_file.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        },
    };
    // Outputs inside the root, folders writable: checked for every job before any render.
    let mut todo: Vec<&Job> = Vec::new();
    let mut probed: HashMap<PathBuf, Result<(), String>> = HashMap::new();
    for job in jobs.iter().filter(|j| options.shard.takes(j.index)) {
        let resolved = match paths::confine(job.output(), &root) {
            Ok(resolved) => resolved,
            Err(message) => {
                reports.push(fail_early(job, message));
                continue;
            }
        };
        let folder = resolved.parent().unwrap_or(Path::new("/")).to_path_buf();
        let probe = probed
            .entry(folder.clone())
            .or_insert_with(|| paths::probe_writable(&folder));
        if let Err(message) = probe {
            reports.push(fail_early(job, message.clone()));
            continue;
        }
        if !options.force && output_is_complete(job) {
            // A batch killed between writing this output and giving its claim up left the
            // claim file (and perhaps temporaries of a later write): free, so removed.
            if let Ok(Some(held)) = claim::try_claim_with(job.output(), &options.claims) {
                remove_job_temps(&held, job);
                held.release();
            }
            reports.push(report(job, JobStatus::Skipped, 0.0, None, None));
        } else {
            todo.push(job);
        }
    }
    let any_embree = todo.iter().any(|j| j.render.backend == BackendKind::Embree);
    let pool = render::thread_pool(
        options.threads,
        if any_embree {
            BackendKind::Embree
        } else {
            BackendKind::Bvh
        },
    )?;
    let progress = Progress::new(&todo, options.quiet);

    let mut load_seconds = 0.0;
    for group in groups(&todo) {
        // Another process may hold or have finished every job of the group: then loading
        // the scene would be wasted. (Only a hint: the claims below decide.)
        if !group
            .iter()
            .any(|job| might_need_rendering(job, options, started))
        {
            for job in group {
                let status = if output_is_complete(job) {
                    JobStatus::Skipped
                } else {
                    JobStatus::Busy
                };
                progress.pass_job(job, "not rendered here (done, or claimed by another batch)");
                reports.push(busy_or_skipped(job, status));
            }
            continue;
        }
        let load_start = Instant::now();
        let first = group[0];
        let prepared = pool.install(|| {
            panics::catch(|| load(first)).unwrap_or_else(|panic| {
                Err(panic.report(&format!(
                    "loading or preparing the scene {}",
                    first.scene().display()
                )))
            })
        });
        load_seconds += load_start.elapsed().as_secs_f64();
        let prepared = match prepared {
            Ok(ok) => ok,
            Err(message) => {
                for job in group {
                    progress.finish_job(job, Err(&message));
                    reports.push(fail(job, message.clone()));
                }
                continue;
            }
        };
        let done: Vec<JobReport> = pool.install(|| {
            group
                .par_iter()
                .map(|job| claim_and_render(job, &prepared, &pool, &progress, options, started))
                .collect()
        });
        reports.extend(done);
    }
    progress.finish();
    reports.sort_by_key(|r| r.index);
    let count = |s| reports.iter().filter(|r| r.status == s).count();
    Ok(BatchReport {
        job_file: job_file.to_path_buf(),
        shard: format!("{}/{}", options.shard.index, options.shard.count),
        jobs_in_file: jobs.len(),
        rendered: count(JobStatus::Rendered),
        skipped: count(JobStatus::Skipped),
        failed: count(JobStatus::Failed),
        busy: count(JobStatus::Busy),
        seconds: start.elapsed().as_secs_f64(),
        load_seconds,
        jobs: reports,
    })
}

/// Removes the temporary files killed runs left for `job`'s outputs (its image and its
/// sidecar), while holding its claim.
fn remove_job_temps(held: &claim::Claim, job: &Job) {
    held.remove_stray_temps();
    for temp in crate::output::atomic::stray_temps(&crate::output::sidecar_path(job.output())) {
        let _ = std::fs::remove_file(temp.path);
    }
}

/// Whether `job` may still need rendering here: its claim is free (checked by taking and
/// dropping it) and its output is not complete (or `force`, and no other batch wrote it
/// since `started`).
fn might_need_rendering(job: &Job, options: &BatchOptions, started: SystemTime) -> bool {
    match claim::try_claim_with(job.output(), &options.claims) {
        // Cannot claim: let the job itself report why.
        Err(_) => true,
        Ok(None) => false,
        Ok(Some(held)) => {
            let needed = if options.force {
                !written_since(job, started)
            } else {
                !output_is_complete(job)
            };
            // Released (file removed) either way, so a failed load leaves no claim file.
            held.release();
            needed
        }
    }
}

/// Whether `job`'s output is complete and was written at or after `started`: by another batch
/// running beside this one (this one renders each job once), whose work `--force` must not
/// redo.
fn written_since(job: &Job, started: SystemTime) -> bool {
    output_is_complete(job)
        && std::fs::metadata(job.output())
            .and_then(|m| m.modified())
            .is_ok_and(|modified| modified >= started)
}

fn busy_or_skipped(job: &Job, status: JobStatus) -> JobReport {
    let error = (status == JobStatus::Busy).then(|| {
        format!(
            "claimed by another glint batch ({}); not rendered here",
            claim::holder(job.output()).unwrap_or_else(|| "holder unknown".into())
        )
    });
    report(job, status, 0.0, None, error)
}

/// Claims, renders and writes one job, and gives its claim up.
fn claim_and_render(
    job: &Job,
    prepared: &PreparedScene,
    pool: &rayon::ThreadPool,
    progress: &Progress,
    options: &BatchOptions,
    started: SystemTime,
) -> JobReport {
    let held = match claim::try_claim_with(job.output(), &options.claims) {
        Ok(Some(held)) => held,
        Ok(None) => {
            progress.pass_job(job, "claimed by another glint batch; not rendered here");
            return busy_or_skipped(job, JobStatus::Busy);
        }
        Err(e) => {
            let message = format!(
                "cannot create the claim file {}: {e}; check the output folder's permissions",
                claim::claim_path(job.output()).display()
            );
            progress.finish_job(job, Err(&message));
            return report(job, JobStatus::Failed, 0.0, None, Some(message));
        }
    };
    remove_job_temps(&held, job);
    // Another process may have finished the job since this one looked (with --force: since
    // this batch started).
    let done_elsewhere = if options.force {
        written_since(job, started)
    } else {
        output_is_complete(job)
    };
    if done_elsewhere {
        held.release();
        progress.pass_job(job, "written by another glint batch meanwhile; skipped");
        return report(job, JobStatus::Skipped, 0.0, None, None);
    }
    let job_start = Instant::now();
    let tick = |done: usize, total: usize| progress.tick(job, done, total);
    let result = panics::catch(|| render_job(job, prepared, pool, &tick)).unwrap_or_else(|panic| {
        Err(panic.report(&format!(
            "rendering {} to {}",
            job.scene().display(),
            job.output().display()
        )))
    });
    held.release();
    let seconds = job_start.elapsed().as_secs_f64();
    progress.finish_job(job, result.as_ref().map(|_| ()).map_err(|e| e.as_str()));
    match result {
        Ok(stats) => report(job, JobStatus::Rendered, seconds, Some(stats), None),
        Err(e) => report(job, JobStatus::Failed, seconds, None, Some(e)),
    }
}

/// Jobs grouped by (canonical scene, backend, scene index, animation time, material variant, asset root,
/// texture and geometry budgets), groups in order of first appearance: jobs share a load only if they load
/// the same scene at the same time under the same rules.
fn groups<'a>(jobs: &[&'a Job]) -> Vec<Vec<&'a Job>> {
    type Key = (
        PathBuf,
        BackendKind,
        Option<usize>,
        Option<u32>,
        Option<String>,
        Option<PathBuf>,
        u64,
        u64,
    );
    let mut keys: Vec<Key> = Vec::new();
    let mut groups: Vec<Vec<&Job>> = Vec::new();
    for &job in jobs {
        let path = std::fs::canonicalize(job.scene()).unwrap_or_else(|_| job.scene().into());
        let key = (
            path,
            job.render.backend,
            job.render.selection.scene,
            job.render.selection.time.map(f32::to_bits),
            job.render.selection.variant.clone(),
            job.render.load_options.asset_root.clone(),
            job.render.load_options.max_texture_pixels,
            job.render.load_options.max_geometry_bytes,
        );
        match keys.iter().position(|k| *k == key) {
            Some(i) => groups[i].push(job),
            None => {
                keys.push(key);
                groups.push(vec![job]);
            }
        }
    }
    groups
}

/// Renders one job on the shared pool; the error is one line naming the job's files (the
/// report's text).
fn render_job(
    job: &Job,
    prepared: &PreparedScene,
    pool: &rayon::ThreadPool,
    tick: &(dyn Fn(usize, usize) + Sync),
) -> Result<render::RenderStats, String> {
    // The output folder exists: the write probe created it. Notes are dropped (a batch
    // reports per job), and `run` names the scene in its errors already.
    let options = RunOptions {
        pool: Some(pool),
        progress: Some(tick),
        ..RunOptions::default()
    };
    let done = crate::job::run(&job.render, prepared, options).map_err(|e| e.to_string())?;
    Ok(done.stats)
}

/// The EXR header attribute naming the metallic-roughness model (`glint.brdf`).
const BRDF_ATTRIBUTE: &str = "glint.brdf";

/// Whether the job's every declared output exists and matches what the job would write now
/// (see the module documentation): the image, of the job's size; the sidecar where the job
/// writes one, naming the image and, with `--annotations`, holding them; for an EXR, the
/// metallic-roughness model, the AOV channels and the denoiser's `noisy` layer the job asks
/// for. Every EXR's header is checked against the pixel and memory budgets before any pixel
/// is read.
pub fn output_is_complete(job: &Job) -> bool {
    let path = job.output();
    let Ok(meta) = std::fs::metadata(path) else {
        return false;
    };
    if !meta.is_file() || meta.len() == 0 {
        return false;
    }
    if job.render.writes_sidecar() {
        let Ok(sidecar) = crate::output::read_sidecar(&crate::output::sidecar_path(path)) else {
            return false;
        };
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
        if Some(sidecar.image) != name
            || (job.render.settings.aovs.annotations && !sidecar.annotated)
        {
            return false;
        }
    }
    let size = match crate::output::OutputFormat::from_path(path) {
        Ok(crate::output::OutputFormat::Png) => {
            // The header first: a PNG declaring more pixels than glint renders is not one of
            // its outputs, and is not decoded.
            match image::image_dimensions(path) {
                Ok((w, h)) if u64::from(w) * u64::from(h) <= crate::render::MAX_PIXELS => {
                    image::open(path)
                        .ok()
                        .map(|image| (image.width(), image.height()))
                }
                _ => None,
            }
        }
        Ok(crate::output::OutputFormat::Exr) => exr_matches(job, path),
        Err(_) => None,
    };
    let Some((width, height)) = size else {
        return false;
    };
    let render = &job.render;
    render.width.is_none_or(|w| w == width) && render.height.is_none_or(|h| h == height)
}

/// The size of the EXR output `path` if it is complete and holds what `job` asks for: its
/// model, its AOV channels, its `noisy` layer. `None` otherwise.
fn exr_matches(job: &Job, path: &Path) -> Option<(u32, u32)> {
    use exr::prelude::traits::*;
    crate::output::budget::check_exr(
        path,
        crate::render::MAX_PIXELS,
        crate::output::budget::memory_budget(),
    )
    .ok()?;
    // On this thread: a decompressor's panic on a corrupt block, caught, is a stale output.
    let image = crate::panics::catch(|| {
        exr::prelude::read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .first_valid_layer()
            .all_attributes()
            .non_parallel()
            .from_file(path)
            .ok()
    })
    .ok()??;
    let layer = &image.layer_data;
    // An EXR names the metallic-roughness model that rendered it: one of another model is
    // stale (a PNG cannot say; `--force` renders it again).
    let model = layer
        .attributes
        .other
        .get(&exr::meta::attribute::Text::from(BRDF_ATTRIBUTE));
    if let Some(exr::meta::attribute::AttributeValue::Text(model)) = model
        && *model != *job.render.settings.brdf.name()
    {
        return None;
    }
    let has = |name: &str| {
        layer
            .channel_data
            .list
            .iter()
            .any(|c| c.name.to_string() == name)
    };
    let aovs = &job.render.settings.aovs;
    let flows = job.render.selection.time.is_some();
    let expected = [
        ("albedo.R", aovs.albedo),
        ("normal.X", aovs.normal),
        ("depth.Z", aovs.depth),
        ("instance_id", aovs.instance_id),
        ("material_id", aovs.material_id),
        ("coverage.id0", aovs.coverage),
        ("z", aovs.z),
        ("position.X", aovs.position),
        ("uv.U", aovs.uv),
        ("flow.X", aovs.flow && flows),
        ("flow_backward.X", aovs.flow_backward && flows),
        ("noisy.R", job.render.denoise),
    ];
    if expected.iter().any(|&(name, wanted)| has(name) != wanted) {
        return None;
    }
    Some((layer.size.0 as u32, layer.size.1 as u32))
}

fn report(
    job: &Job,
    status: JobStatus,
    seconds: f64,
    stats: Option<render::RenderStats>,
    error: Option<String>,
) -> JobReport {
    let rays = stats.map(|s| s.rays).unwrap_or_default();
    JobReport {
        index: job.index,
        origin: job.origin.clone(),
        scene: job.scene().to_path_buf(),
        output: job.output().to_path_buf(),
        status,
        seconds,
        rays: rays.traced(),
        camera_rays: rays.camera,
        shadow_rays: rays.shadow,
        reflection_rays: rays.reflection,
        error,
    }
}

/// One progress bar over the whole batch. Its length is the batch's estimated work: each
/// job counts width × height × spp (with `glint render`'s default size where the job leaves
/// it to the camera), and advances as its tiles finish.
struct Progress {
    bar: ProgressBar,
    jobs: usize,
    finished: AtomicUsize,
    failed: AtomicUsize,
    /// Work units reported so far per job, by position in the shard's job list.
    reported: Vec<AtomicU64>,
    positions: std::collections::HashMap<usize, usize>,
    estimates: Vec<u64>,
    quiet: bool,
}

impl Progress {
    fn new(jobs: &[&Job], quiet: bool) -> Self {
        let estimates: Vec<u64> = jobs
            .iter()
            .map(|j| {
                let width = j.render.width.unwrap_or(DEFAULT_WIDTH) as u64;
                let height = j
                    .render
                    .height
                    .unwrap_or((width as f32 / DEFAULT_ASPECT).round() as u32)
                    as u64;
                (width * height * j.render.settings.spp as u64).max(1)
            })
            .collect();
        let bar = if quiet {
            ProgressBar::hidden()
        } else {
            let bar = ProgressBar::with_draw_target(
                Some(estimates.iter().sum()),
                ProgressDrawTarget::stderr(),
            );
            if let Ok(style) = ProgressStyle::with_template(
                "{elapsed_precise} [{bar:30}] {percent:>3}% {msg}, eta {eta}",
            ) {
                bar.set_style(style.progress_chars("=> "));
            }
            bar
        };
        let progress = Self {
            bar,
            jobs: jobs.len(),
            finished: AtomicUsize::new(0),
            failed: AtomicUsize::new(0),
            reported: jobs.iter().map(|_| AtomicU64::new(0)).collect(),
            positions: jobs.iter().enumerate().map(|(p, j)| (j.index, p)).collect(),
            estimates,
            quiet,
        };
        progress.message();
        progress
    }

    fn message(&self) {
        let failed = self.failed.load(Ordering::Relaxed);
        let failed = if failed > 0 {
            format!(", {failed} failed")
        } else {
            String::new()
        };
        self.bar.set_message(format!(
            "{}/{} jobs{failed}",
            self.finished.load(Ordering::Relaxed),
            self.jobs
        ));
    }

    /// Records that `done` of `total` tiles of `job` are finished.
    fn tick(&self, job: &Job, done: usize, total: usize) {
        let Some(&p) = self.positions.get(&job.index) else {
            return;
        };
        let units = self.estimates[p] * done as u64 / total.max(1) as u64;
        let before = self.reported[p].fetch_max(units, Ordering::Relaxed);
        if units > before {
            self.bar.inc(units - before);
        }
    }

    fn finish_job(&self, job: &Job, result: Result<(), &str>) {
        self.end_job(
            job,
            result.map(|()| format!("wrote {}", job.output().display())),
        );
    }

    /// Ends a job that was not rendered here (complete already, or claimed elsewhere).
    fn pass_job(&self, job: &Job, why: &str) {
        self.end_job(job, Ok(why.to_string()));
    }

    fn end_job(&self, job: &Job, result: Result<String, &str>) {
        if let Some(&p) = self.positions.get(&job.index) {
            let before = self.reported[p].swap(self.estimates[p], Ordering::Relaxed);
            self.bar.inc(self.estimates[p].saturating_sub(before));
        }
        self.finished.fetch_add(1, Ordering::Relaxed);
        let line = match result {
            Ok(_) if self.quiet => None,
            Ok(what) => Some(format!("job {} ({}): {what}", job.index, job.origin)),
            Err(e) => {
                self.failed.fetch_add(1, Ordering::Relaxed);
                Some(format!("job {} ({}) failed: {e}", job.index, job.origin))
            }
        };
        if let Some(line) = line {
            if self.bar.is_hidden() {
                eprintln!("{line}");
            } else {
                self.bar.println(line);
            }
        }
        self.message();
    }

    fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scene load that panics (no real input makes glint's loader panic any more, so the
    /// loader is replaced): its group fails with a message, the other group renders.
    #[test]
    fn a_panic_while_loading_one_scene_fails_its_jobs_only() {
        let dir = tempfile::tempdir().unwrap();
        let demo = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/demo.glb");
        let file = dir.path().join("jobs.toml");
        let job = |index: usize, scene: &Path, output: &str| Job {
            index,
            origin: format!("[[job]] {index}"),
            render: crate::job::Job {
                scene: crate::scene::SceneSource::File(scene.to_path_buf()),
                backend: BackendKind::Bvh,
                width: Some(8),
                height: Some(6),
                settings: crate::render::RenderSettings {
                    spp: 1,
                    ..crate::job::Job::default().settings
                },
                output: Some(crate::job::OutputSpec {
                    path: dir.path().join(output),
                    ..Default::default()
                }),
                ..Default::default()
            },
        };
        let boom = dir.path().join("boom.glb");
        let jobs = [
            job(0, &boom, "a.png"),
            job(1, &demo, "b.png"),
            job(2, &boom, "c.png"),
        ];
        let loader = |job: &Job| {
            if job.scene().ends_with("boom.glb") {
                panic!("injected load panic");
            }
            load_scene(job)
        };
        let options = BatchOptions {
            output_root: None,
            shard: Shard::ALL,
            force: false,
            claims: Default::default(),
            threads: 1,
            quiet: true,
        };
        let report = run_with_loader(&jobs, &file, &options, &loader).unwrap();
        let status: Vec<JobStatus> = report.jobs.iter().map(|j| j.status).collect();
        assert_eq!(
            status,
            [JobStatus::Failed, JobStatus::Rendered, JobStatus::Failed]
        );
        let error = report.jobs[0].error.as_deref().unwrap_or_default();
        assert!(
            error.contains("boom.glb")
                && error.contains("internal error while loading")
                && error.contains("injected load panic"),
            "{error}"
        );
        assert!(dir.path().join("b.png").is_file());
        assert!(!dir.path().join("a.png").exists());
        // No claim or temporary file is left for any job.
        let names: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert!(names.iter().all(|n| !n.starts_with('.')), "{names:?}");
    }
}
