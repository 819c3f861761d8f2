//! Panics as one-line errors: glint's quiet panic hook and the catch every boundary uses.
//!
//! A panic in glint is a bug, never the user's fault, and no user should see Rust's panic text
//! or its backtrace hint. [`install_quiet_hook`] (called first thing by the binary) replaces
//! Rust's default hook with one that prints nothing and records the panic's message and
//! source location. Each boundary that can meet a panic (a `glint` subcommand in `main`, a
//! batch job and its scene load in `batch::runner`, the Basis Universal transcoder in
//! `scene::ktx2_decode`, a render in the Python package) runs its work through [`catch`],
//! which returns the caught panic as a [`Panic`] carrying that message and location, for the
//! boundary to report in one line.
//!
//! For developers, `RUST_BACKTRACE=1` (or `full`) still works: the hook then prints the panic
//! and a backtrace to stderr as it happens.
//!
//! Without the hook installed (library users, unit tests) [`catch`] still works: the message
//! comes from the panic's payload, the location is then unknown.
//!
//! Test-only: in builds with debug assertions (`cargo build`, `cargo test`), the environment
//! variable `GLINT_TEST_PANIC` makes [`test_panic_point`] panic on purpose, so that tests can
//! check what a user sees when glint has a bug (see `tests/hostile/panics.rs`). Release builds never
//! read it.

use std::any::Any;
use std::panic::{AssertUnwindSafe, PanicHookInfo};
use std::sync::Mutex;

/// The exit status of `glint` when an internal error (a panic) ended a subcommand: 70 is
/// `EX_SOFTWARE` of BSD's sysexits.h. User errors exit with 1; Rust's own panic status 101
/// never occurs once the boundary catches.
pub const INTERNAL_ERROR_EXIT: u8 = 70;

/// How many recent panics the hook remembers for the catch sites (concurrent batch jobs may
/// panic at once; each catch takes its own record out).
const RECORDS_KEPT: usize = 64;

/// A caught panic: its message and, where the hook saw it raised, its source location.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Panic {
    /// The panic's message (`panic!`'s text, an `expect`'s text and error, …).
    pub message: String,
    /// `file:line:column` in glint's (or a dependency's) source, when the hook recorded it.
    pub location: Option<String>,
}

impl std::fmt::Display for Panic {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.location {
            Some(location) => write!(f, "{} (at {location})", self.message),
            None => f.write_str(&self.message),
        }
    }
}

impl Panic {
    /// The one line a boundary reports: "internal error while `doing`: message (at location)
    /// (please report this)". `doing` names the work and its file, e.g. "rendering a.gltf".
    pub fn report(&self, doing: &str) -> String {
        format!("internal error while {doing}: {self} (please report this)")
    }
}

/// Panics the hook recorded and no catch has taken yet, oldest first.
static RECORDED: Mutex<Vec<Panic>> = Mutex::new(Vec::new());

/// Replaces Rust's default panic hook (which prints "thread … panicked at …" and a backtrace
/// hint) with one that records the panic for [`catch`] and prints nothing, unless
/// `RUST_BACKTRACE` asks for a backtrace. Call once, at startup.
pub fn install_quiet_hook() {
    std::panic::set_hook(Box::new(quiet_hook));
}

fn quiet_hook(info: &PanicHookInfo<'_>) {
    let panic = Panic {
        message: message_of(info.payload()),
        location: info
            .location()
            .map(|l| format!("{}:{}:{}", l.file(), l.line(), l.column())),
    };
    if backtrace_wanted() {
        // Not `eprintln!`, which panics (inside the hook: an abort) when stderr is closed.
        use std::io::Write as _;
        let _ = writeln!(
            std::io::stderr(),
            "glint: panic: {panic}\n{}",
            std::backtrace::Backtrace::force_capture()
        );
    }
    let mut recorded = RECORDED
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if recorded.len() >= RECORDS_KEPT {
        recorded.remove(0);
    }
    recorded.push(panic);
}

/// Whether `RUST_BACKTRACE` asks for backtraces (set, and not "0"), as Rust's own hook reads it.
fn backtrace_wanted() -> bool {
    std::env::var_os("RUST_BACKTRACE").is_some_and(|v| v != "0")
}

/// Runs `f`, returning its result, or the panic it raised as a [`Panic`].
///
/// Like every catch site in glint, the caller must not use state `f` may have left half
/// updated; glint's boundaries only drop what `f` touched (the scene, the job's film).
pub fn catch<T>(f: impl FnOnce() -> T) -> Result<T, Panic> {
    std::panic::catch_unwind(AssertUnwindSafe(f)).map_err(|payload| from_payload(&*payload))
}

/// The [`Panic`] whose payload a `catch_unwind` returned: the message from the payload, the
/// location from the hook's record of the same message (the panic may have been raised on
/// another thread, e.g. a rayon worker, and resumed on this one).
pub fn from_payload(payload: &(dyn Any + Send)) -> Panic {
    let message = message_of(payload);
    let location = take_record(&message).and_then(|p| p.location);
    Panic { message, location }
}

/// Takes the newest record with `message` out of the hook's list.
fn take_record(message: &str) -> Option<Panic> {
    let mut recorded = RECORDED
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    let position = recorded.iter().rposition(|p| p.message == message)?;
    Some(recorded.remove(position))
}

/// A panic payload's text: `panic!` hands over a `&str` or a `String`; anything else (from
/// `std::panic::panic_any`) has no text.
fn message_of(payload: &(dyn Any + Send)) -> String {
    if let Some(text) = payload.downcast_ref::<&str>() {
        (*text).to_string()
    } else if let Some(text) = payload.downcast_ref::<String>() {
        text.clone()
    } else {
        "a panic without a message".to_string()
    }
}

/// The environment variable of [`test_panic_point`].
pub const TEST_PANIC_VAR: &str = "GLINT_TEST_PANIC";

/// Test-only: panics if `GLINT_TEST_PANIC` names this point, in builds with debug assertions.
/// The value is the point's name (`render`), optionally followed by `:` and text the `subject`
/// (e.g. the scene's label) must contain: `render:broken.gltf` panics only in renders of
/// scenes whose label contains `broken.gltf`. The panic's location is the caller's. Release
/// builds compile this to nothing.
#[track_caller]
pub fn test_panic_point(point: &str, subject: &str) {
    #[cfg(debug_assertions)]
    if let Ok(wanted) = std::env::var(TEST_PANIC_VAR) {
        let (name, filter) = wanted.split_once(':').unwrap_or((&wanted, ""));
        if name == point && subject.contains(filter) {
            panic!("{TEST_PANIC_VAR}={wanted}: a panic forced at {point} of {subject}");
        }
    }
    #[cfg(not(debug_assertions))]
    let _ = (point, subject);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_caught_panic_carries_its_message() {
        let caught = catch(|| -> u32 { panic!("broken {}", 7) }).unwrap_err();
        assert_eq!(caught.message, "broken 7");
        let caught = catch(|| -> u32 { panic!("static text") }).unwrap_err();
        assert_eq!(caught.message, "static text");
        assert_eq!(catch(|| 5).unwrap(), 5);
        let line = caught.report("rendering a.gltf");
        assert!(line.starts_with("internal error while rendering a.gltf: static text"));
        assert!(line.ends_with("(please report this)"));
    }

    #[test]
    fn a_record_is_taken_by_its_message() {
        RECORDED.lock().unwrap().push(Panic {
            message: "unique record 1234".into(),
            location: Some("src/x.rs:1:2".into()),
        });
        let panic = from_payload(&"unique record 1234");
        assert_eq!(panic.location.as_deref(), Some("src/x.rs:1:2"));
        assert_eq!(
            from_payload(&"unique record 1234").location,
            None,
            "taken once"
        );
    }
}
