//! Replays every input the fuzz loops found crashing, kept in `tests/fuzz-regressions/`:
//! each must now load (or be refused with a one-line error naming the file) without a panic.
//! An abort or a hang fails the test binary.
//!
//! - `tests/fuzz-regressions/*.gltf|glb`: found by the file-based loop (`tools/fuzz.sh`),
//!   replayed on every backend;
//! - `tests/fuzz-regressions/TARGET/*`: found by the in-process targets (`examples/fuzz`),
//!   replayed through the same target function, which must come back clean (no panic, no
//!   broken contract).
//!
//! A kept input `NAME.gltf` / `NAME.glb` may have `NAME.seed` beside it: the path of the
//! shared seed file it was mutated from, whose folder its relative URIs resolve against (the
//! part after `shared/` is looked up under `../shared`).

use crate::mutate;

use crate::engine;
use crate::targets;

use std::path::{Path, PathBuf};

fn folder_for(input: &Path) -> PathBuf {
    let here = input.parent().unwrap_or(Path::new(".")).to_path_buf();
    let Ok(seed) = std::fs::read_to_string(input.with_extension("seed")) else {
        return here;
    };
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared");
    match seed.trim().split_once("shared/") {
        Some((_, rest)) => shared
            .join(rest)
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or(here),
        None => here,
    }
}

#[test]
fn every_kept_fuzz_crash_now_loads_or_is_refused() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-regressions");
    let mut inputs: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("tests/fuzz-regressions exists")
        .flatten()
        .map(|e| e.path())
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("gltf" | "glb")))
        .collect();
    inputs.sort();
    std::panic::set_hook(Box::new(|_| {}));
    let mut crashes = Vec::new();
    for input in &inputs {
        let bytes = std::fs::read(input).expect("read input");
        let label = input.display().to_string();
        if let mutate::Outcome::Crash(why) = mutate::execute(&bytes, &label, &folder_for(input)) {
            crashes.push(format!("{label}: {why}"));
        }
    }
    let _ = std::panic::take_hook();
    eprintln!("{} kept fuzz inputs replayed", inputs.len());
    assert!(crashes.is_empty(), "{}", crashes.join("\n"));
}

#[test]
fn every_kept_finding_of_the_in_process_targets_is_now_clean() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-regressions");
    std::panic::set_hook(Box::new(|_| {}));
    let mut broken = Vec::new();
    let mut replayed = 0;
    for target in targets::all() {
        let dir = root.join(target.name);
        let mut inputs: Vec<PathBuf> = std::fs::read_dir(&dir)
            .map(|entries| entries.flatten().map(|e| e.path()).collect())
            .unwrap_or_default();
        inputs.retain(|p| p.extension().is_some_and(|e| e != "txt" && e != "md"));
        inputs.sort();
        let mut fuzzer = engine::Fuzzer::new(target, Vec::new(), 0);
        for input in inputs {
            let bytes = std::fs::read(&input).expect("read a kept finding");
            replayed += 1;
            if let engine::Verdict::Finding(f) = fuzzer.execute(&bytes) {
                broken.push(format!("{}: {}: {}", input.display(), f.kind, f.message));
            }
        }
    }
    eprintln!("{replayed} kept findings of the in-process targets replayed");
    assert!(broken.is_empty(), "{}", broken.join("\n"));
}
