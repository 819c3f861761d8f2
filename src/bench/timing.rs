//! Repeated wall-clock measurements summarised by their median and spread.
//!
//! Machines are shared and noisy: the median of several runs resists a run slowed by another
//! process, the min–max spread shows how noisy the machine was, and a discarded warm-up run
//! keeps first-touch costs (page faults, lazy thread pools, cold caches) out of the figures.

use super::cpu::process_cpu_s;
use serde::Serialize;
use std::time::{Duration, Instant};

/// How many times to run a measured piece of work.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Runs {
    /// Runs done first and discarded.
    pub warmup: usize,
    /// Runs timed (at least one is always done).
    pub timed: usize,
    /// Seconds after which no further timed run starts, once one is done: slow work (a
    /// 20-second build) then gets fewer runs instead of stretching the benchmark to minutes.
    /// `None`: always `timed` runs.
    pub budget_s: Option<f64>,
}

impl Runs {
    /// `timed` runs after `warmup`, with no time budget.
    pub fn exactly(warmup: usize, timed: usize) -> Self {
        Self {
            warmup,
            timed,
            budget_s: None,
        }
    }
}

/// Wall-clock seconds of the timed runs of one piece of work.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Timing {
    /// Median, seconds (the mean of the two middle runs for an even count).
    pub median_s: f64,
    /// Fastest run, seconds.
    pub min_s: f64,
    /// Slowest run, seconds.
    pub max_s: f64,
    /// Number of timed runs.
    pub runs: usize,
}

/// A rate derived from a [`Timing`]: items per second at the median, slowest and fastest run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Rate {
    /// Items per second at the median time.
    pub median: f64,
    /// Items per second of the slowest run.
    pub min: f64,
    /// Items per second of the fastest run.
    pub max: f64,
}

impl Timing {
    /// Summarises run times in seconds; `None` for no runs or a time that is not a finite,
    /// non-negative number.
    pub fn from_samples(samples_s: &[f64]) -> Option<Self> {
        if samples_s.is_empty() || samples_s.iter().any(|s| !s.is_finite() || *s < 0.0) {
            return None;
        }
        let mut sorted = samples_s.to_vec();
        sorted.sort_by(f64::total_cmp);
        let n = sorted.len();
        let median_s = if n % 2 == 1 {
            sorted[n / 2]
        } else {
            0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
        };
        Some(Self {
            median_s,
            min_s: sorted[0],
            max_s: sorted[n - 1],
            runs: n,
        })
    }

    /// `items` per second: at the median time, and at the slowest and fastest run.
    pub fn rate(&self, items: f64) -> Rate {
        Rate {
            median: items / self.median_s,
            min: items / self.max_s,
            max: items / self.min_s,
        }
    }
}

impl Rate {
    /// The same rate in millions per second.
    pub fn in_millions(&self) -> Rate {
        Rate {
            median: self.median * 1e-6,
            min: self.min * 1e-6,
            max: self.max * 1e-6,
        }
    }
}

/// The median of `times` ([`Timing`]'s median: the mean of the two middle runs for an even
/// count); zero for no runs. The one median of every benchmark.
pub fn median_duration(times: &[Duration]) -> Duration {
    let seconds: Vec<f64> = times.iter().map(Duration::as_secs_f64).collect();
    Timing::from_samples(&seconds).map_or(Duration::ZERO, |t| Duration::from_secs_f64(t.median_s))
}

/// How a speed grows from one thread to `threads`: what `bench rays` reports per query
/// ([`super::report::ScalingReport`]) and `bench render` for the renderer
/// ([`super::render::thread_scaling`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Scaling {
    /// The larger thread count.
    pub threads: usize,
    /// Speed with `threads` over speed with one (wall clock: capped by the processors the
    /// machine's load leaves free).
    pub speedup: f64,
    /// `speedup / threads`: 1 is perfect scaling.
    pub efficiency: f64,
}

impl Scaling {
    /// From the speeds (larger is faster, in any one unit) with one thread and with `threads`.
    pub fn of_speeds(threads: usize, one: f64, many: f64) -> Self {
        let speedup = many / one;
        Self {
            threads,
            speedup,
            efficiency: speedup / threads.max(1) as f64,
        }
    }

    /// From the times the same work takes with one thread and with `threads`.
    pub fn of_times(threads: usize, one: Duration, many: Duration) -> Self {
        let speed = |t: Duration| 1.0 / t.as_secs_f64().max(1e-12);
        Self::of_speeds(threads, speed(one), speed(many))
    }
}

/// What a measurement gives: the timing and the value of the last run (e.g. the structure
/// built, or a count to check).
#[derive(Debug)]
pub struct Timed<T> {
    /// Wall-clock times of the timed runs.
    pub timing: Timing,
    /// CPU time the whole process used during each timed run (all its threads), where the
    /// system reports it ([`super::cpu::process_cpu_s`]).
    pub cpu: Option<Timing>,
    /// What the last run returned.
    pub last: T,
}

/// Runs `work` once to warm up, then `runs` times (at least once) timed; see [`measure`].
pub fn median_of<T>(runs: usize, work: impl FnMut() -> T) -> Timed<T> {
    measure(Runs::exactly(1, runs), work)
}

/// Runs `work` `runs.warmup` times untimed, then `runs.timed` times (at least once) timed,
/// stopping early once the timed runs have taken `runs.budget_s`. The value a run returns is
/// dropped outside the timed region, and before the next run starts, so that freeing a large
/// result is never counted and two never coexist.
pub fn measure<T>(runs: Runs, work: impl FnMut() -> T) -> Timed<T> {
    let mut works = [work];
    let mut timed = measure_interleaved(runs, &mut works);
    // Proven invariant: one result per piece of work.
    timed.pop().expect("one piece of work, one result")
}

/// Measures several pieces of work in rounds: each round runs every piece once, so that a
/// change in the machine's load (other processes starting or stopping) hits all of them
/// alike, and ratios between them stay meaningful on a noisy machine. Each piece gets
/// `runs.warmup` untimed rounds, then timed rounds until it has `runs.timed` runs (at least
/// one) or its runs have taken `runs.budget_s`. As in [`measure`], a piece's previous value is
/// dropped before it runs again, outside the timed region. Results are in the order of
/// `works`.
pub fn measure_interleaved<T, W: FnMut() -> T>(runs: Runs, works: &mut [W]) -> Vec<Timed<T>> {
    for _ in 0..runs.warmup {
        for work in works.iter_mut() {
            drop(work());
        }
    }
    // Per piece: the wall and CPU times of its timed runs and the value of its latest run.
    type PieceState<T> = (Vec<f64>, Vec<Option<f64>>, Option<T>);
    let mut state: Vec<PieceState<T>> = works
        .iter()
        .map(|_| (Vec::new(), Vec::new(), None))
        .collect();
    loop {
        let mut ran = false;
        for (work, (samples_s, cpu_samples_s, last)) in works.iter_mut().zip(state.iter_mut()) {
            let spent_s: f64 = samples_s.iter().sum();
            let done = !samples_s.is_empty()
                && (samples_s.len() >= runs.timed
                    || runs.budget_s.is_some_and(|budget| spent_s >= budget));
            if done {
                continue;
            }
            drop(last.take());
            let cpu_before_s = process_cpu_s();
            let start = Instant::now();
            let value = work();
            samples_s.push(start.elapsed().as_secs_f64());
            let cpu_after_s = process_cpu_s();
            cpu_samples_s.push(cpu_before_s.zip(cpu_after_s).map(|(b, a)| (a - b).max(0.0)));
            *last = Some(value);
            ran = true;
        }
        if !ran {
            break;
        }
    }
    state
        .into_iter()
        .map(|(samples_s, cpu_samples_s, last)| Timed {
            // Proven invariants: the first round runs every piece once, setting `last` and
            // one sample; `Duration::as_secs_f64` is finite and non-negative.
            timing: Timing::from_samples(&samples_s).expect("one or more valid durations"),
            cpu: cpu_samples_s
                .into_iter()
                .collect::<Option<Vec<f64>>>()
                .and_then(|cpu_s| Timing::from_samples(&cpu_s)),
            last: last.expect("every piece ran at least once"),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        let odd = Timing::from_samples(&[3.0, 1.0, 2.0]).unwrap();
        assert_eq!(
            (odd.median_s, odd.min_s, odd.max_s, odd.runs),
            (2.0, 1.0, 3.0, 3)
        );
        let even = Timing::from_samples(&[4.0, 1.0, 2.0, 8.0]).unwrap();
        assert_eq!((even.median_s, even.min_s, even.max_s), (3.0, 1.0, 8.0));
    }

    #[test]
    fn bad_samples_give_no_timing() {
        assert_eq!(Timing::from_samples(&[]), None);
        assert_eq!(Timing::from_samples(&[1.0, f64::NAN]), None);
        assert_eq!(Timing::from_samples(&[-1.0]), None);
    }

    #[test]
    fn rate_inverts_times() {
        let t = Timing::from_samples(&[0.5, 0.25, 1.0]).unwrap();
        let r = t.rate(100.0);
        assert_eq!((r.median, r.min, r.max), (200.0, 100.0, 400.0));
        assert!((r.in_millions().median - 200.0e-6).abs() < 1e-15);
    }

    #[test]
    fn warmup_runs_are_done_and_discarded() {
        let mut calls = 0;
        let timed = measure(Runs::exactly(2, 3), || {
            calls += 1;
            calls
        });
        assert_eq!(calls, 5);
        assert_eq!(timed.timing.runs, 3);
        assert_eq!(timed.last, 5, "the value of the last run");
        // Zero timed runs still time one.
        assert_eq!(median_of(0, || ()).timing.runs, 1);
    }

    #[test]
    fn interleaved_work_runs_in_rounds_until_each_is_done() {
        let log = std::cell::RefCell::new(Vec::new());
        let piece = |name: char, pause_ms: u64| {
            let log = &log;
            move || {
                log.borrow_mut().push(name);
                std::thread::sleep(std::time::Duration::from_millis(pause_ms));
                name
            }
        };
        let mut works: [Box<dyn FnMut() -> char>; 2] =
            [Box::new(piece('a', 0)), Box::new(piece('b', 1))];
        let runs = Runs {
            warmup: 1,
            timed: 3,
            budget_s: Some(0.0),
        };
        let zero_budget = measure_interleaved(runs, &mut works);
        // A zero budget is spent by any first run, so each piece runs once after warm-up.
        assert_eq!(log.borrow().as_slice(), ['a', 'b', 'a', 'b']);
        assert_eq!(zero_budget.len(), 2);
        assert_eq!((zero_budget[0].last, zero_budget[1].last), ('a', 'b'));
        log.borrow_mut().clear();
        let ample = Runs {
            budget_s: None,
            ..runs
        };
        let timed = measure_interleaved(ample, &mut works);
        assert_eq!(
            log.borrow().as_slice(),
            ['a', 'b', 'a', 'b', 'a', 'b', 'a', 'b']
        );
        assert!(timed.iter().all(|t| t.timing.runs == 3));
    }

    #[test]
    fn a_spent_budget_stops_further_runs_but_never_the_first() {
        let sleep = || std::thread::sleep(std::time::Duration::from_millis(2));
        // A zero budget is spent by the first run, whatever the machine's speed.
        let zero = Runs {
            warmup: 1,
            timed: 5,
            budget_s: Some(0.0),
        };
        assert_eq!(measure(zero, sleep).timing.runs, 1);
        // A budget no run can spend allows them all.
        let ample = Runs {
            budget_s: Some(1e9),
            ..zero
        };
        assert_eq!(measure(ample, sleep).timing.runs, 5);
    }
}
