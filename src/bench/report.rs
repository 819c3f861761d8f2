//! What `bench rays` measured: every figure as data (serialisable to JSON), the figures derived
//! from measurements of the same run (backend ratios, packet gains, thread scaling), and a
//! plain-text table for people.

use super::structure::Method;
use super::timing::{Rate, Runs, Scaling, Timing};
use crate::accel::BackendKind;
use serde::Serialize;
use std::fmt::Write as _;

/// Which rays a query traces.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Workload {
    /// Camera rays through neighbouring pixels, in 8×8 tiles.
    Coherent,
    /// Rays from random points of the scene's bounds in uniformly random directions.
    Incoherent,
}

impl Workload {
    /// Both workloads.
    pub const ALL: [Workload; 2] = [Workload::Coherent, Workload::Incoherent];

    /// Name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Workload::Coherent => "coherent",
            Workload::Incoherent => "incoherent",
        }
    }
}

/// Which question a query asks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Query {
    /// The closest hit.
    Closest,
    /// Whether anything is hit (shadow rays).
    Occluded,
}

impl Query {
    /// Both queries.
    pub const ALL: [Query; 2] = [Query::Closest, Query::Occluded];

    /// Name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Query::Closest => "closest",
            Query::Occluded => "occluded",
        }
    }
}

/// One timed query: a backend, a way of handing it rays, a workload, a question, a thread
/// count.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct QueryReport {
    /// Backend name (`embree`, `bvh`).
    pub backend: BackendKind,
    /// Single rays or packets.
    pub method: Method,
    /// Coherent or incoherent rays.
    pub workload: Workload,
    /// Closest hit or occlusion.
    pub query: Query,
    /// Worker threads tracing.
    pub threads: usize,
    /// Rays traced per run.
    pub rays: usize,
    /// Rays that hit (closest) or were occluded (occlusion) in the last run.
    pub positives: usize,
    /// Wall-clock seconds per run.
    pub seconds: Timing,
    /// Millions of rays per wall-clock second.
    pub mrays_per_s: Rate,
    /// CPU seconds the process used per run, where the system reports it.
    pub cpu_seconds: Option<Timing>,
    /// Millions of rays per CPU-second: what the code does with the processor time it gets,
    /// which the machine's load hardly changes.
    pub mrays_per_cpu_s: Option<Rate>,
    /// Median CPU seconds over (median wall seconds × threads): the share of the requested
    /// processors this query was given (1: all of them, the machine was otherwise idle).
    pub cpu_share: Option<f64>,
}

impl QueryReport {
    /// A report of `rays` rays traced in `seconds` (and `cpu_seconds`) with `threads` threads;
    /// the rates and the CPU share are derived here.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        backend: BackendKind,
        method: Method,
        workload: Workload,
        query: Query,
        threads: usize,
        rays: usize,
        positives: usize,
        seconds: Timing,
        cpu_seconds: Option<Timing>,
    ) -> Self {
        // A CPU time of zero (a run too short for the statistics) gives no rate.
        let cpu_seconds = cpu_seconds.filter(|cpu| cpu.min_s > 0.0);
        Self {
            backend,
            method,
            workload,
            query,
            threads,
            rays,
            positives,
            seconds,
            mrays_per_s: seconds.rate(rays as f64).in_millions(),
            mrays_per_cpu_s: cpu_seconds.map(|cpu| cpu.rate(rays as f64).in_millions()),
            cpu_share: cpu_seconds.map(|cpu| cpu.median_s / (seconds.median_s * threads as f64)),
            cpu_seconds,
        }
    }
}

/// One build setting of one backend: how long it takes to build and what its trees give.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BuildReport {
    /// Backend name.
    pub backend: BackendKind,
    /// `low`, `medium` or `high`.
    pub quality: String,
    /// Embree's robust flag (always false for obvhs, which has none).
    pub robust: bool,
    /// Whether this is the default setting (`BuildOptions::default()`), the one the full
    /// query matrix was measured on.
    pub is_default: bool,
    /// Build time, wall-clock seconds.
    pub build_s: Timing,
    /// CPU seconds the process used per build (all threads), where the system reports it.
    pub build_cpu_s: Option<Timing>,
    /// Both workloads and both queries, with the most threads and the backend's default
    /// method (what `Accel::intersect_many` uses).
    pub queries: Vec<QueryReport>,
}

/// Whether occlusion agrees with the closest hits of the same rays: a ray is occluded exactly
/// when its closest hit (over `[tnear, ∞)`) lies no farther than the occlusion ray's `tfar`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ConsistencyReport {
    /// Backend name.
    pub backend: BackendKind,
    /// Single rays or packets.
    pub method: Method,
    /// Coherent or incoherent rays.
    pub workload: Workload,
    /// Rays traced.
    pub rays: usize,
    /// Rays with a closest hit.
    pub closest_hits: usize,
    /// Rays whose closest hit is within the occlusion ray's `tfar` (all of them for the
    /// coherent workload, whose rays are unbounded).
    pub closest_hits_within_tfar: usize,
    /// Occluded rays.
    pub occluded: usize,
}

/// Embree's throughput over obvhs's for the same rays, measured in the same run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RatioReport {
    /// Embree's method (obvhs traces single rays).
    pub method: Method,
    /// Coherent or incoherent rays.
    pub workload: Workload,
    /// Closest hit or occlusion.
    pub query: Query,
    /// Worker threads.
    pub threads: usize,
    /// Median Embree Mrays/s over median obvhs Mrays/s (wall clock).
    pub ratio: f64,
    /// The same per CPU-second, where both have CPU times.
    pub ratio_per_cpu_s: Option<f64>,
}

/// Embree's 8-wide packets over its single rays, measured in the same run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PacketGainReport {
    /// Coherent or incoherent rays.
    pub workload: Workload,
    /// Closest hit or occlusion.
    pub query: Query,
    /// Worker threads.
    pub threads: usize,
    /// Median packet Mrays/s over median single-ray Mrays/s (> 1: packets win; wall clock).
    pub packet8_over_single: f64,
    /// The same per CPU-second, where both have CPU times.
    pub packet8_over_single_per_cpu_s: Option<f64>,
}

/// How throughput grows from one thread to many.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ScalingReport {
    /// Backend name.
    pub backend: BackendKind,
    /// Single rays or packets.
    pub method: Method,
    /// Coherent or incoherent rays.
    pub workload: Workload,
    /// Closest hit or occlusion.
    pub query: Query,
    /// The thread count, and the median Mrays/s with it over the median Mrays/s with one.
    #[serde(flatten)]
    pub scaling: Scaling,
    /// Mrays per CPU-second with `threads` over that with one: 1 when more threads cost no
    /// extra work (no contention, no idle spinning), whatever the machine's load.
    pub cpu_efficiency: Option<f64>,
}

/// Everything measured on one scene.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SceneReport {
    /// Built-in name or file path.
    pub name: String,
    /// Triangles in the scene.
    pub triangles: usize,
    /// The camera the coherent rays come from.
    pub camera: String,
    /// Smallest corner of the world-space bounds of the vertices (random rays start inside).
    pub bounds_min: [f32; 3],
    /// Largest corner of those bounds.
    pub bounds_max: [f32; 3],
    /// Coherent (camera) rays per measurement.
    pub camera_rays: usize,
    /// Incoherent (random) rays per measurement.
    pub random_rays: usize,
    /// Every build setting of every backend, with the queries each gives.
    pub builds: Vec<BuildReport>,
    /// On the default build: every method, workload, query and thread count.
    pub queries: Vec<QueryReport>,
    /// Occlusion against closest hits, per backend, method and workload.
    pub consistency: Vec<ConsistencyReport>,
    /// Embree over obvhs, from `queries`.
    pub embree_over_bvh: Vec<RatioReport>,
    /// Embree's packets over its single rays, from `queries`.
    pub packet_gains: Vec<PacketGainReport>,
    /// One thread to many, from `queries`.
    pub scaling: Vec<ScalingReport>,
}

/// The whole `bench rays` report.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RaysReport {
    /// glint's version.
    pub glint_version: String,
    /// Embree's version, if the backend is built in.
    pub embree_version: Option<String>,
    /// When the run finished, seconds since the Unix epoch.
    pub unix_time_s: u64,
    /// Hardware threads of the machine.
    pub available_threads: usize,
    /// Thread counts measured.
    pub threads: Vec<usize>,
    /// Camera-ray image width, pixels.
    pub width: u32,
    /// Camera-ray image height, pixels.
    pub height: u32,
    /// Random rays per incoherent figure.
    pub random_rays: usize,
    /// Warm-up and timed runs (at most) per query figure.
    pub runs: Runs,
    /// Runs (at most) per build figure.
    pub build_runs: Runs,
    /// Per scene.
    pub scenes: Vec<SceneReport>,
}

/// Whether two measurements traced the same rays with the same number of threads.
fn same_rays(a: &QueryReport, b: &QueryReport) -> bool {
    a.workload == b.workload && a.query == b.query && a.threads == b.threads
}

/// `a / b` for the per-CPU-second medians, where both have them.
fn cpu_ratio(a: &QueryReport, b: &QueryReport) -> Option<f64> {
    Some(a.mrays_per_cpu_s?.median / b.mrays_per_cpu_s?.median)
}

/// Embree (each method) over obvhs for every workload, query and thread count measured on
/// both.
pub fn embree_over_bvh(queries: &[QueryReport]) -> Vec<RatioReport> {
    queries
        .iter()
        .filter(|q| q.backend == BackendKind::Embree)
        .filter_map(|embree| {
            let bvh = queries
                .iter()
                .find(|q| q.backend == BackendKind::Bvh && same_rays(q, embree))?;
            Some(RatioReport {
                method: embree.method,
                workload: embree.workload,
                query: embree.query,
                threads: embree.threads,
                ratio: embree.mrays_per_s.median / bvh.mrays_per_s.median,
                ratio_per_cpu_s: cpu_ratio(embree, bvh),
            })
        })
        .collect()
}

/// Embree's packets over its single rays for every workload, query and thread count.
pub fn packet_gains(queries: &[QueryReport]) -> Vec<PacketGainReport> {
    let embree = |method: Method| {
        queries
            .iter()
            .filter(move |q| q.backend == BackendKind::Embree && q.method == method)
    };
    embree(Method::Packet8)
        .filter_map(|packet| {
            let single = embree(Method::Single).find(|q| same_rays(q, packet))?;
            Some(PacketGainReport {
                workload: packet.workload,
                query: packet.query,
                threads: packet.threads,
                packet8_over_single: packet.mrays_per_s.median / single.mrays_per_s.median,
                packet8_over_single_per_cpu_s: cpu_ratio(packet, single),
            })
        })
        .collect()
}

/// Speed-up and efficiency from one thread to each larger count, per backend, method,
/// workload and query.
pub fn scaling(queries: &[QueryReport]) -> Vec<ScalingReport> {
    queries
        .iter()
        .filter(|q| q.threads > 1)
        .filter_map(|many| {
            let one = queries.iter().find(|q| {
                q.threads == 1
                    && q.backend == many.backend
                    && q.method == many.method
                    && q.workload == many.workload
                    && q.query == many.query
            })?;
            Some(ScalingReport {
                backend: many.backend,
                method: many.method,
                workload: many.workload,
                query: many.query,
                scaling: Scaling::of_speeds(
                    many.threads,
                    one.mrays_per_s.median,
                    many.mrays_per_s.median,
                ),
                cpu_efficiency: cpu_ratio(many, one),
            })
        })
        .collect()
}

/// Three significant digits, without exponents, for figures from 0.001 to 10⁵.
fn sig3(x: f64) -> String {
    let decimals = if x >= 100.0 {
        0
    } else if x >= 10.0 {
        1
    } else if x >= 1.0 {
        2
    } else {
        3
    };
    format!("{x:.decimals$}")
}

/// "1 timed run", or "up to 5 timed runs (fewer once a query's runs reach 2 s)".
fn describe_runs(what: &str, runs: &Runs) -> String {
    match runs.budget_s {
        Some(budget) if runs.timed > 1 => format!(
            "up to {} timed runs (fewer once a {what}'s runs reach {budget} s)",
            runs.timed
        ),
        _ => format!("{} timed run(s)", runs.timed.max(1)),
    }
}

fn fmt_rate(rate: &Rate) -> String {
    format!(
        "{} ({}–{})",
        sig3(rate.median),
        sig3(rate.min),
        sig3(rate.max)
    )
}

fn fmt_timing(timing: &Timing) -> String {
    format!(
        "{} ({}–{})",
        sig3(timing.median_s),
        sig3(timing.min_s),
        sig3(timing.max_s)
    )
}

/// A figure that may be missing, as text.
fn or_dash(figure: Option<String>) -> String {
    figure.unwrap_or_else(|| "-".to_string())
}

/// A wall-clock ratio and its per-CPU-second counterpart: `3.10× / 3.25×`.
fn fmt_ratios(wall: f64, per_cpu_s: Option<f64>) -> String {
    format!(
        "{wall:.2}× / {}",
        or_dash(per_cpu_s.map(|r| format!("{r:.2}×")))
    )
}

impl RaysReport {
    /// The report as pretty-printed JSON.
    pub fn to_json(&self) -> Result<String, serde_json::Error> {
        serde_json::to_string_pretty(self)
    }

    /// The report as plain-text tables, one set per scene.
    pub fn to_table(&self) -> String {
        let mut out = String::new();
        let embree = self
            .embree_version
            .as_deref()
            .map_or("not built in".to_string(), |v| v.to_string());
        // Writing to a String cannot fail.
        let _ = writeln!(
            out,
            "glint {} bench rays: Embree {embree}; {} hardware threads; threads measured {:?}.\n\
             Each query figure: median (min–max) of {}, after {} discarded warm-up run(s).\n\
             Each build figure: median (min–max) of {}.\n\
             All settings, tracers and thread counts of a table are measured in interleaved \
             rounds, so their ratios hold even when the machine's load changes. Mrays/CPU-s \
             counts the processor time the process actually got; CPU share is that time over \
             wall time × threads (below 1: other work on the machine took the rest).",
            self.glint_version,
            self.available_threads,
            self.threads,
            describe_runs("query", &self.runs),
            self.runs.warmup,
            describe_runs("build", &self.build_runs),
        );
        for scene in &self.scenes {
            scene.write_table(&mut out, self);
        }
        out
    }
}

impl SceneReport {
    fn write_table(&self, out: &mut String, run: &RaysReport) {
        let widest = run.threads.last().copied().unwrap_or(1);
        let _ = writeln!(
            out,
            "\n== {}: {} triangles; {} coherent rays ({}×{} from the {}, 8×8 tiles); {} \
             incoherent rays (random origins in the bounds, uniform directions)",
            self.name,
            self.triangles,
            self.camera_rays,
            run.width,
            run.height,
            self.camera,
            self.random_rays,
        );
        self.write_builds(out, widest);
        self.write_queries(out);
        self.write_ratios(out);
        self.write_consistency(out);
    }

    fn write_builds(&self, out: &mut String, widest: usize) {
        let _ = writeln!(
            out,
            "\nBuild settings: wall seconds (and CPU seconds) per build, then Mrays/s with \
             {widest} threads and the backend's intersect_many method (embree: packet8, bvh: \
             single)"
        );
        let row = |c: [&str; 10]| {
            format!(
                "{:<7} {:<7} {:<6} {:<22} {:>4} {:>7} {:<22} {:<22} {:<22} {}",
                c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8], c[9]
            )
        };
        let _ = writeln!(
            out,
            "{}",
            row([
                "backend",
                "quality",
                "robust",
                "build s",
                "runs",
                "CPU s",
                "coherent closest",
                "coherent occluded",
                "incoherent closest",
                "incoherent occluded",
            ])
        );
        for build in &self.builds {
            let rate = |w: Workload, q: Query| {
                or_dash(
                    build
                        .queries
                        .iter()
                        .find(|r| r.workload == w && r.query == q)
                        .map(|r| fmt_rate(&r.mrays_per_s)),
                )
            };
            let _ = writeln!(
                out,
                "{}",
                row([
                    build.backend.name(),
                    &build.quality,
                    if build.robust { "yes" } else { "no" },
                    &fmt_timing(&build.build_s),
                    &build.build_s.runs.to_string(),
                    &or_dash(build.build_cpu_s.map(|c| sig3(c.median_s))),
                    &rate(Workload::Coherent, Query::Closest),
                    &rate(Workload::Coherent, Query::Occluded),
                    &rate(Workload::Incoherent, Query::Closest),
                    &rate(Workload::Incoherent, Query::Occluded),
                ])
            );
        }
    }

    fn write_queries(&self, out: &mut String) {
        let default_build = self
            .builds
            .iter()
            .find(|b| b.is_default)
            .map_or("the default", |b| b.quality.as_str());
        let _ = writeln!(
            out,
            "\nQueries on the {default_build} build (not robust). Speed-up: wall Mrays/s over \
             those with 1 thread; CPU eff.: Mrays/CPU-s over those with 1 thread"
        );
        let _ = writeln!(
            out,
            "{:<7} {:<7} {:<10} {:<8} {:>7} {:<22} {:>11} {:>9} {:>8} {:>9} {:>9}",
            "backend",
            "method",
            "workload",
            "query",
            "threads",
            "Mrays/s",
            "Mrays/CPU-s",
            "CPU share",
            "speed-up",
            "CPU eff.",
            "positives"
        );
        for q in &self.queries {
            let scaling = self.scaling.iter().find(|s| {
                s.backend == q.backend
                    && s.method == q.method
                    && s.workload == q.workload
                    && s.query == q.query
                    && s.scaling.threads == q.threads
            });
            let _ = writeln!(
                out,
                "{:<7} {:<7} {:<10} {:<8} {:>7} {:<22} {:>11} {:>9} {:>8} {:>9} {:>9}",
                q.backend,
                q.method.name(),
                q.workload.name(),
                q.query.name(),
                q.threads,
                fmt_rate(&q.mrays_per_s),
                or_dash(q.mrays_per_cpu_s.map(|r| sig3(r.median))),
                or_dash(q.cpu_share.map(|s| format!("{:.0}%", 100.0 * s))),
                or_dash(scaling.map(|s| format!("{:.2}×", s.scaling.speedup))),
                or_dash(
                    scaling
                        .and_then(|s| s.cpu_efficiency)
                        .map(|e| format!("{:.0}%", 100.0 * e))
                ),
                q.positives
            );
        }
    }

    fn write_ratios(&self, out: &mut String) {
        if self.packet_gains.is_empty() {
            return;
        }
        let _ = writeln!(
            out,
            "\nSame-run ratios, wall / per CPU-second: Embree over obvhs (single rays, packets), \
             and Embree's packets over its single rays"
        );
        let _ = writeln!(
            out,
            "{:<10} {:<8} {:>7} {:>16} {:>16} {:>16}",
            "workload", "query", "threads", "single/obvhs", "packet8/obvhs", "packet8/single"
        );
        for gain in &self.packet_gains {
            let ratio = |method: Method| {
                or_dash(
                    self.embree_over_bvh
                        .iter()
                        .find(|r| {
                            r.method == method
                                && r.workload == gain.workload
                                && r.query == gain.query
                                && r.threads == gain.threads
                        })
                        .map(|r| fmt_ratios(r.ratio, r.ratio_per_cpu_s)),
                )
            };
            let _ = writeln!(
                out,
                "{:<10} {:<8} {:>7} {:>16} {:>16} {:>16}",
                gain.workload.name(),
                gain.query.name(),
                gain.threads,
                ratio(Method::Single),
                ratio(Method::Packet8),
                fmt_ratios(gain.packet8_over_single, gain.packet8_over_single_per_cpu_s),
            );
        }
    }

    fn write_consistency(&self, out: &mut String) {
        let _ = writeln!(
            out,
            "\nConsistency: occluded rays must equal closest hits within the occlusion ray's \
             tfar"
        );
        let _ = writeln!(
            out,
            "{:<7} {:<7} {:<10} {:>9} {:>12} {:>12} {:>9}",
            "backend", "method", "workload", "rays", "closest hits", "within tfar", "occluded"
        );
        for check in &self.consistency {
            let _ = writeln!(
                out,
                "{:<7} {:<7} {:<10} {:>9} {:>12} {:>12} {:>9}",
                check.backend,
                check.method.name(),
                check.workload.name(),
                check.rays,
                check.closest_hits,
                check.closest_hits_within_tfar,
                check.occluded
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A query at `mrays` Mrays/s that used `cpu_share` of its threads' processors.
    fn query(backend: BackendKind, method: Method, threads: usize, mrays: f64) -> QueryReport {
        let wall_s = 1.0 / mrays;
        let seconds = Timing::from_samples(&[wall_s]).unwrap();
        // Half the requested processor time: per CPU-second, twice the wall rate per thread.
        let cpu_seconds = Timing::from_samples(&[0.5 * wall_s * threads as f64]).unwrap();
        QueryReport::new(
            backend,
            method,
            Workload::Coherent,
            Query::Closest,
            threads,
            1_000_000,
            10,
            seconds,
            Some(cpu_seconds),
        )
    }

    #[test]
    fn query_rates_and_cpu_share_follow_from_the_times() {
        let q = query(BackendKind::Embree, Method::Single, 2, 4.0);
        assert!((q.mrays_per_s.median - 4.0).abs() < 1e-9);
        assert!((q.cpu_share.unwrap() - 0.5).abs() < 1e-9);
        // 1M rays in 0.25 CPU-s.
        assert!((q.mrays_per_cpu_s.unwrap().median - 4.0).abs() < 1e-9);
        let no_cpu = QueryReport::new(
            BackendKind::Bvh,
            Method::Single,
            Workload::Coherent,
            Query::Closest,
            1,
            10,
            1,
            q.seconds,
            Timing::from_samples(&[0.0]),
        );
        assert_eq!((no_cpu.mrays_per_cpu_s, no_cpu.cpu_share), (None, None));
    }

    #[test]
    fn derived_figures_divide_the_matching_medians() {
        let queries = [
            query(BackendKind::Embree, Method::Single, 1, 10.0),
            query(BackendKind::Embree, Method::Packet8, 1, 30.0),
            query(BackendKind::Embree, Method::Single, 2, 16.0),
            query(BackendKind::Embree, Method::Packet8, 2, 60.0),
            query(BackendKind::Bvh, Method::Single, 1, 2.0),
            query(BackendKind::Bvh, Method::Single, 2, 4.0),
        ];
        let ratios = embree_over_bvh(&queries);
        assert_eq!(ratios.len(), 4);
        let ratio = |m, t| {
            ratios
                .iter()
                .find(|r| r.method == m && r.threads == t)
                .unwrap()
                .ratio
        };
        assert!((ratio(Method::Single, 1) - 5.0).abs() < 1e-9);
        // Equal CPU shares: the per-CPU-second ratio is the wall ratio.
        assert!((ratios[0].ratio_per_cpu_s.unwrap() - 5.0).abs() < 1e-9);
        assert!((ratio(Method::Packet8, 2) - 15.0).abs() < 1e-9);

        let gains = packet_gains(&queries);
        assert_eq!(gains.len(), 2);
        assert!((gains[0].packet8_over_single - 3.0).abs() < 1e-9);
        assert!((gains[1].packet8_over_single - 3.75).abs() < 1e-9);

        let scaling = scaling(&queries);
        assert_eq!(scaling.len(), 3);
        let embree_single = &scaling[0];
        assert_eq!(
            (embree_single.backend, embree_single.method),
            (BackendKind::Embree, Method::Single)
        );
        assert!((embree_single.scaling.speedup - 1.6).abs() < 1e-9);
        assert!((embree_single.scaling.efficiency - 0.8).abs() < 1e-9);
        // Per CPU-second: 16 / (2 · 0.5) over 10 / (1 · 0.5) Mrays per CPU-second.
        assert!((embree_single.cpu_efficiency.unwrap() - 0.8).abs() < 1e-9);
        assert!((scaling[2].scaling.efficiency - 1.0).abs() < 1e-9);
    }

    #[test]
    fn sig3_keeps_three_significant_digits() {
        assert_eq!(sig3(123.456), "123");
        assert_eq!(sig3(12.345), "12.3");
        assert_eq!(sig3(1.2345), "1.23");
        assert_eq!(sig3(0.012345), "0.012");
    }
}
