//! One set of defaults: `glint render SCENE -o OUT` (parsed by the command line's own clap
//! definition, as the binary parses it) is `Job::default()` with that scene and output, and
//! the Python package's keyword arguments start from `Job::default()` (its crate's unit test,
//! `no_keyword_arguments_give_the_default_job`, checks that no keyword gives exactly it).
//! Together: the command line, the library and Python render the same job by default.

use clap::Parser;
use glint::cli::{Cli, Command};
use glint::job::{Job, OutputSpec, SceneSource};
use glint::render::Integrator;

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
