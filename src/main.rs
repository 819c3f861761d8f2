//! The `glint` command line: parses arguments, calls the library, reports.

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// glint: a native CPU renderer for glTF 2.0 scenes.
#[derive(Parser)]
#[command(name = "glint", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a glTF scene (or the built-in demo scene) to PNG or EXR.
    Render(glint::cli::render::RenderArgs),
    /// Measure ray throughput and build times.
    #[command(subcommand)]
    Bench(glint::cli::bench::BenchCommand),
    /// Render the jobs of a TOML job file, resumably, optionally one shard of them.
    Batch(glint::cli::batch::BatchArgs),
    /// Merge partial EXRs (render --sample-range/--shard) into one image.
    Merge(glint::cli::merge::MergeArgs),
    /// Measure error against a reference as samples grow, per backend, sampler and filter.
    Converge(glint::cli::converge::ConvergeArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => glint::cli::render::run(args),
        Command::Bench(cmd) => glint::cli::bench::run(cmd),
        Command::Batch(args) => glint::cli::batch::run(args),
        Command::Merge(args) => glint::cli::merge::run(args),
        Command::Converge(args) => glint::cli::converge::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("glint: {err}");
            ExitCode::FAILURE
        }
    }
}
