//! `glint merge`: combine the partial EXRs of a split render into the final image.

use super::CliError;
use crate::output::fingerprint::SceneTag;
use crate::output::partial::read_partial_exr_tagged;
use crate::output::{OutputFormat, PngOptions, write_exr, write_exr_annotated, write_png};
use crate::render::partial;
use crate::render::partial::PartialImage;
use std::path::{Path, PathBuf};

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
    // The merged image may replace none of its parts; parts must be regular files.
    let mut plan = crate::output::OutputPlan::new();
    for (k, part) in args.parts.iter().enumerate() {
        plan.input(part, format!("a part (number {})", k + 1))
            .map_err(|e| CliError::Usage(e.to_string()))?;
    }
    plan.output(&args.output, "the merged image")
        .map_err(|e| CliError::Usage(e.to_string()))?;
    let tagged = args
        .parts
        .iter()
        .map(|p| read_partial_exr_tagged(p))
        .collect::<Result<Vec<_>, _>>()
        .map_err(CliError::from_display)?;
    check_same_scene(&args.parts, &tagged, &|line| {
        if !args.quiet {
            eprintln!("{line}");
        }
    })?;
    // The model every tagged part names (they agree: check_same_scene refused otherwise).
    let brdf = tagged
        .iter()
        .find_map(|(_, tag)| tag.as_ref().and_then(|t| t.brdf.clone()));
    let parts: Vec<_> = tagged.into_iter().map(|(part, _)| part).collect();
    let (image, aovs) = partial::merge(&parts).map_err(|e| {
        let names: Vec<String> = args.parts.iter().map(|p| p.display().to_string()).collect();
        CliError::Usage(format!("merging {}: {e}", names.join(", ")))
    })?;
    match format {
        OutputFormat::Exr => match &brdf {
            Some(brdf) => write_exr_annotated(&args.output, &image, &aovs, &[("glint.brdf", brdf)]),
            None => write_exr(&args.output, &image, &aovs),
        },
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

/// Refuses parts whose scene fingerprints differ, naming both parts and their scenes. A part
/// without a fingerprint (written by an older glint) cannot be checked: a note says so.
fn check_same_scene(
    paths: &[PathBuf],
    parts: &[(PartialImage, Option<SceneTag>)],
    say: &dyn Fn(String),
) -> Result<(), CliError> {
    let mut first: Option<(&Path, &SceneTag)> = None;
    for (path, (_, tag)) in paths.iter().zip(parts) {
        let Some(tag) = tag else {
            say(format!(
                "note: {} carries no scene fingerprint (written by an older glint); it cannot \
                 be checked against the other parts' scene",
                path.display()
            ));
            continue;
        };
        match first {
            None => first = Some((path, tag)),
            Some((first_path, first_tag)) if first_tag.fingerprint != tag.fingerprint => {
                let what = if first_tag.scene == tag.scene {
                    "the same scene file name but different contents, scene, time, size or camera"
                } else {
                    "different scenes"
                };
                return Err(CliError::Usage(format!(
                    "{} was rendered from {} (fingerprint {}) but {} from {} (fingerprint {}): \
                     {what}; merge only parts of one render command that differ in \
                     --sample-range or --shard",
                    path.display(),
                    tag.scene,
                    tag.fingerprint,
                    first_path.display(),
                    first_tag.scene,
                    first_tag.fingerprint
                )));
            }
            Some((first_path, first_tag)) => {
                if let (Some(a), Some(b)) = (&first_tag.brdf, &tag.brdf)
                    && a != b
                {
                    return Err(CliError::Usage(format!(
                        "{} was rendered with --brdf {b} but {} with --brdf {a}: merge only \
                         parts of one render command that differ in --sample-range or --shard",
                        path.display(),
                        first_path.display(),
                    )));
                }
            }
        }
    }
    note_kernels(paths, parts, say);
    Ok(())
}

/// Notes parts rendered by different ray-query kernels (another Embree version, instruction
/// set or backend): the merged image is then not bit-identical to a render on one machine,
/// though it agrees with one within rounding (see docs/embree4.md, "What is bit-identical").
fn note_kernels(
    paths: &[PathBuf],
    parts: &[(PartialImage, Option<SceneTag>)],
    say: &dyn Fn(String),
) {
    let mut seen: Vec<(&str, &Path)> = Vec::new();
    for (path, (_, tag)) in paths.iter().zip(parts) {
        if let Some(kernels) = tag.as_ref().and_then(|t| t.kernels.as_deref())
            && !seen.iter().any(|(k, _)| *k == kernels)
        {
            seen.push((kernels, path));
        }
    }
    if seen.len() > 1 {
        let list: Vec<String> = seen
            .iter()
            .map(|(k, p)| format!("{k} ({})", p.display()))
            .collect();
        say(format!(
            "note: the parts were rendered by different ray-query kernels: {}; the merged image \
             agrees with a single-machine render within rounding, not bit for bit (pin them \
             with --embree-isa sse4.2 or use --backend bvh for byte-identical parts)",
            list.join(", ")
        ));
    }
}
