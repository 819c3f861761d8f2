//! `bench rays`: build every backend at every build setting over each scene, and trace the
//! same coherent and incoherent rays through each, with one thread and with all.

use super::rays::{self, Bounds};
use super::report::{
    self, BuildReport, ConsistencyReport, Query, QueryReport, RaysReport, SceneReport, Workload,
};
use super::scene::BenchScene;
use super::structure::{Method, Structure};
use super::timing::{Runs, Timing, measure_interleaved};
use crate::accel::{
    self, AccelError, BackendKind, BuildOptions, BuildQuality, Coherence, Hit, Ray, TriangleMesh,
};
use glam::Vec3;
use rayon::ThreadPool;

/// Seed of the random rays: fixed, so every run and every machine traces the same rays.
pub const RAY_SEED: u64 = 0x0067_6c69_6e74;

/// What to measure and how often.
#[derive(Clone, Debug, PartialEq)]
pub struct RaysConfig {
    /// Width of the camera-ray image, pixels.
    pub width: u32,
    /// Height of the camera-ray image, pixels.
    pub height: u32,
    /// Random rays of the incoherent workload.
    pub random_rays: usize,
    /// Warm-up and timed runs of every ray query.
    pub runs: Runs,
    /// Runs of every build. Builds need no warm-up of their own: each starts from fresh
    /// memory, and the backend's one-time start-up (Embree's device and threads) is done by a
    /// tiny build before any is timed.
    pub build_runs: Runs,
    /// The larger thread count (the smaller is always 1).
    pub threads: usize,
    /// Seed of the random rays.
    pub seed: u64,
}

/// Random rays in [`RaysConfig::full`]: 2¹⁸, fewer than the 786k camera rays because
/// incoherent rays are several times slower (obvhs traces some built-ins' at 0.1–0.2 Mrays per
/// CPU-second), and the whole default run should take minutes, not a quarter of an hour.
const FULL_RANDOM_RAYS: usize = 1 << 18;

/// Time budget of one ray-query figure in [`RaysConfig::full`], seconds: five runs fit in it
/// down to about 2 Mrays/s for the camera rays; slower figures get fewer runs.
const QUERY_BUDGET_S: f64 = 2.0;

/// Time budget of one build figure in [`RaysConfig::full`], seconds: enough for five runs of
/// every Embree setting over a million triangles, while obvhs's slowest preset (tens of
/// seconds on two cores) gets one.
const BUILD_BUDGET_S: f64 = 8.0;

impl RaysConfig {
    /// The benchmark proper: 1024 × 768 camera rays and 2¹⁸ random rays per figure; five
    /// timed runs after one warm-up, fewer for figures that exceed their time budget; one
    /// thread per hardware thread.
    pub fn full() -> Self {
        Self {
            width: 1024,
            height: 768,
            random_rays: FULL_RANDOM_RAYS,
            runs: Runs {
                warmup: 1,
                timed: 5,
                budget_s: Some(QUERY_BUDGET_S),
            },
            build_runs: Runs {
                warmup: 0,
                timed: 5,
                budget_s: Some(BUILD_BUDGET_S),
            },
            threads: available_threads(),
            seed: RAY_SEED,
        }
    }

    /// A smoke test: 64 × 48 camera rays and 2048 random rays, one run without warm-up.
    pub fn quick() -> Self {
        Self {
            width: 64,
            height: 48,
            random_rays: 2048,
            runs: Runs::exactly(0, 1),
            build_runs: Runs::exactly(0, 1),
            ..Self::full()
        }
    }

    /// Sets the number of timed runs of queries and builds alike.
    pub fn with_timed_runs(mut self, timed: usize) -> Self {
        self.runs.timed = timed;
        self.build_runs.timed = timed;
        self
    }

    /// Camera rays per measurement.
    pub fn camera_ray_count(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// The thread counts measured: 1 and [`Self::threads`] (just 1 if that is 1).
    pub fn thread_counts(&self) -> Vec<usize> {
        if self.threads > 1 {
            vec![1, self.threads]
        } else {
            vec![1]
        }
    }
}

/// Hardware threads of this machine (1 if unknown).
pub fn available_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Why a benchmark could not run.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The scene has no triangles.
    #[error("scene {scene}: it has no triangles to trace; pass a scene with at least one mesh")]
    EmptyScene {
        /// Scene name.
        scene: String,
    },
    /// The scene's geometry would make a backend misbehave.
    #[error("scene {scene}: {source}; fix the mesh in the scene file")]
    InvalidGeometry {
        /// Scene name.
        scene: String,
        /// What is wrong.
        source: AccelError,
    },
    /// The scene's camera cannot make rays for the image.
    #[error("scene {scene}: its camera is unusable: {reason}; fix the camera or the image size")]
    Camera {
        /// Scene name.
        scene: String,
        /// What is wrong.
        reason: String,
    },
    /// A backend failed to build.
    #[error("scene {scene}: building the {backend} structure failed: {source}")]
    Build {
        /// Scene name.
        scene: String,
        /// The backend.
        backend: BackendKind,
        /// The backend's error.
        source: AccelError,
    },
    /// The rayon pool could not be started.
    #[error("could not start {threads} worker threads: {source}; try a smaller --threads")]
    ThreadPool {
        /// Threads asked for.
        threads: usize,
        /// rayon's error.
        source: rayon::ThreadPoolBuildError,
    },
}

/// A rayon pool and its size.
struct Pool {
    threads: usize,
    pool: ThreadPool,
}

/// The pools measured: one thread, and optionally more.
struct Pools {
    one: Pool,
    many: Option<Pool>,
}

impl Pools {
    fn new(config: &RaysConfig) -> Result<Self, BenchError> {
        let many = if config.threads > 1 {
            Some(Pool::new(config.threads)?)
        } else {
            None
        };
        Ok(Self {
            one: Pool::new(1)?,
            many,
        })
    }

    /// The pools, fewest threads first.
    fn iter(&self) -> impl Iterator<Item = &Pool> {
        std::iter::once(&self.one).chain(self.many.as_ref())
    }

    /// The pool with the most threads.
    fn widest(&self) -> &Pool {
        self.many.as_ref().unwrap_or(&self.one)
    }
}

impl Pool {
    /// A pool of `threads` workers, each set up as Embree asks of every thread that traces.
    fn new(threads: usize) -> Result<Self, BenchError> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(move |i| format!("glint-bench-{threads}-{i}"))
            // Every backend is timed on the same pools, so all workers run in Embree's
            // floating-point modes (a no-op without the embree feature).
            .start_handler(|_| crate::accel::BackendKind::Embree.prepare_worker_thread())
            .build()
            .map_err(|source| BenchError::ThreadPool { threads, source })?;
        Ok(Self { threads, pool })
    }
}

/// Benchmarks `scenes` with every backend compiled in. `progress` receives one line per step
/// (for stderr); the figures are all in the report.
pub fn run_rays(
    scenes: &[BenchScene],
    config: &RaysConfig,
    progress: &mut dyn FnMut(&str),
) -> Result<RaysReport, BenchError> {
    let pools = Pools::new(config)?;
    let scenes = scenes
        .iter()
        .map(|scene| bench_scene(scene, config, &pools, progress))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(RaysReport {
        glint_version: env!("CARGO_PKG_VERSION").to_string(),
        embree_version: embree_version(),
        unix_time_s: std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs()),
        available_threads: available_threads(),
        threads: config.thread_counts(),
        width: config.width,
        height: config.height,
        random_rays: config.random_rays,
        runs: config.runs,
        build_runs: config.build_runs,
        scenes,
    })
}

fn embree_version() -> Option<String> {
    #[cfg(feature = "embree")]
    {
        Some(crate::accel::embree::embree_version())
    }
    #[cfg(not(feature = "embree"))]
    {
        None
    }
}

/// The build settings measured for a backend: every quality, and for Embree each with and
/// without the robust flag (obvhs has none).
pub fn build_variants(kind: BackendKind) -> Vec<BuildOptions> {
    let robust_flags: &[bool] = match kind {
        BackendKind::Embree => &[false, true],
        BackendKind::Bvh => &[false],
    };
    BuildQuality::ALL
        .iter()
        .flat_map(|&quality| {
            robust_flags.iter().map(move |&robust| BuildOptions {
                quality,
                robust,
                embree_isa: None,
            })
        })
        .collect()
}

/// The rays of one scene.
struct Workloads {
    camera: Vec<Ray>,
    random: Vec<Ray>,
    /// `random` cut to finite lengths, for occlusion.
    random_segments: Vec<Ray>,
}

impl Workloads {
    /// The rays a query of a workload traces: camera rays over `[0, ∞)` for both coherent
    /// queries; for incoherent ones, random rays for closest hits and the same rays cut short
    /// for occlusion (shadow rays have an end).
    fn rays(&self, workload: Workload, query: Query) -> &[Ray] {
        match (workload, query) {
            (Workload::Coherent, _) => &self.camera,
            (Workload::Incoherent, Query::Closest) => &self.random,
            (Workload::Incoherent, Query::Occluded) => &self.random_segments,
        }
    }
}

/// A structure built with one setting, and how long building it took.
struct Built {
    kind: BackendKind,
    options: BuildOptions,
    structure: Structure,
    build_s: Timing,
    build_cpu_s: Option<Timing>,
}

/// One way to trace rays: a built structure, a method, and the pool to trace on.
#[derive(Clone, Copy)]
struct Tracer<'a> {
    built: &'a Built,
    method: Method,
    pool: &'a Pool,
}

/// What one tracer answered in one batch.
struct Traced {
    report: QueryReport,
    /// For closest hits: how many lie within the `tfar` of the workload's occlusion rays.
    hits_within_occlusion_tfar: Option<usize>,
}

/// Traces one workload's query with every tracer, interleaved run by run (see
/// [`measure_interleaved`]) so that the ratios between them survive a noisy machine.
fn trace_batch(
    tracers: &[Tracer<'_>],
    workload: Workload,
    query: Query,
    work: &Workloads,
    runs: Runs,
) -> Vec<Traced> {
    let rays = work.rays(workload, query);
    let coherence = match workload {
        Workload::Coherent => Coherence::Coherent,
        Workload::Incoherent => Coherence::Incoherent,
    };
    // Every tracer answers into its own buffer, counted once the timing is over.
    let (timings, positives, within) = match query {
        Query::Closest => {
            let mut buffers = vec![vec![None::<Hit>; rays.len()]; tracers.len()];
            let mut works: Vec<Box<dyn FnMut() + '_>> = tracers
                .iter()
                .zip(buffers.iter_mut())
                .map(|(tracer, hits)| {
                    let tracer = *tracer;
                    Box::new(move || {
                        tracer.pool.pool.install(|| {
                            tracer
                                .built
                                .structure
                                .closest(tracer.method, rays, hits, coherence)
                        })
                    }) as Box<dyn FnMut()>
                })
                .collect();
            let timings = measure_interleaved(runs, &mut works);
            drop(works);
            let occlusion_rays = work.rays(workload, Query::Occluded);
            let positives = buffers
                .iter()
                .map(|hits| hits.iter().filter(|h| h.is_some()).count())
                .collect::<Vec<_>>();
            let within = buffers
                .iter()
                .map(|hits| {
                    Some(
                        hits.iter()
                            .zip(occlusion_rays)
                            .filter(|(hit, ray)| hit.is_some_and(|h| h.t <= ray.tfar))
                            .count(),
                    )
                })
                .collect::<Vec<_>>();
            (timings, positives, within)
        }
        Query::Occluded => {
            let mut buffers = vec![vec![false; rays.len()]; tracers.len()];
            let mut works: Vec<Box<dyn FnMut() + '_>> = tracers
                .iter()
                .zip(buffers.iter_mut())
                .map(|(tracer, out)| {
                    let tracer = *tracer;
                    Box::new(move || {
                        tracer.pool.pool.install(|| {
                            tracer
                                .built
                                .structure
                                .occluded(tracer.method, rays, out, coherence)
                        })
                    }) as Box<dyn FnMut()>
                })
                .collect();
            let timings = measure_interleaved(runs, &mut works);
            drop(works);
            let positives = buffers
                .iter()
                .map(|out| out.iter().filter(|&&o| o).count())
                .collect::<Vec<_>>();
            (timings, positives, vec![None; tracers.len()])
        }
    };
    tracers
        .iter()
        .zip(timings)
        .zip(positives.into_iter().zip(within))
        .map(|((tracer, timed), (positives, within))| Traced {
            report: QueryReport::new(
                tracer.built.kind,
                tracer.method,
                workload,
                query,
                tracer.pool.threads,
                rays.len(),
                positives,
                timed.timing,
                timed.cpu,
            ),
            hits_within_occlusion_tfar: within,
        })
        .collect()
}

/// Builds a one-triangle structure, so that a backend's one-time start-up (Embree creates its
/// device and thread pool on first use) is not counted in the first timed build.
fn warm_up_backend(kind: BackendKind, scene: &BenchScene) -> Result<(), BenchError> {
    let positions = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let indices = [[0, 1, 2]];
    let triangle = [TriangleMesh {
        positions: &positions,
        indices: &indices,
        instances: &[],
    }];
    Structure::build(kind, &triangle, BuildOptions::default())
        .map(drop)
        .map_err(|source| BenchError::Build {
            scene: scene.name.clone(),
            backend: kind,
            source,
        })
}

/// Builds every setting of every backend, interleaved run by run, on the widest pool (obvhs
/// builds on the current rayon pool; Embree on its own threads, one per hardware thread).
fn build_all(
    scene: &BenchScene,
    meshes: &[TriangleMesh<'_>],
    config: &RaysConfig,
    pools: &Pools,
) -> Result<Vec<Built>, BenchError> {
    let variants: Vec<(BackendKind, BuildOptions)> = BackendKind::available()
        .iter()
        .flat_map(|&kind| build_variants(kind).into_iter().map(move |o| (kind, o)))
        .collect();
    for &kind in BackendKind::available() {
        warm_up_backend(kind, scene)?;
    }
    let mut works: Vec<_> = variants
        .iter()
        .map(|&(kind, options)| move || Structure::build(kind, meshes, options))
        .collect();
    let timed = pools
        .widest()
        .pool
        .install(|| measure_interleaved(config.build_runs, &mut works));
    variants
        .iter()
        .zip(timed)
        .map(|(&(kind, options), timed)| {
            let structure = timed.last.map_err(|source| BenchError::Build {
                scene: scene.name.clone(),
                backend: kind,
                source,
            })?;
            Ok(Built {
                kind,
                options,
                structure,
                build_s: timed.timing,
                build_cpu_s: timed.cpu,
            })
        })
        .collect()
}

fn bench_scene(
    scene: &BenchScene,
    config: &RaysConfig,
    pools: &Pools,
    progress: &mut dyn FnMut(&str),
) -> Result<SceneReport, BenchError> {
    let name = &scene.name;
    let meshes = scene.triangle_meshes();
    accel::validate(&meshes).map_err(|source| BenchError::InvalidGeometry {
        scene: name.clone(),
        source,
    })?;
    let bounds = Bounds::of_meshes(&meshes)
        .filter(|_| scene.triangle_count() > 0)
        .ok_or_else(|| BenchError::EmptyScene {
            scene: name.clone(),
        })?;
    let camera = scene.camera.clone().unwrap_or_else(|| {
        let vertices = meshes.iter().flat_map(|m| m.positions.iter().copied());
        rays::framing_camera(&bounds, vertices)
    });
    let work = Workloads {
        camera: rays::camera_rays(&camera, config.width, config.height).map_err(|reason| {
            BenchError::Camera {
                scene: name.clone(),
                reason,
            }
        })?,
        random: rays::random_rays(&bounds, config.random_rays, config.seed),
        random_segments: rays::random_segments(&bounds, config.random_rays, config.seed),
    };

    let variants: usize = BackendKind::available()
        .iter()
        .map(|&k| build_variants(k).len())
        .sum();
    progress(&format!(
        "{name}: building {variants} settings, interleaved"
    ));
    let builds = build_all(scene, &meshes, config, pools)?;

    // What each build setting gives: every query with the most threads and the backend's
    // default method, all settings interleaved.
    progress(&format!("{name}: tracing every build setting"));
    let widest = pools.widest();
    let trade_tracers: Vec<Tracer<'_>> = builds
        .iter()
        .map(|built| Tracer {
            built,
            method: built.structure.default_method(),
            pool: widest,
        })
        .collect();
    let mut trade: Vec<Vec<QueryReport>> = vec![Vec::new(); builds.len()];
    for workload in Workload::ALL {
        for query in Query::ALL {
            let traced = trace_batch(&trade_tracers, workload, query, &work, config.runs);
            for (rows, traced) in trade.iter_mut().zip(traced) {
                rows.push(traced.report);
            }
        }
    }

    // The full matrix on the default builds: every method and thread count, interleaved.
    progress(&format!(
        "{name}: tracing every method with {:?} threads",
        config.thread_counts()
    ));
    let matrix_tracers: Vec<Tracer<'_>> = builds
        .iter()
        .filter(|b| b.options == BuildOptions::default())
        .flat_map(|built| {
            built.structure.methods().iter().flat_map(move |&method| {
                pools.iter().map(move |pool| Tracer {
                    built,
                    method,
                    pool,
                })
            })
        })
        .collect();
    let mut queries = Vec::new();
    let mut consistency = Vec::new();
    for workload in Workload::ALL {
        let closest = trace_batch(
            &matrix_tracers,
            workload,
            Query::Closest,
            &work,
            config.runs,
        );
        let occluded = trace_batch(
            &matrix_tracers,
            workload,
            Query::Occluded,
            &work,
            config.runs,
        );
        for (tracer, (closest, occluded)) in
            matrix_tracers.iter().zip(closest.iter().zip(&occluded))
        {
            // One check per backend and method: the answers do not depend on the pool.
            if tracer.pool.threads == 1 {
                consistency.push(ConsistencyReport {
                    backend: tracer.built.kind,
                    method: tracer.method,
                    workload,
                    rays: closest.report.rays,
                    closest_hits: closest.report.positives,
                    closest_hits_within_tfar: closest.hits_within_occlusion_tfar.unwrap_or(0),
                    occluded: occluded.report.positives,
                });
            }
        }
        queries.extend(closest.into_iter().map(|t| t.report));
        queries.extend(occluded.into_iter().map(|t| t.report));
    }

    let builds = builds
        .iter()
        .zip(trade)
        .map(|(built, queries)| BuildReport {
            backend: built.kind,
            quality: built.options.quality.name().to_string(),
            robust: built.options.robust,
            is_default: built.options == BuildOptions::default(),
            build_s: built.build_s,
            build_cpu_s: built.build_cpu_s,
            queries,
        })
        .collect();
    Ok(SceneReport {
        embree_over_bvh: report::embree_over_bvh(&queries),
        packet_gains: report::packet_gains(&queries),
        scaling: report::scaling(&queries),
        name: name.clone(),
        triangles: scene.triangle_count(),
        camera: camera.name.clone(),
        bounds_min: bounds.min.to_array(),
        bounds_max: bounds.max.to_array(),
        camera_rays: work.camera.len(),
        random_rays: work.random.len(),
        builds,
        queries,
        consistency,
    })
}
