//! In-process fuzzing of glint's decoders and parsers on the stable toolchain.
//!
//! ```text
//! cargo run --release --example fuzz -- list
//! cargo run --release --example fuzz -- run TARGET|all [--seconds S] [--executions N]
//!     [--seed N] [--crashes DIR] [--timeout-ms MS] [--cap-mib MIB]
//! cargo run --release --example fuzz -- replay TARGET FILE...
//! cargo run --release --example fuzz -- seeds [DIR]
//! cargo run --release --example fuzz -- selftest
//! ```
//!
//! `run` supervises a worker process (this binary, `worker`) per target. The worker calls the
//! target function in a loop ([`engine`]), with panics caught, an allocation cap ([`alloc`])
//! and a watchdog thread for hangs; before each execution it writes the input to
//! `CRASHES/TARGET/.in-progress-PID`. What the worker catches it saves itself; when the worker
//! dies (an abort in C or C++ code, an allocation over the cap that aborts, a hang the
//! watchdog ends, a signal) the supervisor keeps the in-progress input as the finding and
//! starts a new worker with the next RNG seed, until the time is spent. `--seconds` is per
//! target (`all` runs every target for that long, one after the other).
//!
//! Findings: `CRASHES/TARGET/KIND-HASH.bin` (the input) and `.txt` (what happened), one per
//! distinct message; KIND is `panic`, `contract`, `oom`, `hang`, `abort`, `signal`.
//! Seeds: `tests/fuzz-corpus/TARGET/` (made by `seeds`), plus for some targets small files of
//! `../shared`. Output: one line per target with its executions and rate, and the findings.

#[path = "../../tests/mutate/mod.rs"]
mod mutate;

mod alloc;
mod draco_seed;
mod engine;
mod seeds;
mod targets;

use engine::{Fuzzer, Target, Verdict};
use std::collections::HashSet;
use std::io::{BufRead, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

#[global_allocator]
static ALLOCATOR: alloc::Capped = alloc::Capped;

/// Inputs kept per kind of worker death (hang, oom, abort, ...) and target in one run.
const KEPT_PER_DEATH_KIND: u64 = 5;

/// The worker's exit status when its watchdog ends a hung execution.
const HANG_EXIT: i32 = 86;

/// Settings of `run` and `worker`.
#[derive(Clone, Debug)]
struct Settings {
    seconds: f64,
    executions: u64,
    seed: u64,
    crashes: PathBuf,
    timeout_ms: u64,
    cap_mib: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            seconds: 60.0,
            executions: u64::MAX,
            seed: 1,
            crashes: PathBuf::from("fuzz-crashes"),
            timeout_ms: 2000,
            cap_mib: 256,
        }
    }
}

fn parse_settings(args: &[String]) -> Result<Settings, String> {
    let mut settings = Settings::default();
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        let value = it.next().ok_or_else(|| format!("{flag} needs a value"))?;
        let number = || {
            value
                .parse::<f64>()
                .map_err(|_| format!("{flag} {value}: not a number"))
        };
        match flag.as_str() {
            "--seconds" => settings.seconds = number()?,
            "--executions" => settings.executions = number()? as u64,
            "--seed" => settings.seed = number()? as u64,
            "--crashes" => settings.crashes = PathBuf::from(value),
            "--timeout-ms" => settings.timeout_ms = number()? as u64,
            "--cap-mib" => settings.cap_mib = number()? as usize,
            other => return Err(format!("unknown option {other}")),
        }
    }
    Ok(settings)
}

fn main() -> std::process::ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("list") => {
            for t in targets::all() {
                println!("{:8} {}", t.name, t.about);
            }
            Ok(true)
        }
        Some("run") => run(&args[1..]),
        Some("worker") => worker(&args[1..]),
        Some("replay") => replay(&args[1..]),
        Some("selftest") => selftest(),
        Some("seeds") => {
            let dir = args
                .get(1)
                .map_or_else(|| root().join("tests/fuzz-corpus"), PathBuf::from);
            seeds::write_all(&dir).map(|n| {
                println!("fuzz: wrote {n} seed files under {}", dir.display());
                true
            })
        }
        _ => Err(
            "usage: fuzz list | run TARGET|all [options] | replay TARGET FILE... | seeds [DIR]"
                .into(),
        ),
    };
    match result {
        Ok(true) => std::process::ExitCode::SUCCESS,
        Ok(false) => std::process::ExitCode::FAILURE,
        Err(message) => {
            eprintln!("fuzz: {message}");
            std::process::ExitCode::from(2)
        }
    }
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn target(name: &str) -> Result<&'static Target, String> {
    targets::by_name(name)
        .or_else(|| PLANTED.iter().find(|t| t.name == name))
        .ok_or_else(|| {
            let names: Vec<&str> = targets::all().iter().map(|t| t.name).collect();
            format!("no target {name:?}; targets: {}", names.join(", "))
        })
}

/// The seeds of `target`: its committed corpus, then the extra seeds read from `../shared`.
fn seeds_of(target: &Target) -> Vec<Vec<u8>> {
    let mut seeds = read_dir_files(&root().join("tests/fuzz-corpus").join(target.name));
    seeds.extend(seeds::shared_extras(target.name, target.max_len));
    seeds
}

fn read_dir_files(dir: &Path) -> Vec<Vec<u8>> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|entries| entries.flatten().map(|e| e.path()).collect())
        .unwrap_or_default();
    paths.retain(|p| p.is_file());
    paths.sort();
    paths.iter().filter_map(|p| std::fs::read(p).ok()).collect()
}

/// `run`: supervises one worker per target and reports.
fn run(args: &[String]) -> Result<bool, String> {
    let name = args.first().ok_or("run needs a target name or `all`")?;
    let settings = parse_settings(&args[1..])?;
    let chosen: Vec<&Target> = if name == "all" {
        targets::all().iter().collect()
    } else {
        vec![target(name)?]
    };
    let mut clean = true;
    let mut grand = 0u64;
    let start = Instant::now();
    for t in chosen {
        let report = supervise(t, &settings)?;
        println!(
            "fuzz: {}: {} executions ({} accepted) in {:.1} s ({:.0}/s), {} findings ({} saved), {} worker deaths",
            t.name,
            report.executions,
            report.accepted,
            report.seconds,
            report.executions as f64 / report.seconds.max(1e-9),
            report.findings,
            report.saved.len(),
            report.deaths
        );
        for file in &report.saved {
            println!("  {}", file.display());
        }
        grand += report.executions;
        clean &= report.findings == 0 && report.deaths == 0;
    }
    println!(
        "fuzz: {grand} executions in all, {:.0} s",
        start.elapsed().as_secs_f64()
    );
    Ok(clean)
}

#[derive(Default)]
struct Report {
    executions: u64,
    accepted: u64,
    findings: u64,
    deaths: u64,
    seconds: f64,
    saved: Vec<PathBuf>,
}

/// Runs workers for `target` until its time or executions are spent; a worker that dies
/// leaves its in-progress input, kept here as a finding.
fn supervise(target: &Target, settings: &Settings) -> Result<Report, String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot find this binary: {e}"))?;
    let dir = settings.crashes.join(target.name);
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let start = Instant::now();
    let mut report = Report::default();
    let mut restart = 0u64;
    let mut last_note = Instant::now();
    let mut deaths_by_kind: std::collections::BTreeMap<&str, u64> = Default::default();
    loop {
        let left = settings.seconds - start.elapsed().as_secs_f64();
        let executions_left = settings.executions.saturating_sub(report.executions);
        if left <= 0.0 || executions_left == 0 {
            break;
        }
        let mut child = std::process::Command::new(&exe)
            .arg("worker")
            .arg(target.name)
            .args(["--seconds", &format!("{left:.3}")])
            .args(["--executions", &executions_left.to_string()])
            .args(["--seed", &(settings.seed + restart).to_string()])
            .args(["--timeout-ms", &settings.timeout_ms.to_string()])
            .args(["--cap-mib", &settings.cap_mib.to_string()])
            .arg("--crashes")
            .arg(&settings.crashes)
            // A backtrace captured inside the panic hook would allocate past the cap (it
            // reads the binary's debug information): the worker reports panics itself.
            .env_remove("RUST_BACKTRACE")
            .env_remove("RUST_LIB_BACKTRACE")
            .stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .map_err(|e| format!("cannot start a worker: {e}"))?;
        let pid = child.id();
        // The worker's stderr is passed on; an abort from the allocation cap is recognised
        // by the standard library's message.
        let stderr = child.stderr.take();
        let out_of_memory = std::thread::spawn(move || {
            let mut seen = false;
            if let Some(stderr) = stderr {
                for line in std::io::BufReader::new(stderr)
                    .lines()
                    .map_while(Result::ok)
                {
                    seen |= line.starts_with("memory allocation of");
                    eprintln!("{line}");
                }
            }
            seen
        });
        let (mut executions, mut findings, mut accepted, mut saved) =
            (0u64, 0u64, 0u64, Vec::new());
        if let Some(stdout) = child.stdout.take() {
            for line in std::io::BufReader::new(stdout)
                .lines()
                .map_while(Result::ok)
            {
                let mut words = line.split_whitespace();
                match words.next() {
                    Some("progress" | "done") => {
                        executions = words
                            .next()
                            .and_then(|w| w.parse().ok())
                            .unwrap_or(executions);
                        if last_note.elapsed() >= Duration::from_secs(60) {
                            last_note = Instant::now();
                            println!(
                                "fuzz: {}: {} executions so far ({:.0} s)",
                                target.name,
                                report.executions + executions,
                                start.elapsed().as_secs_f64()
                            );
                        }
                        findings = words
                            .next()
                            .and_then(|w| w.parse().ok())
                            .unwrap_or(findings);
                        accepted = words
                            .next()
                            .and_then(|w| w.parse().ok())
                            .unwrap_or(accepted);
                    }
                    Some("saved") => saved.push(PathBuf::from(line["saved ".len()..].trim())),
                    _ => println!("{line}"),
                }
            }
        }
        let status = child.wait().map_err(|e| format!("lost the worker: {e}"))?;
        targets::remove_env_files_of(pid);
        let out_of_memory = out_of_memory.join().unwrap_or(false);
        report.executions += executions;
        report.findings += findings;
        report.accepted += accepted;
        report.saved.extend(saved);
        let in_progress = dir.join(format!(".in-progress-{pid}"));
        if status.success() || status.code() == Some(1) {
            let _ = std::fs::remove_file(&in_progress);
            break;
        }
        if status.code() == Some(2) {
            // The worker could not start (its own message is above): no input to blame.
            let _ = std::fs::remove_file(&in_progress);
            return Err(format!("the {} worker could not start", target.name));
        }
        report.deaths += 1;
        report.findings += 1;
        let kind = death_kind(&status, out_of_memory);
        let seen = deaths_by_kind.entry(kind).or_insert(0u64);
        *seen += 1;
        match std::fs::read(&in_progress) {
            // A fault hit again and again (each new worker finds it anew) is kept a few
            // times, not thousands: the rest are counted.
            Ok(_) if *seen > KEPT_PER_DEATH_KIND => {
                let _ = std::fs::remove_file(&in_progress);
            }
            Ok(input) => {
                let why =
                    format!("the worker died: {kind} ({status}) after {executions} executions");
                if let Some(file) = save(&dir, kind, &why, &input) {
                    eprintln!(
                        "fuzz: {}: {why}; input kept in {}",
                        target.name,
                        file.display()
                    );
                    report.saved.push(file);
                }
                let _ = std::fs::remove_file(&in_progress);
            }
            Err(err) => eprintln!(
                "fuzz: {}: the worker died ({kind}, {status}) and left no input ({err})",
                target.name
            ),
        }
        restart += 1;
    }
    report.seconds = start.elapsed().as_secs_f64();
    Ok(report)
}

#[cfg(unix)]
fn death_kind(status: &std::process::ExitStatus, out_of_memory: bool) -> &'static str {
    use std::os::unix::process::ExitStatusExt;
    match (status.code(), status.signal()) {
        (Some(HANG_EXIT), _) => "hang",
        (_, Some(6)) if out_of_memory => "oom",
        (_, Some(6)) => "abort",
        (_, Some(9)) => "killed",
        (_, Some(_)) => "signal",
        _ => "exit",
    }
}

#[cfg(not(unix))]
fn death_kind(status: &std::process::ExitStatus, _: bool) -> &'static str {
    if status.code() == Some(HANG_EXIT) {
        "hang"
    } else {
        "exit"
    }
}

/// Saves a finding once per distinct message: `KIND-HASH.bin` and `.txt`. Returns the path
/// when it was new.
fn save(dir: &Path, kind: &str, why: &str, input: &[u8]) -> Option<PathBuf> {
    let hash = xxhash_rust::xxh3::xxh3_64(input);
    let file = dir.join(format!("{kind}-{hash:016x}.bin"));
    if file.exists() {
        return None;
    }
    std::fs::write(&file, input).ok()?;
    let _ = std::fs::write(file.with_extension("txt"), format!("{why}\n"));
    Some(file)
}

/// Milliseconds since the worker started at which the current execution began; 0: idle.
static STARTED_MS: AtomicU64 = AtomicU64::new(0);

/// Ends the process when one execution runs past `timeout`: its input is already in the
/// in-progress file, which the supervisor keeps.
fn watchdog(epoch: Instant, timeout: Duration) {
    let poll = (timeout / 4).clamp(Duration::from_millis(10), Duration::from_millis(250));
    std::thread::spawn(move || {
        loop {
            std::thread::sleep(poll);
            let started = STARTED_MS.load(Ordering::Relaxed);
            if started == 0 {
                continue;
            }
            let now = epoch.elapsed().as_millis() as u64;
            if now.saturating_sub(started) > timeout.as_millis() as u64 {
                // No formatting: the allocator may be at its cap.
                let _ =
                    std::io::stderr().write_all(b"fuzz: an execution ran past the time limit\n");
                std::process::exit(HANG_EXIT);
            }
        }
    });
}

/// `worker`: the loop itself.
fn worker(args: &[String]) -> Result<bool, String> {
    let name = args.first().ok_or("worker needs a target")?;
    let target = target(name)?;
    let settings = parse_settings(&args[1..])?;
    let dir = settings.crashes.join(target.name);
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let in_progress_path = dir.join(format!(".in-progress-{}", std::process::id()));
    let in_progress = std::fs::File::create(&in_progress_path)
        .map_err(|e| format!("cannot create {}: {e}", in_progress_path.display()))?;
    glint::panics::install_quiet_hook();
    let mut fuzzer = Fuzzer::new(target, seeds_of(target), settings.seed);
    let epoch = Instant::now();
    watchdog(epoch, Duration::from_millis(settings.timeout_ms));
    let cap = settings.cap_mib << 20;
    let budget = Duration::from_secs_f64(settings.seconds.max(0.0));
    let mut seen = HashSet::new();
    let mut last_report = Instant::now();
    let stdout = std::io::stdout();
    while epoch.elapsed() < budget && fuzzer.executions < settings.executions {
        let input = fuzzer.next_input();
        write_in_progress(&in_progress, &input);
        STARTED_MS.store(
            (epoch.elapsed().as_millis() as u64).max(1),
            Ordering::Relaxed,
        );
        alloc::arm(cap);
        let verdict = fuzzer.execute(&input);
        alloc::disarm();
        STARTED_MS.store(0, Ordering::Relaxed);
        let mut found = Vec::new();
        if let Verdict::Finding(f) = verdict {
            found.push((f.kind, f.message));
        }
        if let Some(size) = alloc::refused() {
            fuzzer.findings += 1;
            found.push((
                "oom",
                format!(
                    "an allocation of {size} bytes would have taken the execution past the {} MiB cap \
                     (the decoder handled the failure)",
                    settings.cap_mib
                ),
            ));
        }
        for (kind, message) in found {
            if seen.insert(engine::signature(kind.as_bytes()[0], &message))
                && let Some(file) = save(&dir, kind, &message, &input)
            {
                let _ = writeln!(stdout.lock(), "saved {}", file.display());
                eprintln!("fuzz: {}: {kind}: {message}", target.name);
            }
        }
        if last_report.elapsed() >= Duration::from_millis(250) {
            last_report = Instant::now();
            let _ = writeln!(
                stdout.lock(),
                "progress {} {} {} {}",
                fuzzer.executions,
                fuzzer.findings,
                fuzzer.accepted,
                fuzzer.corpus_len()
            );
        }
    }
    targets::remove_env_file();
    let _ = std::fs::remove_file(&in_progress_path);
    let _ = writeln!(
        stdout.lock(),
        "done {} {} {} {} {:.3}",
        fuzzer.executions,
        fuzzer.findings,
        fuzzer.accepted,
        fuzzer.corpus_len(),
        epoch.elapsed().as_secs_f64()
    );
    Ok(fuzzer.findings == 0)
}

fn write_in_progress(file: &std::fs::File, input: &[u8]) {
    use std::os::unix::fs::FileExt;
    // Written before the execution, so that an abort or a hang leaves it behind.
    let _ = file.set_len(0);
    let _ = file.write_all_at(input, 0);
}

/// `replay`: runs saved inputs once each, in process, and prints what each gives.
fn replay(args: &[String]) -> Result<bool, String> {
    let name = args.first().ok_or("replay needs a target")?;
    let target = target(name)?;
    glint::panics::install_quiet_hook();
    let mut fuzzer = Fuzzer::new(target, Vec::new(), 0);
    let mut clean = true;
    for file in &args[1..] {
        let input = std::fs::read(file).map_err(|e| format!("{file}: {e}"))?;
        let outcome = std::panic::catch_unwind(|| (target.execute)(&input));
        println!("{file}: {outcome:?}");
        clean &= matches!(fuzzer.execute(&input), Verdict::Clean);
    }
    targets::remove_env_file();
    Ok(clean)
}

/// Test-only targets with a planted fault each, behind a 4-byte magic that is also their one
/// dictionary word: what `selftest` checks the harness catches and keeps.
static PLANTED: &[Target] = &[
    planted("planted-panic", b"BUG!"),
    planted("planted-hang", b"HANG"),
    planted("planted-oom", b"OOM!"),
    planted("planted-oom-handled", b"TRY!"),
    planted("planted-abort", b"ABRT"),
];

const fn planted(name: &'static str, magic: &'static [u8; 4]) -> Target {
    Target {
        name,
        about: "test-only: a planted fault (fuzz selftest)",
        execute: planted_fault,
        shape: engine::Shape::Binary,
        dictionary: match magic {
            b"BUG!" => &[b"BUG!"],
            b"HANG" => &[b"HANG"],
            b"OOM!" => &[b"OOM!"],
            b"TRY!" => &[b"TRY!"],
            _ => &[b"ABRT"],
        },
        max_len: 64,
    }
}

/// The planted faults, by the magic an input starts with.
fn planted_fault(input: &[u8]) -> engine::Outcome {
    match input.get(..4) {
        Some(b"BUG!") => panic!("planted panic"),
        Some(b"HANG") => loop {
            std::thread::sleep(Duration::from_millis(10));
        },
        Some(b"OOM!") => {
            // 64 GiB, infallibly: over the cap, the allocation fails and the process aborts.
            let huge = vec![1u8; 1 << 36];
            engine::Outcome::Accepted(format!("{}", huge.len()))
        }
        Some(b"TRY!") => {
            let mut v: Vec<u8> = Vec::new();
            match v.try_reserve(1 << 36) {
                Ok(()) => engine::Outcome::Accepted("reserved".into()),
                Err(_) => engine::Outcome::Refused("too large (handled)".into()),
            }
        }
        Some(b"ABRT") => std::process::abort(),
        _ => engine::Outcome::Refused("no magic".into()),
    }
}

/// `selftest`: runs each planted target briefly under the supervisor and checks that its
/// fault was found and its input kept, with the right kind.
fn selftest() -> Result<bool, String> {
    let dir = std::env::temp_dir().join(format!("glint-fuzz-selftest-{}", std::process::id()));
    let settings = Settings {
        seconds: 10.0,
        executions: u64::MAX,
        seed: 1,
        crashes: dir.clone(),
        timeout_ms: 500,
        cap_mib: 64,
    };
    let mut all = true;
    for (target, kind) in PLANTED.iter().zip(["panic", "hang", "oom", "oom", "abort"]) {
        // Stop at the first finding: a short run is enough.
        let settings = Settings {
            executions: 200_000,
            ..settings.clone()
        };
        let report = supervise(target, &settings)?;
        let found = report.saved.iter().any(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with(&format!("{kind}-")))
        });
        let kept = report
            .saved
            .iter()
            .filter_map(|p| std::fs::read(p).ok())
            .any(|bytes| bytes.len() >= 4);
        println!(
            "fuzz selftest: {}: {} ({} executions, {} saved, {} worker deaths)",
            target.name,
            if found && kept {
                format!("found as {kind}")
            } else {
                "NOT FOUND".into()
            },
            report.executions,
            report.saved.len(),
            report.deaths
        );
        all &= found && kept;
    }
    let _ = std::fs::remove_dir_all(&dir);
    Ok(all)
}
