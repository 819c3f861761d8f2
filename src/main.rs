//! The `glint` command line: parses arguments, calls the library, reports.

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// glint: a native CPU renderer for glTF 2.0 scenes.
#[derive(Parser)]
#[command(name = "glint", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Embree's kernels: native (Embree picks the widest this CPU runs), or sse2, sse4.2,
    /// avx, avx2, avx512 to pin them. Pinned kernels give the same images on every CPU that
    /// has them (sse4.2: every x86-64-v2 CPU). Default: $GLINT_EMBREE_ISA, else native.
    #[arg(long, global = true, value_name = "ISA")]
    embree_isa: Option<glint::accel::EmbreeIsa>,
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
    if let Some(isa) = cli.embree_isa
        && let Err(why) = glint::accel::kernels::set_process_isa(isa)
    {
        eprintln!("glint: --embree-isa: {why}");
        return ExitCode::FAILURE;
    }
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
