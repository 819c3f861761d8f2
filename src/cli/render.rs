//! `glint render`: the command line's spelling of a [`crate::job::Job`]
//! ([`RenderArgs::to_job`]), run by [`job::run`], which completes the scene, renders it and
//! writes a PNG or EXR.

use super::CliError;
use crate::job::{self, JobError, PreparedScene, RunOptions};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

pub use super::render_args::{AovName, DEMO_OUTPUT, RenderArgs, output_path};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Renders shorter than this show no progress bar.
const PROGRESS_DELAY: Duration = Duration::from_secs(1);

/// Runs `glint render`: builds the job, checks it, prepares the scene and runs the job.
pub fn run(args: RenderArgs) -> Result<(), CliError> {
    let say = |line: String| {
        if !args.quiet {
            eprintln!("{line}");
        }
    };
    let job = args.to_job()?;
    // Every file this render writes and reads, the scene's buffers and images included.
    job.plan_files(&mut crate::output::OutputPlan::new(), "")
        .map_err(|e| CliError::Usage(e.to_string()))?;
    for note in job.check()? {
        say(note);
    }
    let scene = job
        .scene
        .load_with(&job.selection, &job.load_options)
        .map_err(JobError::from)?;
    // Checked before the (possibly long) build of the ray-query structure.
    job.check_camera(&scene)?;
    let prepared = PreparedScene::new(scene, job.scene.label(), job.backend)?;
    let bar = DelayedProgress::new(args.quiet);
    let report = |done: usize, total: usize| bar.update(done, total);
    let options = RunOptions {
        progress: Some(&report),
        say: Some(&say),
        ..RunOptions::default()
    };
    let result = job::run(&job, &prepared, options);
    bar.finish();
    let done = result?;
    let denoised = done
        .denoise_seconds
        .map(|s| format!(", denoised (Open Image Denoise, {s:.2} s)"))
        .unwrap_or_default();
    say(format!(
        "wrote {} ({}×{}, {} spp, {}, {} sampler, {} filter{denoised}): {}{}",
        output_path(&args).display(),
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
