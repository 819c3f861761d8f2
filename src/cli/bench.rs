//! `glint bench`.

use super::CliError;
use crate::bench::{BenchScene, RaysConfig, SceneSize, run_rays};

/// Benchmarks.
#[derive(clap::Subcommand, Debug)]
pub enum BenchCommand {
    /// Ray throughput and acceleration-structure build time of both backends.
    Rays(RaysArgs),
    /// The renderer's end-to-end ray rate next to the raw backend rate on the same rays, its
    /// kernel specialisation against the general kernel, and its scaling from 1 thread to all.
    Render(super::bench_render::KernelBenchArgs),
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
            .map(|arg| BenchScene::from_arg(arg, size).map_err(CliError::from_display))
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
        BenchCommand::Render(args) => super::bench_render::run(args),
    }
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
            BenchCommand::Render(_) => panic!("expected bench rays"),
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
