//! `glint bench`.

use super::CliError;
use crate::accel::{BackendKind, BuildOptions};
use crate::bench::render::{
    kernel_bench, procedural_scene, raw_trace, scene_to_bench_with, thread_scaling,
};
use crate::bench::timing::median_duration;
use crate::bench::{BenchScene, RaysConfig, SceneSize, run_rays};
use crate::procedural::Builtin;
use crate::render::{self, RenderSettings};
use std::path::PathBuf;

/// Benchmarks.
#[derive(clap::Subcommand, Debug)]
pub enum BenchCommand {
    /// Ray throughput and acceleration-structure build time of both backends.
    Rays(RaysArgs),
    /// The renderer's end-to-end ray rate next to the raw backend rate on the same rays, its
    /// kernel specialisation against the general kernel, and its scaling from 1 thread to all.
    Render(KernelBenchArgs),
    /// Build time and memory of many copies of one model: placed (two-level) against baked
    /// into world space, on both backends.
    Instances(InstancesArgs),
}

/// Arguments of `glint bench instances`.
#[derive(clap::Args, Debug)]
pub struct InstancesArgs {
    /// The model: a .gltf/.glb file or a built-in (sphere, terrain, soup).
    #[arg(value_name = "SCENE")]
    pub scene: String,
    /// Copies drawn as placements.
    #[arg(long, default_value_t = 10_000, value_parser = clap::value_parser!(u64).range(1..=(1 << 24)))]
    pub count: u64,
    /// Copies baked into world space for the comparison (their bytes are scaled to --count).
    #[arg(long, default_value_t = 100, value_parser = clap::value_parser!(u64).range(1..=(1 << 24)))]
    pub flat_count: u64,
    /// Print the rows as JSON on stdout (the table goes to stderr).
    #[arg(long)]
    pub json: bool,
    /// Every file the scene refers to must resolve inside this folder.
    #[arg(long, value_name = "DIR")]
    pub asset_root: Option<PathBuf>,
}

/// Arguments of `glint bench rays`.
#[derive(clap::Args, Debug)]
pub struct RaysArgs {
    /// Scenes: built-in names (sphere, terrain, soup; about 1M triangles each) or .gltf/.glb
    /// files. None: every built-in.
    #[arg(value_name = "SCENE")]
    pub scenes: Vec<String>,
    /// Print the report as JSON (every figure) on stdout; the tables then go to stderr.
    #[arg(long)]
    pub json: bool,
    /// Timed runs per figure (queries after one discarded warm-up run). Default 5, fewer for a
    /// figure whose runs exceed a few seconds; 1 with --quick.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub runs: Option<u32>,
    /// Smoke test: built-ins of about 5k triangles, 64×48 rays, one run, no warm-up.
    #[arg(long)]
    pub quick: bool,
    /// The larger thread count measured (the smaller is 1). Default: hardware threads.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub threads: Option<u32>,
    /// Width of the camera-ray image, pixels (default 1024; 64 with --quick).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub width: Option<u32>,
    /// Height of the camera-ray image, pixels (default 768; 48 with --quick).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub height: Option<u32>,
    /// Random rays of the incoherent workload (default 262144; 2048 with --quick).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub random_rays: Option<u32>,
    /// Every file a glTF scene refers to must resolve inside this folder (as for glint
    /// render).
    #[arg(long, value_name = "DIR")]
    pub asset_root: Option<PathBuf>,
}

impl RaysArgs {
    /// The benchmark settings these arguments ask for.
    pub fn config(&self) -> RaysConfig {
        let mut config = if self.quick {
            RaysConfig::quick()
        } else {
            RaysConfig::full()
        };
        if let Some(runs) = self.runs {
            config = config.with_timed_runs(runs as usize);
        }
        if let Some(threads) = self.threads {
            config.threads = threads as usize;
        }
        if let Some(width) = self.width {
            config.width = width;
        }
        if let Some(height) = self.height {
            config.height = height;
        }
        if let Some(random_rays) = self.random_rays {
            config.random_rays = random_rays as usize;
        }
        config
    }

    /// The scenes these arguments name, generated or loaded.
    pub fn scenes(&self) -> Result<Vec<BenchScene>, CliError> {
        let size = if self.quick {
            SceneSize::Quick
        } else {
            SceneSize::Full
        };
        if self.scenes.is_empty() {
            return Ok(BenchScene::all_builtins(size));
        }
        self.scenes
            .iter()
            .map(|arg| {
                BenchScene::from_arg_with(arg, size, &load_options(&self.asset_root))
                    .map_err(CliError::from_display)
            })
            .collect()
    }
}

/// Runs `glint bench`: results on stdout, progress on stderr.
pub fn run(cmd: BenchCommand) -> Result<(), CliError> {
    match cmd {
        BenchCommand::Rays(args) => {
            let config = args.config();
            eprintln!("glint bench rays: preparing scenes");
            let scenes = args.scenes()?;
            let report = run_rays(&scenes, &config, &mut |line| eprintln!("{line}"))
                .map_err(CliError::from_display)?;
            if args.json {
                // The tables still reach a person watching the terminal while stdout goes
                // to a file or a pipe.
                eprintln!("{}", report.to_table());
                println!("{}", report.to_json().map_err(CliError::from_display)?);
            } else {
                println!("{}", report.to_table());
            }
            Ok(())
        }
        BenchCommand::Render(args) => run_render(args),
        BenchCommand::Instances(args) => run_instances(&args),
    }
}

fn run_instances(args: &InstancesArgs) -> Result<(), CliError> {
    let scene = BenchScene::from_arg_with(
        &args.scene,
        SceneSize::Full,
        &load_options(&args.asset_root),
    )
    .map_err(CliError::from_display)?;
    let config = crate::bench::instances::InstancesConfig {
        count: args.count as usize,
        flat_count: args.flat_count as usize,
        options: BuildOptions::default(),
    };
    let rows = crate::bench::instances::run(&scene, &config, &mut |line| eprintln!("{line}"))
        .map_err(CliError::from_display)?;
    let table = crate::bench::instances::table(&rows, config.count);
    if args.json {
        eprintln!("{table}");
        println!(
            "{}",
            serde_json::to_string_pretty(&rows).map_err(CliError::from_display)?
        );
    } else {
        println!("{table}");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(clap::Parser)]
    struct Cli {
        #[command(subcommand)]
        bench: BenchCommand,
    }

    fn parse(args: &[&str]) -> Result<RaysArgs, clap::Error> {
        let cli = Cli::try_parse_from(std::iter::once("bench").chain(args.iter().copied()))?;
        match cli.bench {
            BenchCommand::Rays(args) => Ok(args),
            BenchCommand::Render(_) | BenchCommand::Instances(_) => panic!("expected bench rays"),
        }
    }

    #[test]
    fn flags_override_the_preset() {
        let args = parse(&[
            "rays",
            "sphere",
            "x.glb",
            "--quick",
            "--runs",
            "3",
            "--threads",
            "4",
            "--width",
            "10",
        ])
        .unwrap();
        assert_eq!(args.scenes, ["sphere", "x.glb"]);
        let config = args.config();
        assert_eq!((config.runs.timed, config.build_runs.timed), (3, 3));
        assert_eq!(config.runs.warmup, RaysConfig::quick().runs.warmup);
        assert_eq!(
            (config.threads, config.width, config.height),
            (4, 10, RaysConfig::quick().height)
        );
    }

    #[test]
    fn zero_counts_are_refused() {
        for flag in [
            "--runs",
            "--threads",
            "--width",
            "--height",
            "--random-rays",
        ] {
            assert!(parse(&["rays", flag, "0"]).is_err(), "{flag} 0 accepted");
        }
    }
}

/// Arguments of the render benchmark.
#[derive(clap::Args, Debug, Clone)]
pub struct KernelBenchArgs {
    /// glTF scene; without it, a procedural scene (see --procedural).
    pub scene: Option<PathBuf>,
    /// Procedural scene when no file is given: sphere, terrain or soup.
    #[arg(long, default_value = "sphere")]
    pub procedural: String,
    /// Image width.
    #[arg(long, default_value_t = 640)]
    pub width: u32,
    /// Image height.
    #[arg(long, default_value_t = 360)]
    pub height: u32,
    /// Samples per pixel.
    #[arg(long, default_value_t = 4)]
    pub spp: u32,
    /// Ray-query backend.
    #[arg(long, default_value_t = BackendKind::default())]
    pub backend: BackendKind,
    /// Renders per kernel (the median is reported).
    #[arg(long, default_value_t = 5)]
    pub runs: usize,
    /// Worker threads; 0 uses every core.
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Integrator (the engine's default, `path`): `path` records the path tracer's own rays and
    /// replays them unshaded; `direct` compares the kernels and the raw camera + shadow trace.
    #[arg(long, value_parser = super::values::integrator(), default_value_t = RenderSettings::default().integrator)]
    pub integrator: render::Integrator,
    /// Bounces of the path tracer (`--integrator path`).
    #[arg(long, default_value_t = 8)]
    pub max_depth: u32,
    /// Environment map for `--integrator path`; without it, a uniform white environment of
    /// radiance 1 (`glint render --background 1,1,1`).
    #[arg(long)]
    pub env: Option<PathBuf>,
    /// Every file the glTF refers to must resolve inside this folder (as for glint render).
    #[arg(long, value_name = "DIR")]
    pub asset_root: Option<PathBuf>,
}

/// Loader options with `asset_root` and the default texture budget.
fn load_options(asset_root: &Option<PathBuf>) -> crate::scene::gltf::LoadOptions {
    crate::scene::gltf::LoadOptions {
        asset_root: asset_root.clone(),
        ..Default::default()
    }
}

/// The path tracer's benchmark: the scene's own lights (no default sun) under `--env` or the
/// default environment, its rays recorded and replayed ([`crate::bench::ray_mix`]).
fn run_path_mix(args: &KernelBenchArgs) -> Result<(), CliError> {
    let (scene, camera) = match &args.scene {
        Some(path) => {
            let scene = crate::scene::gltf::load_full(
                path,
                &crate::scene::gltf::SceneSelection::default(),
                &load_options(&args.asset_root),
            )
            .map(crate::scene::gltf::print_warnings)
            .map_err(CliError::from_display)?;
            let camera = scene
                .cameras
                .first()
                .cloned()
                .unwrap_or_else(|| crate::scene::defaults::default_camera(&scene));
            (scene, camera)
        }
        None => {
            let builtin = procedural(&args.procedural)?;
            procedural_scene(builtin, 1)
        }
    };
    let environment = match &args.env {
        Some(path) => crate::light::environment::EnvironmentLight::from_file(path, 1.0, 0.0)
            .map_err(CliError::from_display)?,
        None => crate::light::environment::EnvironmentLight::constant(glam::Vec3::ONE),
    };
    let accel = render::prepare(&scene, args.backend, BuildOptions::default())
        .map_err(CliError::from_display)?;
    let mipmaps = render::build_mipmaps(&scene);
    let area_lights =
        render::build_area_lights(&scene, Some(&mipmaps)).map_err(CliError::from_display)?;
    let inputs = render::RenderInputs {
        mipmaps: Some(&mipmaps),
        environment: Some(&environment),
        area_lights: Some(&area_lights),
        ..render::RenderInputs::of_scene(&scene, accel.as_ref(), &camera)
    };
    let settings = RenderSettings {
        width: args.width,
        height: args.height,
        spp: args.spp,
        threads: args.threads,
        integrator: render::Integrator::Path,
        max_depth: args.max_depth,
        ..RenderSettings::default()
    };
    let report = crate::bench::ray_mix::path_mix_bench(&inputs, &settings, args.runs)
        .map_err(CliError::from_display)?;
    println!(
        "{} triangles, {}×{}, {} spp, path tracer (max depth {}), {}",
        scene.triangle_count(),
        args.width,
        args.height,
        args.spp,
        args.max_depth,
        args.backend
    );
    println!("{report}");
    Ok(())
}

/// The procedural scene named `name`.
fn procedural(name: &str) -> Result<Builtin, CliError> {
    Builtin::ALL
        .into_iter()
        .find(|b| b.name() == name)
        .ok_or_else(|| {
            CliError::Usage(format!(
                "unknown procedural scene '{name}': use sphere, terrain or soup"
            ))
        })
}

/// Runs the render benchmark and prints its report to stdout.
pub fn run_render(args: KernelBenchArgs) -> Result<(), CliError> {
    if args.integrator == render::Integrator::Path {
        return run_path_mix(&args);
    }
    let (scene, camera) = match &args.scene {
        Some(path) => scene_to_bench_with(path, &load_options(&args.asset_root))
            .map_err(CliError::from_display)?,
        None => procedural_scene(procedural(&args.procedural)?, 1),
    };
    let accel = render::prepare(&scene, args.backend, BuildOptions::default())
        .map_err(CliError::from_display)?;
    let settings = RenderSettings {
        integrator: crate::render::Integrator::Direct,
        width: args.width,
        height: args.height,
        spp: args.spp,
        threads: args.threads,
        ..RenderSettings::default()
    };
    // The raw trace's median run, like the renders' (one run is too noisy on a shared machine).
    let mut raws = Vec::new();
    for _ in 0..args.runs.max(1) {
        raws.push(
            raw_trace(&scene, accel.as_ref(), &camera, &settings)
                .map_err(CliError::from_display)?,
        );
    }
    let elapsed: Vec<_> = raws.iter().map(|r| r.elapsed).collect();
    // Every run traces the same rays; only the time varies.
    let raw = crate::bench::render::RawTrace {
        elapsed: median_duration(&elapsed),
        ..raws[0]
    };
    let report = kernel_bench(&scene, accel.as_ref(), &camera, &settings, args.runs)
        .map_err(CliError::from_display)?;
    let rendered = report.rays as f64 / report.specialised.as_secs_f64().max(1e-12) / 1e6;
    println!(
        "{} triangles, {}×{}, {} spp, {}",
        scene.triangle_count(),
        args.width,
        args.height,
        args.spp,
        args.backend
    );
    println!("{report}");
    println!(
        "raw trace (camera + unshaded shadow rays, same batches, median): {:.3} s, {:.1} \
         Mrays/s; renderer reaches {:.0}% of it",
        raw.elapsed.as_secs_f64(),
        raw.mrays_per_second(),
        100.0 * rendered / raw.mrays_per_second().max(1e-12)
    );
    let threads = match args.threads {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
        n => n,
    };
    if threads > 1 {
        let scaling = thread_scaling(
            &scene,
            accel.as_ref(),
            &camera,
            &settings,
            threads,
            args.runs,
        )
        .map_err(CliError::from_display)?;
        println!(
            "scaling: 1 thread {:.3} s, {threads} threads {:.3} s: {:.2}× speed-up, {:.0}% \
             efficiency (median of {})",
            scaling.one.as_secs_f64(),
            scaling.all.as_secs_f64(),
            scaling.scaling.speedup,
            100.0 * scaling.scaling.efficiency,
            args.runs
        );
    }
    Ok(())
}
