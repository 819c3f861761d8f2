//! `glint render`.

use super::CliError;

/// Arguments of `glint render`.
#[derive(clap::Args, Debug)]
pub struct RenderArgs {}

/// Runs `glint render`.
pub fn run(_args: RenderArgs) -> Result<(), CliError> {
    Err(CliError("render is not implemented yet".into()))
}
