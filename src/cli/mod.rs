//! The subcommands of the `glint` binary, each in its own module with its clap arguments.
//! They live in the library so that tests can drive them without spawning processes. This is
//! the only layer that knows clap: [`render_args`] is `glint render`'s spelling of a
//! [`crate::job::Job`], and [`job_options`] lends it to batch job files.

pub mod batch;
#[cfg(feature = "bench")]
pub mod bench;
pub mod check_gt;
pub mod converge;
pub mod info;
pub mod job_options;
pub mod merge;
pub mod render;
pub mod render_args;
pub mod values;

/// glint: a native CPU renderer for glTF 2.0 scenes.
#[derive(clap::Parser)]
#[command(name = "glint", version, about)]
pub struct Cli {
    /// The subcommand.
    #[command(subcommand)]
    pub command: Command,
    /// Embree's kernels: native (Embree picks the widest this CPU runs), or sse2, sse4.2,
    /// avx, avx2, avx512 to pin them. Pinned kernels give the same images on every CPU that
    /// has them (sse4.2: every x86-64-v2 CPU). Default: $GLINT_EMBREE_ISA, else native.
    #[arg(long, global = true, value_name = "ISA")]
    pub embree_isa: Option<crate::accel::EmbreeIsa>,
}

/// A subcommand of `glint`.
// One value per process, parsed once: boxing `render`'s options would save nothing.
#[allow(clippy::large_enum_variant)]
#[derive(clap::Subcommand)]
pub enum Command {
    /// Render a glTF scene (or the built-in demo scene) to PNG or EXR.
    // Boxed: `glint render`'s many options would make every `Command` as large.
    Render(Box<render::RenderArgs>),
    /// Measure ray throughput and build times.
    #[cfg(feature = "bench")]
    #[command(subcommand)]
    Bench(bench::BenchCommand),
    /// Render the jobs of a TOML job file, resumably, optionally one shard of them.
    Batch(batch::BatchArgs),
    /// Merge partial EXRs (render --sample-range/--shard) into one image.
    Merge(merge::MergeArgs),
    /// Measure error against a reference as samples grow, per backend, sampler and filter.
    Converge(converge::ConvergeArgs),
    /// Check an output's ground truth (z, position, flow) against its camera sidecar.
    #[command(name = "check-gt")]
    CheckGt(check_gt::CheckGtArgs),
    /// List what a glTF file holds: scenes, cameras, lights, animations, variants, extensions.
    Info(info::InfoArgs),
}

impl Command {
    /// Runs the subcommand.
    pub fn run(self) -> Result<(), CliError> {
        match self {
            Command::Render(args) => render::run(*args),
            #[cfg(feature = "bench")]
            Command::Bench(cmd) => bench::run(cmd),
            Command::Batch(args) => batch::run(args),
            Command::Merge(args) => merge::run(args),
            Command::Converge(args) => converge::run(args),
            Command::CheckGt(args) => check_gt::run(args),
            Command::Info(args) => info::run(args),
        }
    }

    /// What the subcommand does, naming its input file where it has one, for the line that
    /// reports an internal error: "rendering scene.gltf".
    pub fn doing(&self) -> String {
        let scene = |path: &Option<std::path::PathBuf>| {
            path.as_ref()
                .map_or_else(|| "the demo scene".to_string(), |p| p.display().to_string())
        };
        match self {
            Command::Render(args) => format!("rendering {}", scene(&args.scene)),
            #[cfg(feature = "bench")]
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
            Command::CheckGt(args) => format!("checking {}", args.output.display()),
            Command::Info(args) => format!("inspecting {}", args.file.display()),
        }
    }
}

/// An error a subcommand reports to the user: typed where the library's error is, one line
/// of text where the command line itself found the problem. `main` prints it.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// A problem found by the command line, already carrying its context.
    #[error("{0}")]
    Usage(String),
    /// A render job failed.
    #[error(transparent)]
    Job(#[from] crate::job::JobError),
    /// A job file is unusable.
    #[error(transparent)]
    JobFile(#[from] crate::batch::JobFileError),
    /// A render failed.
    #[error(transparent)]
    Render(#[from] crate::render::RenderError),
    /// An output could not be written.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
}

impl CliError {
    /// Wraps any displayable error as a one-line message.
    pub fn from_display(err: impl std::fmt::Display) -> Self {
        CliError::Usage(err.to_string())
    }
}
