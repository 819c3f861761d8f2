//! `glint bench`.

use super::CliError;

/// Benchmarks.
#[derive(clap::Subcommand, Debug)]
pub enum BenchCommand {
    /// Ray throughput and acceleration-structure build time of both backends.
    Rays {},
    /// The renderer's end-to-end ray rate next to the raw backend rate on the same rays, and
    /// its scaling from 1 thread to all.
    Render(super::bench_render::KernelBenchArgs),
}

/// Runs `glint bench`.
pub fn run(cmd: BenchCommand) -> Result<(), CliError> {
    if let BenchCommand::Render(args) = cmd {
        return super::bench_render::run(args);
    }
    Err(CliError("bench is not implemented yet".into()))
}
