//! Exclusive claim files for file systems without `flock`: created with `O_EXCL`, holding
//! the claimer's identity, kept fresh by a heartbeat, taken over only when stale (the rule is
//! in the parent module's documentation).

use super::{ClaimPolicy, HEARTBEAT, MIN_STEAL_AGE};
use std::fs::OpenOptions;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, SystemTime};

/// Who made a claim, as its file says.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Owner {
    /// The host name.
    pub host: String,
    /// The kernel's boot id (`/proc/sys/kernel/random/boot_id`), empty if unknown.
    pub boot: String,
    /// The process id.
    pub pid: u32,
    /// The process's start time in clock ticks since boot (`/proc/PID/stat` field 22).
    pub start: u64,
    /// Random text that tells this claim from any other.
    pub token: String,
}

impl Owner {
    /// This process.
    pub fn me() -> Self {
        let pid = std::process::id();
        let nanos = SystemTime::now()
            .duration_since(SystemTime::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        Self {
            host: host(),
            boot: boot_id(),
            pid,
            start: process_start(pid).unwrap_or(0),
            token: format!("{pid:x}-{nanos:x}"),
        }
    }

    fn text(&self) -> String {
        format!(
            "glint batch claim\nhost {}\nboot {}\npid {}\nstart {}\ntoken {}\n",
            self.host, self.boot, self.pid, self.start, self.token
        )
    }

    fn parse(text: &str) -> Option<Self> {
        let mut lines = text.lines();
        if lines.next()? != "glint batch claim" {
            return None;
        }
        let mut field = |name: &str| -> Option<String> {
            let line = lines.next()?;
            line.strip_prefix(name)?
                .strip_prefix(' ')
                .map(str::to_string)
        };
        Some(Self {
            host: field("host")?,
            boot: field("boot")?,
            pid: field("pid")?.parse().ok()?,
            start: field("start")?.parse().ok()?,
            token: field("token")?,
        })
    }
}

/// This machine's host name.
pub fn host() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_string())
        .unwrap_or_else(|_| "unknown-host".into())
}

fn boot_id() -> String {
    std::fs::read_to_string("/proc/sys/kernel/random/boot_id")
        .map(|h| h.trim().to_string())
        .unwrap_or_default()
}

/// A process's start time in clock ticks since boot, if it exists.
pub fn process_start(pid: u32) -> Option<u64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The command name (field 2) may hold spaces and parentheses: count from the last ')'.
    let after = &stat[stat.rfind(')')? + 1..];
    // Fields 3, 4, ... follow; the start time is field 22.
    after.split_whitespace().nth(22 - 3)?.parse().ok()
}

/// The kernel's user-visible clock tick (`USER_HZ`) in which `/proc` reports times: 100 on
/// every Linux architecture glint builds for (x86-64, arm64).
const USER_HZ: f64 = 100.0;

/// This process's start as recorded by [`mark_process_start`], if it was.
static MARKED_START: std::sync::OnceLock<SystemTime> = std::sync::OnceLock::new();

/// Records now as this process's start, for [`this_process_started`]. The `glint` binary
/// calls it first thing in `main`, a millisecond or so after the process began: far more
/// exact than what `/proc` says (10 ms ticks), and exactness matters when one batch follows
/// another within milliseconds. Later calls change nothing.
pub fn mark_process_start() {
    let _ = MARKED_START.set(SystemTime::now());
}

/// How far the `/proc` estimate of a process's start may err: its two figures count in
/// 10 ms ticks.
const PROC_START_ERROR: Duration = Duration::from_millis(20);

/// When this process started, as wall-clock time: the moment [`mark_process_start`]
/// recorded, or else an estimate from `/proc` (now minus its age, the age from
/// `/proc/uptime` and its start in ticks since boot in `/proc/self/stat`).
///
/// The estimate is pushed [`PROC_START_ERROR`] later (never past now), so that it is never
/// earlier than the true start: a file written before this process began (by a batch that
/// ended a moment ago) must never count as written since. The price of the push is at most
/// a job of a concurrent batch written in the first 20 ms, rendered a second time.
/// `None` where neither is known, or `/proc` says something impossible.
pub fn this_process_started() -> Option<SystemTime> {
    if let Some(marked) = MARKED_START.get() {
        return Some(*marked);
    }
    let now = SystemTime::now();
    let uptime: f64 = std::fs::read_to_string("/proc/uptime")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()?;
    let start = process_start(std::process::id())? as f64 / USER_HZ;
    let age = uptime - start;
    // A process older than an hour has no side-by-side batch to tell apart; a negative age
    // is a clock the two files disagree on.
    if !(0.0..3600.0).contains(&age) {
        return None;
    }
    let estimate = now.checked_sub(Duration::from_secs_f64(age))? + PROC_START_ERROR;
    Some(estimate.min(now))
}

/// Whether a claim whose file says `owner` (or is unreadable: `None`) and was last touched
/// `age` ago is stale for `me` under `policy`.
pub fn is_stale(owner: Option<&Owner>, age: Duration, me: &Owner, policy: &ClaimPolicy) -> bool {
    let Some(owner) = owner else {
        return age >= MIN_STEAL_AGE;
    };
    if owner.host == me.host {
        if !owner.boot.is_empty() && !me.boot.is_empty() && owner.boot != me.boot {
            return true;
        }
        return match process_start(owner.pid) {
            None => true,
            // 0: the claimer could not read its own start time; then only the id counts.
            Some(start) => owner.start != 0 && start != owner.start,
        };
    }
    policy
        .steal_after
        .is_some_and(|after| age >= after.max(MIN_STEAL_AGE))
}

/// A held exclusive claim file and its heartbeat.
#[derive(Debug)]
pub struct Held {
    path: PathBuf,
    token: String,
    stop: Option<mpsc::Sender<()>>,
}

impl Held {
    /// Removes the claim file if it is still this claim's, and stops the heartbeat.
    pub fn release(mut self) {
        self.stop.take();
        if read_owner(&self.path).is_some_and(|o| o.token == self.token) {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

impl Drop for Held {
    fn drop(&mut self) {
        // Dropping the sender ends the heartbeat thread.
        self.stop.take();
    }
}

fn read_owner(path: &Path) -> Option<Owner> {
    Owner::parse(&std::fs::read_to_string(path).ok()?)
}

/// The claim's age: since its file was last touched.
fn age(path: &Path) -> Option<Duration> {
    let modified = std::fs::metadata(path).ok()?.modified().ok()?;
    Some(
        SystemTime::now()
            .duration_since(modified)
            .unwrap_or_default(),
    )
}

/// Creates `path` with `O_EXCL` holding `owner`; `Ok(false)` when it exists.
fn create(path: &Path, owner: &Owner) -> std::io::Result<bool> {
    match OpenOptions::new().write(true).create_new(true).open(path) {
        Ok(mut file) => {
            file.write_all(owner.text().as_bytes())?;
            file.sync_all()?;
            Ok(true)
        }
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Ok(false),
        Err(e) => Err(e),
    }
}

/// Describes the holder of the exclusive claim at `path` (`pid 4242 on node17`), if any.
pub fn describe(path: &Path) -> Option<String> {
    let owner = read_owner(path)?;
    Some(format!("pid {} on {}", owner.pid, owner.host))
}

/// Tries to claim `path`; takes over a stale claim (see the module documentation).
pub fn try_claim(path: &Path, policy: &ClaimPolicy) -> std::io::Result<Option<Held>> {
    let me = Owner::me();
    for _ in 0..4 {
        if create(path, &me)? {
            return Ok(Some(hold(path, &me)));
        }
        // Taken: by a live process, or a stale claim to take over.
        let text = std::fs::read_to_string(path).unwrap_or_default();
        let owner = Owner::parse(&text);
        let Some(age) = age(path) else {
            continue; // removed meanwhile: try again
        };
        if !is_stale(owner.as_ref(), age, &me, policy) || !take_over(path, &text, &me, policy)? {
            return Ok(None);
        }
    }
    Ok(None)
}

/// Removes the stale claim at `path` if it still reads `stale`, under the takeover file.
/// Returns whether it was removed (the caller then creates its own like anyone else).
fn take_over(path: &Path, stale: &str, me: &Owner, policy: &ClaimPolicy) -> std::io::Result<bool> {
    let mut marker = path.as_os_str().to_owned();
    marker.push(".takeover");
    let marker = PathBuf::from(marker);
    if !create(&marker, me)? {
        // Another process is taking over; or one died doing it, which the same rule judges.
        let owner = read_owner(&marker);
        if age(&marker).is_some_and(|age| is_stale(owner.as_ref(), age, me, policy)) {
            let _ = std::fs::remove_file(&marker);
        }
        return Ok(false);
    }
    let still = std::fs::read_to_string(path).is_ok_and(|now| now == stale);
    if still {
        let _ = std::fs::remove_file(path);
    }
    let _ = std::fs::remove_file(&marker);
    Ok(still)
}

/// The held claim, with a heartbeat thread that touches the file every [`HEARTBEAT`] until the
/// claim is released or dropped.
fn hold(path: &Path, me: &Owner) -> Held {
    let (stop, stopped) = mpsc::channel::<()>();
    let beating = path.to_path_buf();
    let spawned = std::thread::Builder::new()
        .name("glint-claim-heartbeat".into())
        .spawn(move || {
            while let Err(mpsc::RecvTimeoutError::Timeout) = stopped.recv_timeout(HEARTBEAT) {
                if let Ok(file) = OpenOptions::new().write(true).open(&beating) {
                    let _ = file.set_modified(SystemTime::now());
                }
            }
        });
    Held {
        path: path.to_path_buf(),
        token: me.token.clone(),
        stop: spawned.is_ok().then_some(stop),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dead_pid() -> u32 {
        let mut child = std::process::Command::new("true")
            .spawn()
            .expect("run true");
        let pid = child.id();
        child.wait().expect("wait");
        pid
    }

    fn other(me: &Owner) -> Owner {
        Owner {
            token: "someone-else".into(),
            ..me.clone()
        }
    }

    #[test]
    fn this_process_started_before_now_and_not_long_ago() {
        let before_now = SystemTime::now();
        let started = this_process_started().expect("/proc says when this process started");
        // Both /proc figures count in ticks of 10 ms: allow two of them past `before_now`.
        let age = (before_now + Duration::from_millis(20))
            .duration_since(started)
            .unwrap_or_else(|_| panic!("started {started:?} after {before_now:?}"));
        // The test binary has run for less than its whole suite's time limit.
        assert!(age < Duration::from_secs(3600), "{age:?}");
    }

    #[test]
    fn the_owner_text_round_trips_and_this_process_has_a_start_time() {
        let me = Owner::me();
        assert_eq!(Owner::parse(&me.text()), Some(me.clone()));
        assert!(me.start > 0);
        assert_eq!(Owner::parse("glint batch claim\nhost a\n"), None);
    }

    #[test]
    fn the_stale_claim_rule() {
        let me = Owner::me();
        let policy = ClaimPolicy::default();
        let fresh = Duration::from_secs(1);
        // A live process of this host (this one): never stale.
        assert!(!is_stale(
            Some(&other(&me)),
            Duration::from_secs(1 << 20),
            &me,
            &policy
        ));
        // A dead one: stale at once.
        let dead = Owner {
            pid: dead_pid(),
            ..other(&me)
        };
        assert!(is_stale(Some(&dead), fresh, &me, &policy));
        // The id reused by another process (this one, which started at another time).
        let reused = Owner {
            start: me.start + 1,
            ..other(&me)
        };
        assert!(is_stale(Some(&reused), fresh, &me, &policy));
        // This host before a restart.
        let rebooted = Owner {
            boot: "another-boot".into(),
            ..other(&me)
        };
        assert!(is_stale(Some(&rebooted), fresh, &me, &policy));
        // Another host: never without --steal-claims, then only past the age (and never
        // sooner than three heartbeats).
        let remote = Owner {
            host: "elsewhere".into(),
            ..other(&me)
        };
        let long = Duration::from_secs(3600);
        assert!(!is_stale(Some(&remote), long, &me, &policy));
        let steal = ClaimPolicy {
            steal_after: Some(Duration::from_secs(600)),
            ..policy
        };
        assert!(!is_stale(
            Some(&remote),
            Duration::from_secs(300),
            &me,
            &steal
        ));
        assert!(is_stale(Some(&remote), long, &me, &steal));
        let hasty = ClaimPolicy {
            steal_after: Some(Duration::from_secs(1)),
            ..policy
        };
        assert!(!is_stale(
            Some(&remote),
            Duration::from_secs(60),
            &me,
            &hasty
        ));
        // Unreadable: only once old.
        assert!(!is_stale(None, fresh, &me, &policy));
        assert!(is_stale(None, MIN_STEAL_AGE, &me, &policy));
    }

    #[test]
    fn a_claim_is_exclusive_and_a_dead_processs_claim_is_taken_over() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(".a.png.glint-excl-claim");
        let policy = ClaimPolicy::default();
        let held = try_claim(&path, &policy).unwrap().expect("free");
        assert!(
            try_claim(&path, &policy).unwrap().is_none(),
            "held by a live process"
        );
        held.release();
        assert!(!path.exists());
        // What a killed batch leaves: its claim, naming a process that is gone.
        let me = Owner::me();
        let dead = Owner {
            pid: dead_pid(),
            ..other(&me)
        };
        std::fs::write(&path, dead.text()).unwrap();
        let taken = try_claim(&path, &policy)
            .unwrap()
            .expect("a dead process's claim is stale");
        assert_eq!(read_owner(&path).unwrap().pid, std::process::id());
        taken.release();
        // Another host's claim stays, however old, without --steal-claims.
        let remote = Owner {
            host: "elsewhere".into(),
            ..other(&me)
        };
        std::fs::write(&path, remote.text()).unwrap();
        let old = SystemTime::now() - Duration::from_secs(7200);
        std::fs::File::options()
            .write(true)
            .open(&path)
            .unwrap()
            .set_modified(old)
            .unwrap();
        assert!(try_claim(&path, &policy).unwrap().is_none());
        let steal = ClaimPolicy {
            steal_after: Some(Duration::from_secs(3600)),
            ..policy
        };
        try_claim(&path, &steal)
            .unwrap()
            .expect("stolen past the age")
            .release();
    }
}
