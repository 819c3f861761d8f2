//! `glint merge`: combine the partial EXRs of a split render into the final image.

use super::CliError;
use crate::output::partial::read_partial_exr;
use crate::output::{OutputFormat, PngOptions, write_exr, write_png};
use crate::render::partial;
use std::path::PathBuf;

/// Arguments of `glint merge`.
#[derive(clap::Args, Debug, Clone)]
pub struct MergeArgs {
    /// Partial EXRs from `glint render --sample-range` or `--shard`, in any order.
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// The merged image (.exr, linear; or .png, sRGB at exposure 0).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Print nothing but errors.
    #[arg(long, short)]
    pub quiet: bool,
}

/// Runs `glint merge`.
pub fn run(args: MergeArgs) -> Result<(), CliError> {
    let format = OutputFormat::from_path(&args.output).map_err(CliError::from_display)?;
    let parts = args
        .parts
        .iter()
        .map(|p| read_partial_exr(p))
        .collect::<Result<Vec<_>, _>>()
        .map_err(CliError::from_display)?;
    let (image, aovs) = partial::merge(&parts).map_err(|e| {
        let names: Vec<String> = args.parts.iter().map(|p| p.display().to_string()).collect();
        CliError::Usage(format!("merging {}: {e}", names.join(", ")))
    })?;
    match format {
        OutputFormat::Exr => write_exr(&args.output, &image, &aovs),
        OutputFormat::Png => write_png(&args.output, &image, PngOptions::default()),
    }
    .map_err(CliError::from_display)?;
    if !args.quiet {
        eprintln!(
            "wrote {} ({}×{}, {} parts, {} spp)",
            args.output.display(),
            image.width,
            image.height,
            parts.len(),
            parts[0].spp
        );
    }
    Ok(())
}
