//! Runs the jobs of one shard.
//!
//! Jobs are grouped by (canonical scene path, backend). Each group's scene is loaded and its
//! ray-query structure built once, then all its jobs render concurrently on one rayon pool,
//! whose workers also share the tiles of every job: small jobs run side by side, a large job
//! spreads over all cores, and no core idles while work is left in the group. Groups run one
//! after the other, so one scene is in memory at a time. (Loading inside the concurrent part
//! would need a lock held across rayon work, which can deadlock when a waiting worker steals
//! a job that waits for the same lock.)
//!
//! Resume: a job whose output exists and is complete is skipped. glint writes every output
//! atomically (temporary file, then rename), so a file present under the output's name is
//! complete. The runner still decodes the whole file and checks the image size against the
//! job's `width`/`height` (where the job gives them), so a file glint did not write (copied
//! in, truncated by hand) or a stale one of another size is rendered again; decoding a small
//! image costs far less than rendering it. A failing job (bad scene, bad path, even a panic) is reported and
//! the others go on.

use super::jobs::Job;
use super::report::{BatchReport, JobReport, JobStatus};
use super::shard::Shard;
use crate::accel::BackendKind;
use crate::render::job::{DEFAULT_ASPECT, DEFAULT_WIDTH, SceneSource};
use crate::render::{self, PreparedScene, RenderError};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::time::Instant;

/// How to run a batch.
#[derive(Clone, Copy, Debug)]
pub struct BatchOptions {
    /// Which jobs to run.
    pub shard: Shard,
    /// Render jobs whose output already exists.
    pub force: bool,
    /// Worker threads shared by all jobs; 0 uses every core.
    pub threads: usize,
    /// No progress bar and no per-job lines (errors still print).
    pub quiet: bool,
}

/// Runs the jobs of `options.shard` out of `jobs` (all the jobs of `job_file`). Fails only
/// when the thread pool cannot start; job failures are in the report.
pub fn run(
    jobs: &[Job],
    job_file: &Path,
    options: &BatchOptions,
) -> Result<BatchReport, RenderError> {
    let start = Instant::now();
    let mut reports: Vec<JobReport> = Vec::new();
    let mut todo: Vec<&Job> = Vec::new();
    for job in jobs.iter().filter(|j| options.shard.takes(j.index)) {
        if !options.force && output_is_complete(job) {
            reports.push(report(job, JobStatus::Skipped, 0.0, None, None));
        } else {
            todo.push(job);
        }
    }
    let any_embree = todo.iter().any(|j| j.args.backend == BackendKind::Embree);
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
        let load_start = Instant::now();
        let first = group[0];
        let prepared = pool.install(|| {
            PreparedScene::load(
                &SceneSource::File(first.scene().to_path_buf()),
                &crate::scene::gltf::SceneSelection {
                    scene: first.args.scene_index,
                    time: first.args.time,
                },
                &first.args.load_options(),
                first.args.backend,
            )
            .map_err(|e| e.to_string())
        });
        load_seconds += load_start.elapsed().as_secs_f64();
        let prepared = match prepared {
            Ok(ok) => ok,
            Err(message) => {
                for job in group {
                    progress.finish_job(job, Err(&message));
                    reports.push(report(
                        job,
                        JobStatus::Failed,
                        0.0,
                        None,
                        Some(message.clone()),
                    ));
                }
                continue;
            }
        };
        let done: Vec<JobReport> = pool.install(|| {
            group
                .par_iter()
                .map(|job| {
                    let job_start = Instant::now();
                    let tick = |done: usize, total: usize| progress.tick(job, done, total);
                    let result = catch_unwind(AssertUnwindSafe(|| {
                        render_job(job, &prepared, &pool, &tick)
                    }))
                    .unwrap_or_else(|_| {
                        Err("the render panicked (a bug in glint: please report it)".into())
                    });
                    let seconds = job_start.elapsed().as_secs_f64();
                    progress.finish_job(job, result.as_ref().map(|_| ()).map_err(|e| e.as_str()));
                    match result {
                        Ok(stats) => report(job, JobStatus::Rendered, seconds, Some(stats), None),
                        Err(e) => report(job, JobStatus::Failed, seconds, None, Some(e)),
                    }
                })
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
        seconds: start.elapsed().as_secs_f64(),
        load_seconds,
        jobs: reports,
    })
}

/// Jobs grouped by (canonical scene, backend, scene index, animation time), groups in order
/// of first appearance: jobs share a load only if they load the same scene at the same time.
fn groups<'a>(jobs: &[&'a Job]) -> Vec<Vec<&'a Job>> {
    type Key = (PathBuf, BackendKind, Option<usize>, Option<u32>);
    let mut keys: Vec<Key> = Vec::new();
    let mut groups: Vec<Vec<&Job>> = Vec::new();
    for &job in jobs {
        let path = std::fs::canonicalize(job.scene()).unwrap_or_else(|_| job.scene().into());
        let key = (
            path,
            job.args.backend,
            job.args.scene_index,
            job.args.time.map(f32::to_bits),
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
    let output = job.output();
    if let Some(folder) = output.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(folder).map_err(|e| {
            format!(
                "cannot create the output folder {}: {e}; fix the job's output path",
                folder.display()
            )
        })?;
    }
    let quiet = |_: String| {};
    let in_scene = |e: render::JobError| format!("{}: {e}", job.scene().display());
    let render_job = job.to_job().map_err(in_scene)?;
    // `run` names the scene in its errors already.
    let done = render::job::run(&render_job, prepared, Some(pool), Some(tick), &quiet)
        .map_err(|e| e.to_string())?;
    Ok(done.stats)
}

/// Whether the job's output exists and is complete (see the module documentation).
pub fn output_is_complete(job: &Job) -> bool {
    let path = job.output();
    let Ok(meta) = std::fs::metadata(path) else {
        return false;
    };
    if !meta.is_file() || meta.len() == 0 {
        return false;
    }
    let size = match crate::output::OutputFormat::from_path(path) {
        Ok(crate::output::OutputFormat::Png) => image::open(path)
            .ok()
            .map(|image| (image.width(), image.height())),
        Ok(crate::output::OutputFormat::Exr) => exr::prelude::read_all_flat_layers_from_file(path)
            .ok()
            .and_then(|image| {
                image
                    .layer_data
                    .first()
                    .map(|layer| (layer.size.0 as u32, layer.size.1 as u32))
            }),
        Err(_) => None,
    };
    let Some((width, height)) = size else {
        return false;
    };
    job.args.width.is_none_or(|w| w == width) && job.args.height.is_none_or(|h| h == height)
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
                let width = j.args.width.unwrap_or(DEFAULT_WIDTH) as u64;
                let height = j
                    .args
                    .height
                    .unwrap_or((width as f32 / DEFAULT_ASPECT).round() as u32)
                    as u64;
                (width * height * j.args.spp as u64).max(1)
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
        if let Some(&p) = self.positions.get(&job.index) {
            let before = self.reported[p].swap(self.estimates[p], Ordering::Relaxed);
            self.bar.inc(self.estimates[p].saturating_sub(before));
        }
        self.finished.fetch_add(1, Ordering::Relaxed);
        let line = match result {
            Ok(()) if self.quiet => None,
            Ok(()) => Some(format!(
                "job {} ({}): wrote {}",
                job.index,
                job.origin,
                job.output().display()
            )),
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
