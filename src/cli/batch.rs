//! `glint batch`: render the jobs of a TOML job file (or one shard of them) in one process.

use super::CliError;
use super::job_options::RenderOptions;
use crate::batch::{self, BatchOptions, Shard, ShardSpec};
use std::path::PathBuf;

/// Arguments of `glint batch`.
#[derive(clap::Args, Debug, Clone)]
pub struct BatchArgs {
    /// The job file (TOML; format in docs/batch.md).
    pub jobs: PathBuf,
    /// Write a JSON report (status, seconds, rays, output, error of each job) here.
    #[arg(long, value_name = "REPORT.json")]
    pub report: Option<PathBuf>,
    /// Run only the jobs whose index ≡ I (mod N), I from 0 (for Slurm arrays, Kubernetes
    /// Indexed Jobs, GNU parallel). `auto` reads the task index from the environment:
    /// SLURM_ARRAY_TASK_ID (with SLURM_ARRAY_TASK_COUNT, or MIN/MAX) or JOB_COMPLETION_INDEX
    /// (with --shard-count or GLINT_SHARD_COUNT).
    #[arg(long, value_name = "I/N|auto")]
    pub shard: Option<ShardSpec>,
    /// The number of shards for `--shard auto` under a Kubernetes Indexed Job (its
    /// `completions`); overrides GLINT_SHARD_COUNT.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub shard_count: Option<u32>,
    /// Outputs must resolve inside this folder (after `..` and links); default: the job
    /// file's `output_root`, else the job file's folder.
    #[arg(long, value_name = "DIR")]
    pub output_root: Option<PathBuf>,
    /// Render jobs whose output already exists (by default they are skipped); never one that
    /// another batch running beside this one wrote meanwhile.
    #[arg(long)]
    pub force: bool,
    /// On file systems without flock: take over claims of other hosts not touched for this
    /// many seconds (at least 180; by default never). See docs/batch.md.
    #[arg(long, value_name = "SECONDS", value_parser = clap::value_parser!(u64).range(180..))]
    pub steal_claims: Option<u64>,
    /// Worker threads shared by all jobs; 0 uses every core (at most 1024).
    #[arg(long, default_value_t = 0, value_parser = super::values::threads)]
    pub threads: usize,
    /// List the jobs of the shard (index, origin, output) and render nothing.
    #[arg(long)]
    pub list: bool,
    /// No progress bar and no per-job lines (failures still print).
    #[arg(long, short)]
    pub quiet: bool,
    /// Gather every job's per-instance annotations into one COCO detection file (turns on
    /// --annotations for every job; see docs/ground-truth.md).
    #[arg(long, value_name = "FILE.json")]
    pub coco: Option<PathBuf>,
}

/// Runs `glint batch`. Fails (non-zero exit) when the job file is unusable or any job failed.
pub fn run(args: BatchArgs) -> Result<(), CliError> {
    let file =
        batch::jobs::load_file(&args.jobs, &RenderOptions).map_err(CliError::from_display)?;
    let mut jobs = file.jobs;
    let mut plan = file.plan;
    if args.coco.is_some() {
        for job in &mut jobs {
            job.render.settings.aovs.annotations = true;
        }
        // Every job now writes a sidecar too.
        plan = batch::jobs::plan_jobs(&jobs, &args.jobs).map_err(|(origin, message)| {
            CliError::Usage(format!("{}: {origin}: {message}", args.jobs.display()))
        })?;
    }
    // The batch's own files join the plan before anything renders: neither may replace an
    // input, an output of a job or each other.
    if let Some(report) = &args.report {
        plan.output(report, "the report (--report)")
            .map_err(|e| CliError::Usage(e.to_string()))?;
    }
    if let Some(coco) = &args.coco {
        plan.output(coco, "the COCO file (--coco)")
            .map_err(|e| CliError::Usage(e.to_string()))?;
    }
    let shard = match args.shard {
        None => Shard::ALL,
        Some(ShardSpec::Fixed(shard)) => shard,
        Some(ShardSpec::Auto) => {
            let (shard, line) =
                batch::shard::from_environment(|name| std::env::var(name).ok(), args.shard_count)
                    .map_err(CliError::Usage)?;
            // On stderr even with -q: a farm's log should say which part this task took.
            eprintln!("{line}");
            shard
        }
    };
    if args.shard_count.is_some() && args.shard != Some(ShardSpec::Auto) {
        return Err(CliError::Usage(
            "--shard-count applies to --shard auto only; with --shard I/N, N is the count".into(),
        ));
    }
    if args.list {
        use std::io::Write;
        let mut out = std::io::stdout().lock();
        for job in jobs.iter().filter(|j| shard.takes(j.index)) {
            // A closed pipe (`| head`) ends the listing quietly.
            if writeln!(
                out,
                "{}\t{}\t{}",
                job.index,
                job.origin,
                job.output().display()
            )
            .is_err()
            {
                break;
            }
        }
        return Ok(());
    }
    if let Some(report) = &args.report {
        let folder = report.parent().filter(|p| !p.as_os_str().is_empty());
        if folder.is_some_and(|f| !f.is_dir()) {
            return Err(CliError::Usage(format!(
                "cannot write the report {}: its folder does not exist; create it first",
                report.display()
            )));
        }
    }
    let options = BatchOptions {
        output_root: args.output_root.clone().or(file.output_root),
        shard,
        force: args.force,
        claims: crate::batch::claim::ClaimPolicy {
            steal_after: args.steal_claims.map(std::time::Duration::from_secs),
            ..Default::default()
        },
        threads: args.threads,
        quiet: args.quiet,
    };
    let report = batch::run(&jobs, &args.jobs, &options).map_err(CliError::from_display)?;
    if let Some(path) = &args.report {
        report.write_json(path).map_err(CliError::from_display)?;
    }
    if let Some(coco_path) = &args.coco
        && report.all_succeeded()
    {
        // Jobs another batch claimed are that batch's to finish: wait for them (see
        // docs/batch.md, "Concurrent batches and --coco").
        let busy: Vec<&batch::Job> = report
            .jobs
            .iter()
            .filter(|r| r.status == batch::JobStatus::Busy)
            .filter_map(|r| jobs.iter().find(|j| j.index == r.index))
            .collect();
        if !busy.is_empty() && !args.quiet {
            eprintln!(
                "--coco: waiting for {} jobs that another glint batch is rendering",
                busy.len()
            );
        }
        batch::coco::wait_for_others(&busy, &options.claims, batch::coco::COCO_WAIT)
            .map_err(CliError::Usage)?;
        let images: Vec<PathBuf> = report.jobs.iter().map(|j| j.output.clone()).collect();
        let coco = batch::coco::gather(&images, coco_path).map_err(CliError::from_display)?;
        batch::coco::write_coco(coco_path, &coco).map_err(CliError::from_display)?;
        if !args.quiet {
            eprintln!(
                "{}: {} images, {} categories, {} annotations",
                coco_path.display(),
                coco.images.len(),
                coco.categories.len(),
                coco.annotations.len()
            );
        }
    }
    println!(
        "{}: shard {} ({} of {} jobs): {} rendered, {} skipped, {} failed{} in {:.2} s",
        args.jobs.display(),
        report.shard,
        report.jobs.len(),
        report.jobs_in_file,
        report.rendered,
        report.skipped,
        report.failed,
        if report.busy > 0 {
            format!(", {} left to another batch that claimed them", report.busy)
        } else {
            String::new()
        },
        report.seconds
    );
    if report.all_succeeded() {
        Ok(())
    } else {
        Err(CliError::Usage(format!(
            "{} of {} jobs failed{}",
            report.failed,
            report.jobs.len(),
            match &args.report {
                Some(path) => format!("; details in {}", path.display()),
                None => "; the errors are above".to_string(),
            }
        )))
    }
}
