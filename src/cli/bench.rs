//! `glint bench`.

use super::CliError;

/// Benchmarks.
#[derive(clap::Subcommand, Debug)]
pub enum BenchCommand {
    /// Ray throughput and acceleration-structure build time of both backends.
    Rays {},
}

/// Runs `glint bench`.
pub fn run(_cmd: BenchCommand) -> Result<(), CliError> {
    Err(CliError("bench is not implemented yet".into()))
}
