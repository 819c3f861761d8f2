//! CPU time used by this process.
//!
//! On a machine shared with other work, wall-clock throughput measures the share of the
//! processors this process was given as much as the code. The CPU time its threads actually
//! ran gives a throughput per CPU-second that the load hardly changes, and, set against the
//! wall-clock time, the share of the requested processors that was granted.

/// Seconds all threads of this process (those alive and those that have exited) have spent
/// running on a processor: the POSIX process CPU-time clock. `None` where there is none.
pub fn process_cpu_s() -> Option<f64> {
    #[cfg(unix)]
    {
        use rustix::time::{ClockId, clock_gettime};
        let now = clock_gettime(ClockId::ProcessCPUTime);
        Some(now.tv_sec as f64 + now.tv_nsec as f64 * 1e-9)
    }
    #[cfg(not(unix))]
    {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn busy_work_shows_as_cpu_time() {
        let Some(start_s) = process_cpu_s() else {
            // No process CPU clock on this system: nothing to check.
            return;
        };
        // Spin for up to a second of wall time: the clock must advance, never go back.
        let wall = std::time::Instant::now();
        let mut x = 0u64;
        let mut now_s = start_s;
        while now_s <= start_s && wall.elapsed().as_secs_f64() < 1.0 {
            x = std::hint::black_box(x.wrapping_add(1));
            now_s = process_cpu_s().unwrap();
        }
        assert!(
            now_s > start_s,
            "the CPU clock did not advance while spinning"
        );
    }
}
