//! The `glint` command line: parses arguments, calls the library, reports.
//!
//! Exit status: 0 on success; 1 for an error the user can fix (a bad file, option or job; a
//! batch with a failed job); [`INTERNAL_ERROR_EXIT`] (70) for an internal error, a panic
//! caught at the subcommand's boundary and reported in one line (see [`glint::panics`]).

use clap::{Parser, Subcommand};
use glint::panics::{self, INTERNAL_ERROR_EXIT};
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
    panics::install_quiet_hook();
    let cli = Cli::parse();
    if let Some(isa) = cli.embree_isa
        && let Err(why) = glint::accel::kernels::set_process_isa(isa)
    {
        eprintln!("glint: --embree-isa: {why}");
        return ExitCode::FAILURE;
    }
    let doing = cli.command.doing();
    match panics::catch(|| cli.command.run()) {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(err)) => {
            eprintln!("glint: {err}");
            ExitCode::FAILURE
        }
        Err(panic) => {
            eprintln!("glint: {}", panic.report(&doing));
            ExitCode::from(INTERNAL_ERROR_EXIT)
        }
    }
}

impl Command {
    /// Runs the subcommand.
    fn run(self) -> Result<(), glint::cli::CliError> {
        match self {
            Command::Render(args) => glint::cli::render::run(args),
            Command::Bench(cmd) => glint::cli::bench::run(cmd),
            Command::Batch(args) => glint::cli::batch::run(args),
            Command::Merge(args) => glint::cli::merge::run(args),
            Command::Converge(args) => glint::cli::converge::run(args),
        }
    }

    /// What the subcommand does, naming its input file where it has one, for the line that
    /// reports an internal error: "rendering scene.gltf".
    fn doing(&self) -> String {
        let scene = |path: &Option<std::path::PathBuf>| {
            path.as_ref()
                .map_or_else(|| "the demo scene".to_string(), |p| p.display().to_string())
        };
        match self {
            Command::Render(args) => format!("rendering {}", scene(&args.scene)),
            Command::Bench(_) => "benchmarking".to_string(),
            Command::Batch(args) => format!("running the batch {}", args.jobs.display()),
            Command::Merge(args) => {
                let parts: Vec<String> =
                    args.parts.iter().map(|p| p.display().to_string()).collect();
                format!("merging {}", parts.join(", "))
            }
            Command::Converge(args) => {
                format!("measuring the convergence of {}", scene(&args.scene))
            }
        }
    }
}
