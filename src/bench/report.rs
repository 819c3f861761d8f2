//! What `bench rays` measured: every figure as data (serialisable to JSON), the figures derived
//! from measurements of the same run (backend ratios, packet gains, thread scaling), and a
//! plain-text table for people.

use super::structure::Method;
use super::timing::{Rate, Runs, Timing};
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
    pub backend: String,
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
    /// Seconds per run.
    pub seconds: Timing,
    /// Millions of rays per second.
    pub mrays_per_s: Rate,
}

/// One build setting of one backend: how long it takes to build and what its trees give.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BuildReport {
    /// Backend name.
    pub backend: String,
    /// `low`, `medium` or `high`.
    pub quality: String,
    /// Embree's robust flag (always false for obvhs, which has none).
    pub robust: bool,
    /// Whether this is the default setting (`BuildOptions::default()`), the one the full
    /// query matrix was measured on.
    pub is_default: bool,
    /// Build time, seconds.
    pub build_s: Timing,
    /// Both workloads and both queries, with the most threads and the backend's default
    /// method (what `Accel::intersect_many` uses).
    pub queries: Vec<QueryReport>,
}

/// Whether occlusion agrees with the closest hits of the same rays: a ray is occluded exactly
/// when its closest hit (over `[tnear, ∞)`) lies no farther than the occlusion ray's `tfar`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ConsistencyReport {
    /// Backend name.
    pub backend: String,
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
    /// Median Embree Mrays/s over median obvhs Mrays/s.
    pub ratio: f64,
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
    /// Median packet Mrays/s over median single-ray Mrays/s (> 1: packets win).
    pub packet8_over_single: f64,
}

/// How throughput grows from one thread to many.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ScalingReport {
    /// Backend name.
    pub backend: String,
    /// Single rays or packets.
    pub method: Method,
    /// Coherent or incoherent rays.
    pub workload: Workload,
    /// Closest hit or occlusion.
    pub query: Query,
    /// The larger thread count.
    pub threads: usize,
    /// Median Mrays/s with `threads` over median Mrays/s with one.
    pub speedup: f64,
    /// `speedup / threads`: 1 is perfect scaling.
    pub efficiency: f64,
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
    /// Warm-up and timed runs (at most) per query figure.
    pub runs: Runs,
    /// Runs (at most) per build figure.
    pub build_runs: Runs,
    /// Per scene.
    pub scenes: Vec<SceneReport>,
}

/// Key that identifies a measurement apart from its backend and method.
fn same_rays(a: &QueryReport, b: &QueryReport) -> bool {
    a.workload == b.workload && a.query == b.query && a.threads == b.threads
}

/// Embree (each method) over obvhs for every workload, query and thread count measured on
/// both.
pub fn embree_over_bvh(queries: &[QueryReport]) -> Vec<RatioReport> {
    queries
        .iter()
        .filter(|q| q.backend == "embree")
        .filter_map(|embree| {
            let bvh = queries
                .iter()
                .find(|q| q.backend == "bvh" && same_rays(q, embree))?;
            Some(RatioReport {
                method: embree.method,
                workload: embree.workload,
                query: embree.query,
                threads: embree.threads,
                ratio: embree.mrays_per_s.median / bvh.mrays_per_s.median,
            })
        })
        .collect()
}

/// Embree's packets over its single rays for every workload, query and thread count.
pub fn packet_gains(queries: &[QueryReport]) -> Vec<PacketGainReport> {
    let embree = |method: Method| {
        queries
            .iter()
            .filter(move |q| q.backend == "embree" && q.method == method)
    };
    embree(Method::Packet8)
        .filter_map(|packet| {
            let single = embree(Method::Single).find(|q| same_rays(q, packet))?;
            Some(PacketGainReport {
                workload: packet.workload,
                query: packet.query,
                threads: packet.threads,
                packet8_over_single: packet.mrays_per_s.median / single.mrays_per_s.median,
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
            let speedup = many.mrays_per_s.median / one.mrays_per_s.median;
            Some(ScalingReport {
                backend: many.backend.clone(),
                method: many.method,
                workload: many.workload,
                query: many.query,
                threads: many.threads,
                speedup,
                efficiency: speedup / many.threads as f64,
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

/// "5 runs", or "up to 5 runs (fewer once a query's runs reach 2 s)".
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
             Each figure: median (min–max) of {}; queries after {} discarded warm-up run(s).",
            self.glint_version,
            self.available_threads,
            self.threads,
            describe_runs("query", &self.runs),
            self.runs.warmup,
        );
        let _ = writeln!(
            out,
            "Builds: median (min–max) of {}.",
            describe_runs("build", &self.build_runs)
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
             incoherent rays",
            self.name,
            self.triangles,
            self.camera_rays,
            run.width,
            run.height,
            self.camera,
            self.random_rays,
        );

        let _ = writeln!(
            out,
            "\nBuild settings: build seconds, then Mrays/s with {widest} threads and the \
             backend's intersect_many method (embree: packet8, bvh: single)"
        );
        let _ = writeln!(
            out,
            "{:<7} {:<7} {:<6} {:<22} {:>4} {:<22} {:<22} {:<22} {:<22}",
            "backend",
            "quality",
            "robust",
            "build s",
            "runs",
            "coherent closest",
            "coherent occluded",
            "incoherent closest",
            "incoherent occluded"
        );
        for build in &self.builds {
            let rate = |w: Workload, q: Query| {
                build
                    .queries
                    .iter()
                    .find(|r| r.workload == w && r.query == q)
                    .map_or("-".to_string(), |r| fmt_rate(&r.mrays_per_s))
            };
            let _ = writeln!(
                out,
                "{:<7} {:<7} {:<6} {:<22} {:>4} {:<22} {:<22} {:<22} {:<22}",
                build.backend,
                build.quality,
                if build.robust { "yes" } else { "no" },
                fmt_timing(&build.build_s),
                build.build_s.runs,
                rate(Workload::Coherent, Query::Closest),
                rate(Workload::Coherent, Query::Occluded),
                rate(Workload::Incoherent, Query::Closest),
                rate(Workload::Incoherent, Query::Occluded),
            );
        }

        let default_build = self
            .builds
            .iter()
            .find(|b| b.is_default)
            .map_or("the default", |b| b.quality.as_str());
        let _ = writeln!(
            out,
            "\nQueries on the {default_build} build (not robust): Mrays/s per thread count, \
             scaling = speed-up / threads"
        );
        let mut header = format!(
            "{:<7} {:<7} {:<10} {:<8}",
            "backend", "method", "workload", "query"
        );
        for threads in &run.threads {
            let _ = write!(header, " {:<22}", format!("{threads} thread(s)"));
        }
        let _ = writeln!(out, "{header} {:<8} {:>9}", "scaling", "positives");
        for first in self.queries.iter().filter(|q| q.threads == 1) {
            let mut line = format!(
                "{:<7} {:<7} {:<10} {:<8}",
                first.backend,
                first.method.name(),
                first.workload.name(),
                first.query.name()
            );
            for &threads in &run.threads {
                let cell = self
                    .queries
                    .iter()
                    .find(|q| {
                        q.threads == threads
                            && q.backend == first.backend
                            && q.method == first.method
                            && q.workload == first.workload
                            && q.query == first.query
                    })
                    .map_or("-".to_string(), |q| fmt_rate(&q.mrays_per_s));
                let _ = write!(line, " {cell:<22}");
            }
            let scaling = self
                .scaling
                .iter()
                .find(|s| {
                    s.backend == first.backend
                        && s.method == first.method
                        && s.workload == first.workload
                        && s.query == first.query
                })
                .map_or("-".to_string(), |s| format!("{:.0}%", 100.0 * s.efficiency));
            let _ = writeln!(out, "{line} {scaling:<8} {:>9}", first.positives);
        }

        if !self.embree_over_bvh.is_empty() {
            let _ = writeln!(
                out,
                "\nSame-run ratios: Embree over obvhs (single rays, packets), and Embree's \
                 packets over its single rays"
            );
            let _ = writeln!(
                out,
                "{:<10} {:<8} {:<7} {:>14} {:>15} {:>16}",
                "workload", "query", "threads", "single/obvhs", "packet8/obvhs", "packet8/single"
            );
            for gain in &self.packet_gains {
                let ratio = |method: Method| {
                    self.embree_over_bvh
                        .iter()
                        .find(|r| {
                            r.method == method
                                && r.workload == gain.workload
                                && r.query == gain.query
                                && r.threads == gain.threads
                        })
                        .map_or("-".to_string(), |r| format!("{:.2}×", r.ratio))
                };
                let _ = writeln!(
                    out,
                    "{:<10} {:<8} {:<7} {:>14} {:>15} {:>16}",
                    gain.workload.name(),
                    gain.query.name(),
                    gain.threads,
                    ratio(Method::Single),
                    ratio(Method::Packet8),
                    format!("{:.2}×", gain.packet8_over_single),
                );
            }
        }

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

    fn query(backend: &str, method: Method, threads: usize, mrays: f64) -> QueryReport {
        let seconds = Timing::from_samples(&[1.0 / mrays]).unwrap();
        QueryReport {
            backend: backend.into(),
            method,
            workload: Workload::Coherent,
            query: Query::Closest,
            threads,
            rays: 1_000_000,
            positives: 10,
            seconds,
            mrays_per_s: seconds.rate(1.0),
        }
    }

    #[test]
    fn derived_figures_divide_the_matching_medians() {
        let queries = [
            query("embree", Method::Single, 1, 10.0),
            query("embree", Method::Packet8, 1, 30.0),
            query("embree", Method::Single, 2, 16.0),
            query("embree", Method::Packet8, 2, 60.0),
            query("bvh", Method::Single, 1, 2.0),
            query("bvh", Method::Single, 2, 4.0),
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
        assert!((ratio(Method::Packet8, 2) - 15.0).abs() < 1e-9);

        let gains = packet_gains(&queries);
        assert_eq!(gains.len(), 2);
        assert!((gains[0].packet8_over_single - 3.0).abs() < 1e-9);
        assert!((gains[1].packet8_over_single - 3.75).abs() < 1e-9);

        let scaling = scaling(&queries);
        assert_eq!(scaling.len(), 3);
        let embree_single = &scaling[0];
        assert_eq!(
            (embree_single.backend.as_str(), embree_single.method),
            ("embree", Method::Single)
        );
        assert!((embree_single.speedup - 1.6).abs() < 1e-9);
        assert!((embree_single.efficiency - 0.8).abs() < 1e-9);
        assert!((scaling[2].efficiency - 1.0).abs() < 1e-9);
    }

    #[test]
    fn sig3_keeps_three_significant_digits() {
        assert_eq!(sig3(123.456), "123");
        assert_eq!(sig3(12.345), "12.3");
        assert_eq!(sig3(1.2345), "1.23");
        assert_eq!(sig3(0.012345), "0.012");
    }
}
