//! The subcommands of the `glint` binary, each in its own module with its clap arguments.
//! They live in the library so that tests can drive them without spawning processes.

pub mod batch;
pub mod bench;
pub mod converge;
pub mod merge;
pub mod render;

/// An error a subcommand reports to the user: typed where the library's error is, one line
/// of text where the command line itself found the problem. `main` prints it.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// A problem found by the command line, already carrying its context.
    #[error("{0}")]
    Usage(String),
    /// A render job failed.
    #[error(transparent)]
    Job(#[from] crate::render::JobError),
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
