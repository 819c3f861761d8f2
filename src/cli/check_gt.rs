//! `glint check-gt`: checks an output's ground truth against itself and its sidecar
//! ([`crate::gt_check`]).

use super::CliError;
use crate::gt_check::{self, GroundTruthFile};
use std::path::PathBuf;

/// Arguments of `glint check-gt`.
#[derive(clap::Args, Debug, Clone)]
pub struct CheckGtArgs {
    /// An EXR rendered with --sidecar and --aov z,position (and flow for --next).
    pub output: PathBuf,
    /// The next frame's EXR (with --aov flow_backward): checks the forward flow against it.
    #[arg(long, value_name = "NEXT.exr")]
    pub next: Option<PathBuf>,
    /// Largest accepted reprojection error, relative to the scene's scale in the image.
    #[arg(long, default_value_t = 1e-4, value_parser = super::values::tolerance)]
    pub tolerance: f64,
    /// Largest accepted forward-backward flow error, pixels.
    #[arg(long, default_value_t = 0.05, value_parser = super::values::tolerance)]
    pub flow_tolerance: f64,
}

/// Runs `glint check-gt`: prints each check's largest disagreement; fails if one is over its
/// tolerance.
pub fn run(args: CheckGtArgs) -> Result<(), CliError> {
    let file = GroundTruthFile::read(&args.output).map_err(CliError::from_display)?;
    let mut failures = Vec::new();
    let reprojection = gt_check::reprojection(&file).map_err(CliError::from_display)?;
    println!(
        "reprojection: largest error {:.3e} (relative to the scene's scale) at pixel {:?}; {} pixels compared, {} invalid",
        reprojection.largest, reprojection.at, reprojection.compared, reprojection.skipped
    );
    if reprojection.exceeds(args.tolerance) {
        failures.push(format!(
            "reprojection error {:.3e} exceeds --tolerance {:.1e}",
            reprojection.largest, args.tolerance
        ));
    }
    if let Some(next) = &args.next {
        let next = GroundTruthFile::read(next).map_err(CliError::from_display)?;
        let flow = gt_check::flow_round_trip(&file, &next).map_err(CliError::from_display)?;
        println!(
            "flow: largest forward-backward error {:.3e} px at pixel {:?}; {} pixels compared, {} left out (invalid or at an edge)",
            flow.largest, flow.at, flow.compared, flow.skipped
        );
        if flow.exceeds(args.flow_tolerance) {
            failures.push(format!(
                "flow error {:.3e} px exceeds --flow-tolerance {}",
                flow.largest, args.flow_tolerance
            ));
        }
    }
    if failures.is_empty() {
        println!("{}: consistent", args.output.display());
        Ok(())
    } else {
        Err(CliError::Usage(format!(
            "{}: {}",
            args.output.display(),
            failures.join("; ")
        )))
    }
}
