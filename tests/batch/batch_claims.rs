//! Batch claims without `flock` (exclusive claim files, `src/batch/claim.rs`), with the test
//! hook `GLINT_TEST_NO_FLOCK` making `flock` fail as on mounts that lack it: two concurrent
//! batches render each job exactly once; a dead process's claim is taken over; another
//! host's claim is left alone; and `--force` does not redo what a concurrent batch wrote.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use crate::support::{batch_report, demo, glint_command, job_statuses};

fn command(args: &[&str], cwd: &Path, no_flock: bool) -> Command {
    let mut command = glint_command(args, cwd);
    for var in [
        "SLURM_ARRAY_TASK_ID",
        "SLURM_ARRAY_TASK_COUNT",
        "JOB_COMPLETION_INDEX",
        "GLINT_SHARD_COUNT",
    ] {
        command.env_remove(var);
    }
    if no_flock {
        command.env("GLINT_TEST_NO_FLOCK", "1");
    } else {
        command.env_remove("GLINT_TEST_NO_FLOCK");
    }
    command
}

/// A job file of `n` tiny demo-scene jobs (a seed sweep).
fn jobs(dir: &Path, n: usize) -> PathBuf {
    let seeds: Vec<String> = (0..n).map(|s| s.to_string()).collect();
    let text = format!(
        "[defaults]\nscene = \"{}\"\nwidth = 48\nheight = 32\nspp = 1\n\
         [[sweep]]\noutput = \"out/job-{{seed:03}}.png\"\nseed = [{}]\n",
        demo().display(),
        seeds.join(", ")
    );
    std::fs::create_dir_all(dir.join("out")).unwrap();
    let path = dir.join("jobs.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn statuses(path: &Path) -> BTreeMap<u64, String> {
    job_statuses(&batch_report(path)).into_iter().collect()
}

/// Runs two batches side by side and checks each job was rendered by exactly one.
fn two_batches_render_each_job_once(extra: &[&str], no_flock: bool) -> (usize, usize) {
    const JOBS: usize = 24;
    let dir = tempfile::tempdir().unwrap();
    jobs(dir.path(), JOBS);
    if extra.contains(&"--force") {
        // Every output exists already: --force is what makes them render at all.
        let first = command(&["batch", "jobs.toml", "-q"], dir.path(), no_flock)
            .output()
            .unwrap();
        assert!(first.status.success());
    }
    let spawn = |report: &str| {
        let mut args = vec![
            "batch",
            "jobs.toml",
            "--report",
            report,
            "-q",
            "--threads",
            "1",
        ];
        args.extend_from_slice(extra);
        command(&args, dir.path(), no_flock)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let (a, b) = (spawn("a.json"), spawn("b.json"));
    let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
    assert!(a.status.success(), "{}", String::from_utf8_lossy(&a.stderr));
    assert!(b.status.success(), "{}", String::from_utf8_lossy(&b.stderr));
    let (sa, sb) = (
        statuses(&dir.path().join("a.json")),
        statuses(&dir.path().join("b.json")),
    );
    for index in 0..JOBS as u64 {
        let rendered = [&sa, &sb]
            .iter()
            .filter(|s| s[&index] == "rendered")
            .count();
        assert_eq!(
            rendered, 1,
            "job {index}: {} and {}",
            sa[&index], sb[&index]
        );
    }
    // No claim file is left behind.
    let left: Vec<String> = std::fs::read_dir(dir.path().join("out"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains("claim"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    let count = |s: &BTreeMap<u64, String>| s.values().filter(|v| *v == "rendered").count();
    (count(&sa), count(&sb))
}

#[test]
fn without_flock_two_concurrent_batches_render_each_job_once() {
    let (a, b) = two_batches_render_each_job_once(&[], true);
    eprintln!("without flock: a rendered {a}, b rendered {b}");
}

#[test]
fn with_force_two_concurrent_batches_still_render_each_job_once() {
    let (a, b) = two_batches_render_each_job_once(&["--force"], false);
    eprintln!("--force with flock: a rendered {a}, b rendered {b}");
    let (a, b) = two_batches_render_each_job_once(&["--force"], true);
    eprintln!("--force without flock: a rendered {a}, b rendered {b}");
}

/// The exclusive claim file a process with id `pid` on `host` would leave for `output`.
fn claim_text(host: &str, pid: u32) -> String {
    format!("glint batch claim\nhost {host}\nboot \npid {pid}\nstart 0\ntoken left-behind\n")
}

fn this_host() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .unwrap()
        .trim()
        .to_string()
}

#[test]
fn a_dead_processs_claim_is_taken_over_and_another_hosts_is_not() {
    let dir = tempfile::tempdir().unwrap();
    jobs(dir.path(), 2);
    let mut child = Command::new("true").spawn().unwrap();
    let dead = child.id();
    child.wait().unwrap();
    let out = dir.path().join("out");
    std::fs::write(
        out.join(".job-000.png.glint-excl-claim"),
        claim_text(&this_host(), dead),
    )
    .unwrap();
    std::fs::write(
        out.join(".job-001.png.glint-excl-claim"),
        claim_text("elsewhere", 1),
    )
    .unwrap();
    let run = command(
        &["batch", "jobs.toml", "--report", "r.json", "-q"],
        dir.path(),
        true,
    )
    .output()
    .unwrap();
    let first = statuses(&dir.path().join("r.json"));
    assert_eq!(
        first[&0],
        "rendered",
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert_eq!(first[&1], "busy");
    assert!(out.join("job-000.png").exists() && !out.join("job-001.png").exists());
    assert!(!out.join(".job-000.png.glint-excl-claim").exists());
    // Still held by the other host: --steal-claims below its minimum age is refused, and a
    // claim touched just now is not old enough for a valid one.
    let refused = command(
        &["batch", "jobs.toml", "--steal-claims", "10"],
        dir.path(),
        true,
    )
    .output()
    .unwrap();
    assert_eq!(refused.status.code(), Some(2));
    let young = command(
        &[
            "batch",
            "jobs.toml",
            "--steal-claims",
            "600",
            "--report",
            "r2.json",
            "-q",
        ],
        dir.path(),
        true,
    )
    .output()
    .unwrap();
    assert!(young.status.success() || young.status.code() == Some(1));
    assert_eq!(statuses(&dir.path().join("r2.json"))[&1], "busy");
}
