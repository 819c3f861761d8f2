//! The subcommands of the `glint` binary, each in its own module with its clap arguments.
//! They live in the library so that tests can drive them without spawning processes.

pub mod batch;
pub mod bench;
pub mod bench_render;
pub mod converge;
pub mod merge;
pub mod render;

/// An error a subcommand reports to the user: one line, already carrying its context.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct CliError(pub String);

impl CliError {
    /// Wraps any displayable error.
    pub fn from_display(err: impl std::fmt::Display) -> Self {
        CliError(err.to_string())
    }
}
