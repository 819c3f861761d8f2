//! One claim per job, so that batch processes sharing a job file (two runs started by
//! mistake, a requeued array task overlapping its first attempt) never render a job twice.
//!
//! # With `flock` (the default)
//! A claim is the file `.NAME.glint-claim` next to the job's output `NAME`, holding an
//! exclusive advisory lock (`flock` through [`std::fs::File::try_lock`]). A process renders a
//! job only while it holds the job's claim, and gives the claim up after writing the output
//! (or failing) by removing the file and then unlocking it. The kernel drops the locks of a
//! process that dies, even by SIGKILL, so a claim left by a dead process is free at once: no
//! process ids to test, no reuse of ids to fear, and it works across machines on file systems
//! that carry locks (NFS does, through its lock manager or NFSv4 leases). The file also holds
//! the claimer's process id and host name, for people reading it; glint never trusts it.
//!
//! Exclusivity: after locking, the claimer checks that the path still names the file it
//! locked. A process that opened the file just before its holder removed it locks a removed
//! file, sees the mismatch and starts over, so two processes never both hold a claim that the
//! path names.
//!
//! # Without `flock`: exclusive claim files
//! Some FUSE and network mounts refuse `flock` (ENOLCK, EOPNOTSUPP, ENOSYS). There the claim
//! is the file `.NAME.glint-excl-claim`, created with `O_CREAT | O_EXCL` (one creator wins,
//! also over NFSv3 and later), holding the claimer's host name, boot id, process id and the
//! process's start time (field 22 of `/proc/PID/stat`), and a random token. The holder
//! touches the file every [`HEARTBEAT`] while it renders, and removes it (if the token is still
//! its own) when done. A process that dies leaves the file; whether another process may take
//! it over is the *stale-claim rule*:
//!
//! - **same host, same boot**: stale when no process has that id, or one has it but started at
//!   another time (the id was reused); never while the claimer runs;
//! - **same host, another boot id**: stale (the machine restarted; its processes are gone);
//! - **another host**: glint cannot see the other machine's processes, so such a claim is never
//!   stale by default: the job is reported busy. With `glint batch --steal-claims SECONDS` it is
//!   stale once its file has not been touched for that long; since a live holder touches it every
//!   [`HEARTBEAT`], the age must be at least [`MIN_STEAL_AGE`]. A clock skew between the machines
//!   shortens or lengthens the age by the skew;
//! - **unreadable** (a claimer killed between creating and writing the file, microseconds):
//!   stale once untouched for [`MIN_STEAL_AGE`].
//!
//! A stale claim is taken over under a second exclusive file, `.NAME.glint-excl-claim.takeover`:
//! its creator re-reads the claim, removes it only if it still holds the stale content, then
//! creates its own claim with `O_EXCL` like anyone else, so two processes judging one claim
//! stale never both hold the job. A takeover file left by a process that died during the
//! takeover is judged by the same rule.
//!
//! The exclusive files are used when `flock` fails on the claim file with one of those errors,
//! per claim, so every process on such a mount agrees. For tests, debug builds read the
//! environment variable `GLINT_TEST_NO_FLOCK` (any value): `flock` is then treated as
//! unsupported everywhere.

use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};
use std::time::Duration;

mod exclusive;

pub use exclusive::{mark_process_start, this_process_started};

/// How often the holder of an exclusive claim file touches it.
pub const HEARTBEAT: Duration = Duration::from_secs(60);

/// The least age, since its last touch, at which a claim of another host (with
/// `--steal-claims`) or an unreadable claim is stale: three missed heartbeats.
pub const MIN_STEAL_AGE: Duration = Duration::from_secs(180);

/// The environment variable that makes debug builds treat `flock` as unsupported (tests).
pub const TEST_NO_FLOCK_VAR: &str = "GLINT_TEST_NO_FLOCK";

/// What a batch may do with other processes' claims.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ClaimPolicy {
    /// Exclusive claim files of other hosts untouched for this long are stale (see the
    /// module documentation); `None`: never.
    pub steal_after: Option<Duration>,
    /// Use exclusive claim files even where `flock` works (tests).
    pub exclusive_files: bool,
}

/// A held claim on one job's output. Dropping it without [`Claim::release`] unlocks a
/// `flock` claim but leaves its file (the next claimer reuses it); an exclusive claim file
/// is left too (stale once this process is gone).
#[derive(Debug)]
pub struct Claim {
    held: Held,
    output: PathBuf,
}

#[derive(Debug)]
enum Held {
    Lock { file: File, path: PathBuf },
    Exclusive(exclusive::Held),
}

/// The claim file of `output`: `.NAME.glint-claim` in the same folder.
pub fn claim_path(output: &Path) -> PathBuf {
    let name = output
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    output.with_file_name(format!(".{name}.glint-claim"))
}

/// Tries to claim `output`'s job: `Ok(Some)` when this process now holds it, `Ok(None)` when
/// another live process does ([`holder`] says which). Never waits.
pub fn try_claim(output: &Path) -> std::io::Result<Option<Claim>> {
    try_claim_with(output, &ClaimPolicy::default())
}

/// [`try_claim`] under `policy`.
pub fn try_claim_with(output: &Path, policy: &ClaimPolicy) -> std::io::Result<Option<Claim>> {
    if policy.exclusive_files || flock_disabled_for_tests() {
        return exclusive_claim(output, policy);
    }
    let path = claim_path(output);
    // Each retry follows a holder that removed the file between our open and our lock; a
    // holder renders a whole job before it removes the file again, so a few retries suffice.
    for _ in 0..16 {
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)?;
        match file.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => return Ok(None),
            Err(TryLockError::Error(e)) if flock_unsupported(&e) => {
                // This file system has no flock: the file is of no use to anyone here.
                drop(file);
                let _ = std::fs::remove_file(&path);
                return exclusive_claim(output, policy);
            }
            Err(TryLockError::Error(e)) => return Err(e),
        }
        if !same_file(&file, &path) {
            continue;
        }
        file.set_len(0)?;
        file.rewind()?;
        writeln!(file, "pid {} on {}", std::process::id(), exclusive::host())?;
        return Ok(Some(Claim {
            held: Held::Lock { file, path },
            output: output.to_path_buf(),
        }));
    }
    Ok(None)
}

fn exclusive_claim(output: &Path, policy: &ClaimPolicy) -> std::io::Result<Option<Claim>> {
    Ok(
        exclusive::try_claim(&exclusive_claim_path(output), policy)?.map(|held| Claim {
            held: Held::Exclusive(held),
            output: output.to_path_buf(),
        }),
    )
}

/// Whether `flock`'s error says the file system does not do locks.
fn flock_unsupported(e: &std::io::Error) -> bool {
    /// ENOLCK, ENOSYS, EOPNOTSUPP (= ENOTSUP) on Linux.
    const NO_LOCKS: [i32; 3] = [37, 38, 95];
    e.kind() == std::io::ErrorKind::Unsupported
        || e.raw_os_error()
            .is_some_and(|code| NO_LOCKS.contains(&code))
}

/// The test hook: debug builds with `GLINT_TEST_NO_FLOCK` set treat `flock` as unsupported.
fn flock_disabled_for_tests() -> bool {
    cfg!(debug_assertions) && std::env::var_os(TEST_NO_FLOCK_VAR).is_some()
}

/// The exclusive claim file of `output` (file systems without `flock`):
/// `.NAME.glint-excl-claim` in the same folder.
pub fn exclusive_claim_path(output: &Path) -> PathBuf {
    let name = output
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    output.with_file_name(format!(".{name}.glint-excl-claim"))
}

/// Who holds the claim of `output`, as its file says (`pid 4242 on node17`), if readable.
pub fn holder(output: &Path) -> Option<String> {
    if let Some(owner) = exclusive::describe(&exclusive_claim_path(output)) {
        return Some(owner);
    }
    let mut text = String::new();
    File::open(claim_path(output))
        .ok()?
        .read_to_string(&mut text)
        .ok()?;
    let text = text.trim();
    (!text.is_empty()).then(|| text.to_string())
}

/// Whether `path` still names the file `file` has open.
#[cfg(unix)]
fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// Without inode numbers the check is skipped (the claim is then best effort).
#[cfg(not(unix))]
fn same_file(_: &File, path: &Path) -> bool {
    path.exists()
}

impl Claim {
    /// Removes the temporary files of earlier, interrupted writes of the claimed output
    /// (`.NAME.glint-PID-N.tmp`): every batch process writes an output only while holding its
    /// claim, so while this one holds it they are all leftovers, whichever process (on
    /// whichever machine) made them. Returns how many were removed.
    pub fn remove_stray_temps(&self) -> usize {
        crate::output::atomic::stray_temps(&self.output)
            .into_iter()
            .filter(|t| std::fs::remove_file(&t.path).is_ok())
            .count()
    }

    /// Gives the claim up: removes the claim file, then unlocks it (an exclusive claim
    /// file is removed only while it is still this claim's).
    pub fn release(self) {
        match self.held {
            Held::Lock { file, path } => {
                let _ = std::fs::remove_file(&path);
                drop(file);
            }
            Held::Exclusive(held) => held.release(),
        }
    }

    /// Whether this claim is an exclusive claim file (the file system has no `flock`).
    pub fn is_exclusive_file(&self) -> bool {
        matches!(self.held, Held::Exclusive(_))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_claim_is_exclusive_until_released_and_leaves_no_file() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("a.png");
        let first = try_claim(&out).unwrap().expect("free claim");
        // Locks are per open file, so a second open in this process conflicts like another
        // process would.
        assert!(try_claim(&out).unwrap().is_none());
        let note = holder(&out).unwrap();
        assert!(note.contains(&std::process::id().to_string()), "{note}");
        first.release();
        assert!(!claim_path(&out).exists());
        let again = try_claim(&out).unwrap().expect("released claim is free");
        again.release();
    }

    #[test]
    fn a_dropped_claim_is_free_again_like_a_dead_process() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("b.exr");
        // What a killed process leaves: the claim file, unlocked.
        drop(try_claim(&out).unwrap().unwrap());
        assert!(claim_path(&out).exists());
        let claim = try_claim(&out).unwrap().expect("stale claim reclaimed");
        claim.release();
    }

    #[test]
    fn stray_temporaries_of_the_claimed_output_are_removed() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("c.png");
        let stray = dir.path().join(".c.png.glint-1-0.tmp");
        let unrelated = dir.path().join(".d.png.glint-1-0.tmp");
        std::fs::write(&stray, b"half").unwrap();
        std::fs::write(&unrelated, b"half").unwrap();
        let claim = try_claim(&out).unwrap().unwrap();
        assert_eq!(claim.remove_stray_temps(), 1);
        claim.release();
        assert!(!stray.exists() && unrelated.exists());
    }
}
