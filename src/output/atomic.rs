//! Atomic file writes: write to a temporary file in the destination's folder, flush it to
//! disk, then rename it over the destination. A rename within one file system is atomic, so
//! readers see either the old file or the complete new one; on any error (or a panic inside
//! the writer) the temporary file is removed and the destination is untouched.
//!
//! **Temporary names.** `.NAME.glint-PID-N.tmp` next to `NAME`: hidden, recognisable, and
//! naming the writing process (`PID`; `N` counts the process's writes). A process killed
//! with SIGKILL cannot remove its temporary file; [`stray_temps`] finds such leftovers by
//! name, and `glint batch` removes those of its own outputs (see `batch::claim`).
//!
//! **Jobs of several files.** [`write_together`] makes the atomic writes inside it one unit:
//! each file is written to its temporary name, and only when every one of them is complete
//! are they renamed, in the order they were written (a job writes its image last, so a
//! present image means every other output of the job is present too). A failure before the
//! renames leaves no output; a failed rename removes the files already renamed by the unit.
//!
//! **Fault injection (tests).** In builds with debug assertions, the environment variable
//! `GLINT_TEST_FAIL_WRITE=NAME` fails the write of every file named `NAME` as a full disk
//! would, `GLINT_TEST_FAIL_WRITE=rename:NAME` fails its rename, and
//! `GLINT_TEST_FAIL_WRITE=kill:NAME` aborts the process (SIGABRT: no cleanup runs, as after a
//! SIGKILL) just before that rename; several, comma-separated. Release builds never read it.
//!
//! **Mode.** The temporary file is created by `open(O_CREAT | O_EXCL)` with mode 0666, which
//! the kernel reduces by the process's umask, so outputs get the mode every other program's
//! new files get (0644 under umask 022). (The `tempfile` crate creates 0600 files, which a
//! rename would carry over to the output.)

use super::OutputError;
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// The marker between an output's name and the writer's process id in a temporary name.
const MARK: &str = ".glint-";
/// The temporary name's suffix.
const SUFFIX: &str = ".tmp";

/// Counts this process's temporary files, so that two writes of one process never collide.
static WRITES: AtomicU64 = AtomicU64::new(0);

/// Writes `path` atomically; `write` fills the file through a buffered writer (seekable, as
/// some encoders need). An error from `write` aborts the whole write.
pub fn write_atomically<F>(path: &Path, write: F) -> Result<(), OutputError>
where
    F: FnOnce(&mut BufWriter<&mut File>) -> Result<(), OutputError>,
{
    let io = |source: std::io::Error| OutputError::Io {
        path: path.to_path_buf(),
        source,
    };
    let folder = folder_of(path);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    if injected("", &name) {
        return Err(io(std::io::Error::other(
            "no space left on device (injected by GLINT_TEST_FAIL_WRITE)",
        )));
    }
    let (mut file, temp) = create_temp(folder, &name).map_err(io)?;
    // Removes the temporary file on every early return and on unwinding.
    let mut guard = RemoveOnDrop(Some(temp));
    {
        let mut writer = BufWriter::new(&mut file);
        write(&mut writer)?;
        writer.flush().map_err(io)?;
    }
    file.sync_all().map_err(io)?;
    drop(file);
    let temp = guard.0.take().unwrap_or_default();
    let deferred = UNIT.with(|unit| match unit.borrow_mut().as_mut() {
        Some(staged) => {
            staged.push((temp.clone(), path.to_path_buf()));
            true
        }
        None => false,
    });
    if deferred {
        return Ok(());
    }
    commit(&temp, path).map_err(io)
}

/// Renames the complete temporary file `temp` over `path` and makes the rename durable.
fn commit(temp: &Path, path: &Path) -> std::io::Result<()> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    if injected("kill:", &name) {
        std::process::abort();
    }
    let renamed = if injected("rename:", &name) {
        Err(std::io::Error::other(
            "rename refused (injected by GLINT_TEST_FAIL_WRITE)",
        ))
    } else {
        std::fs::rename(temp, path)
    };
    if let Err(e) = renamed {
        let _ = std::fs::remove_file(temp);
        return Err(e);
    }
    // Makes the rename itself durable; a folder that cannot be opened or synced (some
    // network file systems) only loses that guarantee.
    if let Ok(dir) = File::open(folder_of(path)) {
        let _ = dir.sync_all();
    }
    Ok(())
}

thread_local! {
    /// The files staged by the [`write_together`] running on this thread: (temporary, final).
    static UNIT: std::cell::RefCell<Option<Vec<(PathBuf, PathBuf)>>> =
        const { std::cell::RefCell::new(None) };
}

/// Runs `write`, whose atomic writes on this thread ([`write_atomically`] and every writer
/// built on it) become one unit: each is written to its temporary file, and when `write`
/// succeeds they are renamed in the order written. When `write` fails, no file is renamed
/// and every temporary is removed; when a rename fails, the files the unit renamed before it
/// are removed, so that no output of the unit is left looking complete. Nested calls join
/// the outer unit.
pub fn write_together<F>(write: F) -> Result<(), OutputError>
where
    F: FnOnce() -> Result<(), OutputError>,
{
    let outer = UNIT.with(|unit| unit.borrow().is_some());
    if outer {
        return write();
    }
    UNIT.with(|unit| *unit.borrow_mut() = Some(Vec::new()));
    // Takes the staged files out on every exit, a panic's unwinding included.
    struct Staged;
    impl Drop for Staged {
        fn drop(&mut self) {
            let left = UNIT
                .with(|unit| unit.borrow_mut().take())
                .unwrap_or_default();
            for (temp, _) in left {
                let _ = std::fs::remove_file(temp);
            }
        }
    }
    let staged_guard = Staged;
    write()?;
    let staged = UNIT
        .with(|unit| unit.borrow_mut().replace(Vec::new()))
        .unwrap_or_default();
    drop(staged_guard);
    for (k, (temp, path)) in staged.iter().enumerate() {
        if let Err(source) = commit(temp, path) {
            for (_, done) in &staged[..k] {
                let _ = std::fs::remove_file(done);
            }
            for (later, _) in &staged[k + 1..] {
                let _ = std::fs::remove_file(later);
            }
            return Err(OutputError::Io {
                path: path.clone(),
                source,
            });
        }
    }
    Ok(())
}

/// The test-only fault-injection variable (see the module documentation).
pub const FAIL_WRITE_VAR: &str = "GLINT_TEST_FAIL_WRITE";

/// Whether `GLINT_TEST_FAIL_WRITE` asks to fail the step `kind` (`""`: the write,
/// `rename:`, `kill:`) of the file `name`; always false in release builds.
fn injected(kind: &str, name: &str) -> bool {
    #[cfg(debug_assertions)]
    if let Ok(wanted) = std::env::var(FAIL_WRITE_VAR) {
        return wanted.split(',').any(|w| {
            w.strip_prefix(kind).is_some_and(|n| n == name) && (kind.is_empty() != w.contains(':'))
        });
    }
    let _ = (kind, name);
    false
}

/// The folder `path` is in (`.` for a bare file name).
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Creates a fresh temporary file for `name` in `folder` (mode 0666 less the umask).
fn create_temp(folder: &Path, name: &str) -> std::io::Result<(File, PathBuf)> {
    let pid = std::process::id();
    loop {
        let n = WRITES.fetch_add(1, Ordering::Relaxed);
        let temp = folder.join(format!(".{name}{MARK}{pid}-{n}{SUFFIX}"));
        match OpenOptions::new()
            .read(true)
            .write(true)
            .create_new(true)
            .open(&temp)
        {
            Ok(file) => return Ok((file, temp)),
            // A leftover of an earlier process with the same id: take the next number.
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
}

struct RemoveOnDrop(Option<PathBuf>);

impl Drop for RemoveOnDrop {
    fn drop(&mut self) {
        if let Some(path) = self.0.take() {
            let _ = std::fs::remove_file(path);
        }
    }
}

/// A temporary file of an atomic write of some destination, left behind or in progress.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StrayTemp {
    /// The temporary file.
    pub path: PathBuf,
    /// The process that created it.
    pub pid: u32,
}

/// The temporary files of atomic writes of `destination` present in its folder (by name:
/// `.NAME.glint-PID-N.tmp`). An unreadable folder has none.
pub fn stray_temps(destination: &Path) -> Vec<StrayTemp> {
    let Some(name) = destination.file_name().map(|n| n.to_string_lossy()) else {
        return Vec::new();
    };
    let Ok(entries) = std::fs::read_dir(folder_of(destination)) else {
        return Vec::new();
    };
    entries
        .flatten()
        .filter_map(|entry| {
            let file = entry.file_name();
            let pid = temp_writer(&file.to_string_lossy(), &name)?;
            Some(StrayTemp {
                path: entry.path(),
                pid,
            })
        })
        .collect()
}

/// The writer's process id if `file` is a temporary name of an atomic write of `name`.
fn temp_writer(file: &str, name: &str) -> Option<u32> {
    let rest = file
        .strip_prefix('.')?
        .strip_prefix(name)?
        .strip_prefix(MARK)?
        .strip_suffix(SUFFIX)?;
    let (pid, n) = rest.split_once('-')?;
    n.parse::<u64>().ok()?;
    pid.parse().ok()
}

/// Whether process `pid` is running on this machine: `Some(false)` only when it certainly is
/// not (Linux's `/proc` is mounted and has no entry for it), `None` when that cannot be told.
pub fn process_is_alive(pid: u32) -> Option<bool> {
    let proc = Path::new("/proc");
    if !proc.join("self").exists() {
        return None;
    }
    Some(proc.join(pid.to_string()).exists())
}

/// Removes the temporary files of `destination` whose writer is certainly dead, or is this
/// process (a leftover of an earlier process that had the same id: this process is not
/// writing `destination` when it asks). Returns how many were removed.
pub fn remove_dead_temps(destination: &Path) -> usize {
    let me = std::process::id();
    stray_temps(destination)
        .into_iter()
        .filter(|t| t.pid == me || process_is_alive(t.pid) == Some(false))
        .filter(|t| std::fs::remove_file(&t.path).is_ok())
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write_text(path: &Path, text: &[u8]) -> Result<(), OutputError> {
        write_atomically(path, |w| {
            w.write_all(text).map_err(|source| OutputError::Io {
                path: path.to_path_buf(),
                source,
            })
        })
    }

    #[test]
    fn replaces_the_file_only_when_complete() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.txt");
        write_text(&path, b"first").unwrap();
        let failed = write_atomically(&path, |w| {
            let _ = w.write_all(b"partial");
            Err(OutputError::Encode {
                path: path.clone(),
                format: "test",
                message: "injected".into(),
            })
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read(&path).unwrap(), b"first");
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            1,
            "no temp left"
        );
    }

    #[test]
    fn a_panicking_writer_leaves_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.txt");
        let result = std::panic::catch_unwind(|| {
            write_atomically(&path, |w| {
                let _ = w.write_all(b"half");
                panic!("encoder bug");
            })
        });
        assert!(result.is_err());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    #[test]
    fn temporary_names_are_recognised_with_their_writer() {
        assert_eq!(temp_writer(".a.png.glint-123-0.tmp", "a.png"), Some(123));
        assert_eq!(temp_writer(".a.png.glint-123-7.tmp", "b.png"), None);
        assert_eq!(temp_writer(".a.png.abc123.tmp", "a.png"), None);
        assert_eq!(temp_writer(".a.png.glint-x-1.tmp", "a.png"), None);
        assert_eq!(temp_writer("a.png", "a.png"), None);
        // A name that is a prefix of another output's name does not claim its temporaries.
        assert_eq!(temp_writer(".a.png.x.glint-1-1.tmp", "a.png"), None);
    }

    #[test]
    fn leftovers_of_dead_writers_are_found_and_removed_live_ones_kept() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("o.exr");
        // Process ids above the kernel's pid_max (2^22) never exist.
        let dead = dir.path().join(".o.exr.glint-99999999-0.tmp");
        let mine = dir
            .path()
            .join(format!(".o.exr.glint-{}-9.tmp", std::process::id()));
        let other = dir.path().join(".p.exr.glint-99999999-0.tmp");
        for p in [&dead, &mine, &other] {
            std::fs::write(p, b"x").unwrap();
        }
        let mut found: Vec<u32> = stray_temps(&out).iter().map(|t| t.pid).collect();
        found.sort();
        assert_eq!(found.len(), 2);
        if process_is_alive(1) == Some(true) {
            assert_eq!(remove_dead_temps(&out), 2);
            assert!(!dead.exists() && !mine.exists());
        }
        assert!(
            other.exists(),
            "another output's temporary file is not touched"
        );
    }

    #[cfg(unix)]
    #[test]
    fn outputs_get_the_default_mode_not_0600() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.txt");
        write_text(&path, b"x").unwrap();
        // The umask is process-wide and this test does not change it: whatever it is, a
        // plain `File::create` gets the same mode, and group/other bits survive a 022 umask.
        let reference = dir.path().join("reference.txt");
        std::fs::write(&reference, b"x").unwrap();
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&path), mode(&reference));
    }
}
