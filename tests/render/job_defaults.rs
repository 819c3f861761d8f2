//! One set of defaults: `glint render SCENE -o OUT` (parsed by the command line's own clap
//! definition, as the binary parses it) is `Job::default()` with that scene and output, and
//! the Python package's keyword arguments start from `Job::default()` (its crate's unit test,
//! `no_keyword_arguments_give_the_default_job`, checks that no keyword gives exactly it).
//! Together: the command line, the library and Python render the same job by default.

use clap::Parser;
use glint::cli::{Cli, Command};
use glint::job::{Job, OutputSpec, SceneSource};
use glint::render::{BrdfModel, Integrator};

fn parsed(args: &[&str]) -> Job {
    let cli = Cli::try_parse_from(args).unwrap_or_else(|e| panic!("{e}"));
    let Command::Render(render) = cli.command else {
        panic!("{args:?} is not a render");
    };
    render.to_job().unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn glint_render_defaults_are_the_default_job() {
    let job = parsed(&["glint", "render", "x.gltf", "-o", "y.png"]);
    let expected = Job {
        scene: SceneSource::File("x.gltf".into()),
        output: Some(OutputSpec {
            path: "y.png".into(),
            ..OutputSpec::default()
        }),
        ..Job::default()
    };
    assert_eq!(job, expected);
    // The path tracer, not the engine's own default (the direct integrator).
    assert_eq!(job.settings.integrator, Integrator::Path);
}

#[test]
fn the_demo_scene_is_the_default_scene() {
    let job = parsed(&["glint", "render"]);
    assert_eq!(job.scene, Job::default().scene);
    let output = job.output.expect("glint render always writes");
    assert_eq!(
        output.path,
        std::path::Path::new(glint::cli::render::DEMO_OUTPUT)
    );
}

/// The energy-compensated BRDF is the default everywhere; `--brdf spec` on the command line
/// and `brdf = "spec"` in a job file (parsed by the same option parser) select Appendix B.
#[test]
fn the_brdf_option_defaults_to_compensated_and_selects_the_spec() {
    assert_eq!(Job::default().settings.brdf, BrdfModel::Compensated);
    let job = parsed(&["glint", "render", "x.gltf", "-o", "y.png"]);
    assert_eq!(job.settings.brdf, BrdfModel::Compensated);
    let job = parsed(&["glint", "render", "x.gltf", "-o", "y.png", "--brdf", "spec"]);
    assert_eq!(job.settings.brdf, BrdfModel::Spec);
    let cli = Cli::try_parse_from(["glint", "render", "--brdf", "multiscatter"]);
    let message = cli.err().expect("an unknown model is refused").to_string();
    assert!(
        message.contains("compensated") && message.contains("spec"),
        "{message}"
    );
    let jobs = glint::batch::jobs::parse(
        "[[job]]\nscene = \"a.glb\"\noutput = \"a.png\"\nbrdf = \"spec\"\n\n[[job]]\nscene = \"b.glb\"\noutput = \"b.png\"",
        std::path::Path::new("/somewhere/jobs.toml"),
        &glint::cli::job_options::RenderOptions,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(jobs[0].render.settings.brdf, BrdfModel::Spec);
    assert_eq!(jobs[1].render.settings.brdf, BrdfModel::Compensated);
}
