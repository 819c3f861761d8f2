//! Running the `glint` binary that Cargo built for the tests.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `glint ARGS` in `cwd`, ready to run (a caller may add environment variables first).
pub fn glint_command(args: &[&str], cwd: &Path) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_glint"));
    command.args(args).current_dir(cwd);
    command
}

/// Runs `glint ARGS` in `cwd` and returns what it did (the test fails if it cannot start).
pub fn glint(args: &[&str], cwd: &Path) -> Output {
    glint_command(args, cwd).output().expect("run glint")
}

/// The process's standard error as text.
pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The built-in demo scene's file, `scenes/demo.glb`.
pub fn demo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/demo.glb")
}

/// A `glint batch --report` file, read.
pub fn batch_report(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("read the report"))
        .expect("the report is JSON")
}

/// (index, status) of each job of a batch report, in the report's order.
pub fn job_statuses(report: &serde_json::Value) -> Vec<(u64, String)> {
    report["jobs"]
        .as_array()
        .expect("a jobs array")
        .iter()
        .map(|j| {
            let index = j["index"].as_u64().expect("a job index");
            (
                index,
                j["status"].as_str().expect("a job status").to_string(),
            )
        })
        .collect()
}

/// The names of the entries of `dir`, sorted (what a command left behind).
pub fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("read the folder")
        .map(|e| {
            e.expect("a folder entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    names.sort();
    names
}
