//! One claim per job, so that batch processes sharing a job file (two runs started by
//! mistake, a requeued array task overlapping its first attempt) never render a job twice.
//!
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

use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

/// A held claim on one job's output. Dropping it without [`Claim::release`] unlocks it but
/// leaves the file (the next claimer reuses it).
#[derive(Debug)]
pub struct Claim {
    file: File,
    path: PathBuf,
    output: PathBuf,
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
            Err(TryLockError::Error(e)) => return Err(e),
        }
        if !same_file(&file, &path) {
            continue;
        }
        file.set_len(0)?;
        file.rewind()?;
        let host = std::fs::read_to_string("/proc/sys/kernel/hostname")
            .map(|h| h.trim().to_string())
            .unwrap_or_else(|_| "unknown host".into());
        writeln!(file, "pid {} on {host}", std::process::id())?;
        return Ok(Some(Claim {
            file,
            path,
            output: output.to_path_buf(),
        }));
    }
    Ok(None)
}

/// Who holds the claim of `output`, as its file says (`pid 4242 on node17`), if readable.
pub fn holder(output: &Path) -> Option<String> {
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

    /// Gives the claim up: removes the claim file, then unlocks it.
    pub fn release(self) {
        let _ = std::fs::remove_file(&self.path);
        drop(self.file);
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
