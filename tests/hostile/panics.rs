//! No panic reaches a user: a panic forced inside a render (the test-only `GLINT_TEST_PANIC`
//! of `glint::panics`, read only in builds with debug assertions) ends `glint render` with
//! the internal-error exit status and one line on stderr naming the file, without Rust's panic
//! text or backtrace hint and without an output file; through `glint batch` it fails only its
//! own job, in one line, and the other jobs render.

use std::path::Path;
use std::process::Output;

use crate::support::{demo, glint_command, stderr};

/// `glint` in `cwd` with `GLINT_TEST_PANIC=panic`, and without `RUST_BACKTRACE` (which asks
/// the hook for a developer's backtrace).
fn glint_panicking(args: &[&str], panic: &str, cwd: &Path) -> Output {
    glint_command(args, cwd)
        .env(glint::panics::TEST_PANIC_VAR, panic)
        .env_remove("RUST_BACKTRACE")
        .env_remove("RUST_LIB_BACKTRACE")
        .output()
        .expect("run glint")
}

/// Rust's own panic text, which no user may see.
fn assert_no_rust_panic_text(said: &str) {
    for text in [
        "panicked at",
        "RUST_BACKTRACE",
        "stack backtrace",
        "note: run with",
    ] {
        assert!(!said.contains(text), "{text:?} in: {said}");
    }
}

#[test]
#[cfg_attr(
    not(debug_assertions),
    ignore = "GLINT_TEST_PANIC exists in debug builds only"
)]
fn a_panic_in_a_render_is_one_line_and_exit_status_70() {
    let dir = tempfile::tempdir().unwrap();
    let scene = demo().display().to_string();
    let out = glint_panicking(
        &[
            "render", &scene, "--width", "8", "--height", "6", "--spp", "1", "-o", "out.png",
        ],
        "render",
        dir.path(),
    );
    assert_eq!(
        out.status.code(),
        Some(i32::from(glint::panics::INTERNAL_ERROR_EXIT)),
        "{}",
        stderr(&out)
    );
    let said = stderr(&out);
    let lines: Vec<&str> = said.lines().collect();
    assert_eq!(lines.len(), 1, "{said}");
    let line = lines[0];
    assert!(
        line.starts_with("glint: internal error while rendering ")
            && line.contains("demo.glb")
            && line.contains("GLINT_TEST_PANIC")
            && line.contains("src/job/run.rs")
            && line.ends_with("(please report this)"),
        "{line}"
    );
    assert_no_rust_panic_text(&said);
    assert!(!dir.path().join("out.png").exists());
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert!(left.is_empty(), "{left:?}");
}

#[test]
#[cfg_attr(
    not(debug_assertions),
    ignore = "GLINT_TEST_PANIC exists in debug builds only"
)]
fn a_panic_in_one_batch_job_fails_that_job_alone_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(demo(), dir.path().join("broken.glb")).unwrap();
    let text = format!(
        "[defaults]\nwidth = 8\nheight = 6\nspp = 1\n\
         [[job]]\nscene = \"{demo}\"\noutput = \"a.png\"\n\
         [[job]]\nscene = \"broken.glb\"\noutput = \"b.png\"\n\
         [[job]]\nscene = \"{demo}\"\noutput = \"c.png\"\nseed = 2\n",
        demo = demo().display()
    );
    std::fs::write(dir.path().join("jobs.toml"), text).unwrap();
    let out = glint_panicking(
        &["batch", "jobs.toml", "--report", "r.json", "-q"],
        "render:broken.glb",
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(1), "a failed job: {}", stderr(&out));
    let said = stderr(&out);
    assert_no_rust_panic_text(&said);
    let about_job: Vec<&str> = said.lines().filter(|l| l.contains("broken.glb")).collect();
    assert_eq!(about_job.len(), 1, "{said}");
    assert!(
        about_job[0].starts_with("job 1 ")
            && about_job[0].contains("internal error while rendering")
            && about_job[0].contains("b.png")
            && about_job[0].ends_with("(please report this)"),
        "{}",
        about_job[0]
    );
    assert!(dir.path().join("a.png").is_file() && dir.path().join("c.png").is_file());
    assert!(!dir.path().join("b.png").exists());
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("r.json")).unwrap()).unwrap();
    let statuses: Vec<&str> = report["jobs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| j["status"].as_str().unwrap())
        .collect();
    assert_eq!(statuses, ["rendered", "failed", "rendered"]);
    let error = report["jobs"][1]["error"].as_str().unwrap();
    assert!(
        error.contains("internal error") && error.contains("broken.glb"),
        "{error}"
    );
}
