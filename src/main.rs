//! The `glint` command line: parses arguments, calls the library, reports.
//!
//! Exit status: 0 on success; 1 for an error the user can fix (a bad file, option or job; a
//! batch with a failed job); [`INTERNAL_ERROR_EXIT`] (70) for an internal error, a panic
//! caught at the subcommand's boundary and reported in one line (see [`glint::panics`]).

use clap::Parser;
use glint::cli::Cli;
use glint::panics::{self, INTERNAL_ERROR_EXIT};
use std::process::ExitCode;

fn main() -> ExitCode {
    // First: `batch --force` tells another batch's fresh outputs by this moment.
    glint::batch::claim::mark_process_start();
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
