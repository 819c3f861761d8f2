//! Batch rendering: many jobs in one process, resumable, and split over machines by an
//! existing scheduler.
//!
//! - [`jobs`]: the TOML job file, read into [`Job`]s (options as `glint render` takes them).
//! - [`sweep`]: `[[sweep]]` tables (value lists, camera orbits) expanded into jobs.
//! - [`shard`]: `--shard I/N`, the deterministic split of jobs (or samples) over machines.
//! - [`runner`]: runs a shard's jobs: shared scene loads, one thread pool, skips complete
//!   outputs, isolates failures.
//! - [`report`]: the per-job JSON report.
//! - [`coco`]: the batch's COCO detection file (`--coco`), gathered from every job's
//!   per-instance annotations.
//! - [`claim`]: one lock file per job, so concurrent batches never render a job twice.
//! - [`paths`]: outputs confined to an output root, output folders probed before rendering.

pub mod claim;
pub mod coco;
pub mod jobs;
pub mod paths;
pub mod report;
pub mod runner;
pub mod shard;
pub mod sweep;

pub use jobs::{CameraOverride, Job, JobFileError};
pub use report::{BatchReport, JobReport, JobStatus};
pub use runner::{BatchOptions, run};
pub use shard::{Shard, ShardSpec};
