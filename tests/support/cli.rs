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
