//! A stable-toolchain fuzz loop for the glTF/GLB loader and scene preparation.
//!
//! Mutates the seed files of `../shared/scenes` and `../shared/khronos` (structure-aware: JSON
//! value edits, plus byte flips, truncations and splices; see `tests/mutate/mod.rs`), feeds
//! each mutant to the loader and both ray backends, catches panics, and saves every mutant
//! that breaks the contract (a panic or a malformed error) to the crash folder.
//!
//! Usage: `cargo run --release --example fuzz_loader -- SECONDS [SEED] [CRASH_DIR]`; prints
//! executions, executions per second and crashes (and a progress line every 10 s).
//! `tools/fuzz.sh SECONDS` wraps it and survives what this process cannot catch.
//!
//! Crash files: `CRASH_DIR/crash-SEED-N.{gltf,glb}`, each with `….seed` beside it naming the
//! seed file it came from (its relative URIs resolve against that file's folder). Before
//! each execution the mutant is written to `CRASH_DIR/in-progress.{gltf,glb}` (and
//! `in-progress.seed`), so that an abort (Embree's assertions), a hang or an out-of-memory
//! kill, which end this process, still leave the input that caused it for `tools/fuzz.sh`
//! to keep. A normal exit removes them.

#[path = "../tests/mutate/mod.rs"]
mod mutate;

use rand::{Rng, SeedableRng};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Seeds larger than this are skipped: their texture decoding would dominate the run.
const MAX_SEED_BYTES: u64 = 512 * 1024;

fn main() -> std::process::ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let seconds: f64 = args.first().and_then(|s| s.parse().ok()).unwrap_or(60.0);
    let rng_seed: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(1);
    let crash_dir = PathBuf::from(args.get(2).map_or("fuzz-crashes", String::as_str));
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared");
    let seeds = mutate::seeds(
        &[shared.join("scenes"), shared.join("khronos")],
        MAX_SEED_BYTES,
    );
    if seeds.is_empty() {
        eprintln!("fuzz_loader: no seed files under {}", shared.display());
        return std::process::ExitCode::FAILURE;
    }
    // Panics are caught and counted; their default report would flood the terminal.
    std::panic::set_hook(Box::new(|_| {}));
    let mut rng = rand_pcg::Pcg64::seed_from_u64(rng_seed);
    let start = Instant::now();
    let budget = Duration::from_secs_f64(seconds.max(0.0));
    let (mut executions, mut rendered, mut crashes) = (0u64, 0u64, 0u64);
    if let Err(err) = std::fs::create_dir_all(&crash_dir) {
        eprintln!("fuzz_loader: cannot create {}: {err}", crash_dir.display());
        return std::process::ExitCode::FAILURE;
    }
    let in_progress = |ext: &str| crash_dir.join(format!("in-progress.{ext}"));
    let mut last_report = Instant::now();
    while start.elapsed() < budget {
        let seed = &seeds[rng.random_range(0..seeds.len())];
        let mutant = mutate::mutate(&seed.bytes, &mut rng);
        let ext = if mutant.starts_with(b"glTF") {
            "glb"
        } else {
            "gltf"
        };
        // Kept if this execution ends the process (abort, hang, out of memory).
        let _ = std::fs::remove_file(in_progress(if ext == "glb" { "gltf" } else { "glb" }));
        let _ = std::fs::write(in_progress(ext), &mutant)
            .and_then(|()| std::fs::write(in_progress("seed"), &seed.name));
        match mutate::execute(&mutant, &seed.name, &seed.dir) {
            mutate::Outcome::Rendered => rendered += 1,
            mutate::Outcome::Refused => {}
            mutate::Outcome::Crash(why) => {
                crashes += 1;
                let file = crash_dir.join(format!("crash-{rng_seed}-{executions}.{ext}"));
                let saved = std::fs::write(&file, &mutant)
                    .and_then(|()| std::fs::write(file.with_extension("seed"), &seed.name));
                eprintln!(
                    "crash ({}) from {}: {why}",
                    match saved {
                        Ok(()) => file.display().to_string(),
                        Err(err) => format!("not saved: {err}"),
                    },
                    seed.name
                );
            }
        }
        executions += 1;
        if last_report.elapsed() >= Duration::from_secs(10) {
            last_report = Instant::now();
            println!("fuzz_loader: progress: {executions} executions, {crashes} crashes");
        }
    }
    for ext in ["gltf", "glb", "seed"] {
        let _ = std::fs::remove_file(in_progress(ext));
    }
    let elapsed = start.elapsed().as_secs_f64();
    println!(
        "fuzz_loader: {executions} executions in {elapsed:.0} s ({:.0}/s) over {} seeds, rng seed {rng_seed}: \
         {rendered} loaded and prepared, {} refused, {crashes} crashes",
        executions as f64 / elapsed.max(1e-9),
        seeds.len(),
        executions - rendered - crashes
    );
    if crashes == 0 {
        std::process::ExitCode::SUCCESS
    } else {
        std::process::ExitCode::FAILURE
    }
}
