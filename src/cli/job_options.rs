//! `glint render`'s options as the keys of batch job files: [`RenderOptions`] hands the clap
//! definition of [`RenderArgs`] to `glint batch` ([`OptionParser`]), which turns each job table
//! into long options and lets it parse them. Batch, a layer below the command line, knows no
//! clap; the two spellings of a render cannot drift.

use super::render_args::RenderArgs;
use crate::batch::jobs::{OptionKind, OptionParser};
use clap::{CommandFactory, Parser};
use std::path::Path;

/// `glint render`'s options, parsed from a job's argument list.
#[derive(Parser)]
#[command(no_binary_name = true, disable_help_flag = true)]
struct JobCli {
    #[command(flatten)]
    args: RenderArgs,
}

/// The render options of job files: `glint render`'s, through its clap definition.
#[derive(Clone, Copy, Debug, Default)]
pub struct RenderOptions;

impl OptionParser for RenderOptions {
    fn kind(&self, name: &str) -> Option<OptionKind> {
        let command = JobCli::command();
        let arg = command
            .get_arguments()
            .find(|a| a.get_long() == Some(name))?;
        Some(match arg.get_action() {
            clap::ArgAction::Append => OptionKind::List,
            action if action.takes_values() => OptionKind::Value,
            _ => OptionKind::Flag,
        })
    }

    fn names(&self) -> Vec<String> {
        JobCli::command()
            .get_arguments()
            .filter_map(|a| a.get_long())
            .map(str::to_string)
            .collect()
    }

    fn parse(&self, scene: Option<&Path>, args: &[String]) -> Result<crate::job::Job, String> {
        let mut argv: Vec<std::ffi::OsString> = args.iter().map(Into::into).collect();
        if let Some(scene) = scene {
            // After `--`, so that a scene whose name starts with `-` is still the scene.
            argv.extend(["--".into(), scene.as_os_str().to_owned()]);
        }
        let cli = JobCli::try_parse_from(&argv).map_err(|e| clap_message(&e))?;
        cli.args.to_job().map_err(|e| e.to_string())
    }
}

/// A clap error in one line: its first line without the `error: ` prefix, and the list of
/// possible values where clap gives one.
fn clap_message(e: &clap::Error) -> String {
    let text = e.to_string();
    let mut lines = text.lines();
    let first = lines.next().unwrap_or_default();
    let mut message = first.strip_prefix("error: ").unwrap_or(first).to_string();
    if let Some(values) = lines
        .map(str::trim)
        .find(|l| l.starts_with("[possible values"))
    {
        message.push(' ');
        message.push_str(values);
    }
    message
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_are_classified_as_the_command_line_takes_them() {
        let options = RenderOptions;
        assert_eq!(options.kind("photometric"), Some(OptionKind::Flag));
        assert_eq!(options.kind("spp"), Some(OptionKind::Value));
        assert_eq!(options.kind("light"), Some(OptionKind::List));
        assert_eq!(options.kind("aov"), Some(OptionKind::List));
        assert_eq!(options.kind("speed"), None);
        assert!(options.names().iter().any(|n| n == "max-depth"));
    }

    #[test]
    fn a_job_parses_to_the_render_the_command_line_would_run() {
        let args: Vec<String> = ["--spp", "4", "--integrator", "direct", "-o", "a.exr"]
            .map(String::from)
            .to_vec();
        let job = RenderOptions
            .parse(Some(Path::new("-scene.glb")), &args)
            .unwrap();
        assert_eq!(job.settings.spp, 4);
        assert_eq!(job.settings.integrator, crate::render::Integrator::Direct);
        assert_eq!(
            job.scene,
            crate::scene::SceneSource::File("-scene.glb".into())
        );
        let bad = RenderOptions
            .parse(None, &["--integrator".into(), "bogus".into()])
            .unwrap_err();
        assert!(
            bad.contains("bogus") && bad.contains("[possible values: path, direct]"),
            "{bad}"
        );
        let background = RenderOptions
            .parse(None, &["--background".into(), "1,2".into()])
            .unwrap_err();
        assert!(background.contains("--background"), "{background}");
    }
}
