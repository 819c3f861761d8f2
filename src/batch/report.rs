//! The batch report: one entry per job of the shard, written as JSON with `--report`.

use crate::output::{OutputError, write_atomically};
use serde::Serialize;
use std::io::Write;
use std::path::{Path, PathBuf};

/// What happened to a job.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum JobStatus {
    /// Rendered and written.
    Rendered,
    /// Its output already existed, complete; not rendered again (use `--force`).
    Skipped,
    /// Could not be rendered; see the error.
    Failed,
    /// Another live `glint batch` held the job's claim (it renders the job); not rendered
    /// by this run.
    Busy,
}

/// One job's outcome.
#[derive(Clone, Debug, Serialize)]
pub struct JobReport {
    /// Index in the expanded job list (from 0).
    pub index: usize,
    /// Where it comes from in the job file.
    pub origin: String,
    /// The scene file.
    pub scene: PathBuf,
    /// The output file.
    pub output: PathBuf,
    /// What happened.
    pub status: JobStatus,
    /// Wall-clock seconds of the job, including its share of waiting for threads (0 when
    /// skipped; the scene's load is counted in [`BatchReport::load_seconds`]).
    pub seconds: f64,
    /// Rays traced: camera + shadow + reflection.
    pub rays: u64,
    /// Camera rays traced.
    pub camera_rays: u64,
    /// Shadow rays traced.
    pub shadow_rays: u64,
    /// Reflection rays traced.
    pub reflection_rays: u64,
    /// Why it failed, when it did.
    pub error: Option<String>,
}

/// The outcome of one `glint batch` run.
#[derive(Clone, Debug, Serialize)]
pub struct BatchReport {
    /// The job file.
    pub job_file: PathBuf,
    /// The shard run, `I/N`.
    pub shard: String,
    /// Jobs in the whole file (all shards).
    pub jobs_in_file: usize,
    /// Jobs of this shard rendered.
    pub rendered: usize,
    /// Jobs of this shard skipped.
    pub skipped: usize,
    /// Jobs of this shard that failed.
    pub failed: usize,
    /// Jobs of this shard left to another batch process that held their claims.
    pub busy: usize,
    /// Wall-clock seconds of the whole batch.
    pub seconds: f64,
    /// Seconds spent loading scenes and building their ray-query structures.
    pub load_seconds: f64,
    /// Each job of this shard, by index.
    pub jobs: Vec<JobReport>,
}

impl BatchReport {
    /// Whether no job of the shard failed (each was rendered, skipped, or left to another
    /// process that claimed it).
    pub fn all_succeeded(&self) -> bool {
        self.failed == 0
    }

    /// Writes the report as pretty-printed JSON to `path`, atomically.
    pub fn write_json(&self, path: &Path) -> Result<(), OutputError> {
        let io = |source| OutputError::Io {
            path: path.to_path_buf(),
            source,
        };
        let json = serde_json::to_vec_pretty(self).map_err(|e| io(e.into()))?;
        write_atomically(path, |w| {
            w.write_all(&json)
                .and_then(|()| w.write_all(b"\n"))
                .map_err(io)
        })
    }
}
