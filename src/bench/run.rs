//! `bench rays`: build every backend at every build setting over each scene, and trace the
//! same coherent and incoherent rays through each, with one thread and with all.

use super::rays::{self, Bounds};
use super::report::{
    self, BuildReport, ConsistencyReport, Query, QueryReport, RaysReport, SceneReport, Workload,
};
use super::scene::BenchScene;
use super::structure::{Method, Structure};
use super::timing::{Runs, measure};
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
    /// Height of the camera-ray image, pixels. The incoherent workload traces as many random
    /// rays as the image has pixels, so both workloads count the same rays.
    pub height: u32,
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

/// Time budget of one ray-query figure in [`RaysConfig::full`], seconds: five runs of
/// 786k rays fit in it down to about 2 Mrays/s; slower figures (obvhs, incoherent, one
/// thread) get fewer runs.
const QUERY_BUDGET_S: f64 = 2.0;

/// Time budget of one build figure in [`RaysConfig::full`], seconds: enough for five runs of
/// every Embree setting over a million triangles, while obvhs's slowest preset (tens of
/// seconds on two cores) gets one.
const BUILD_BUDGET_S: f64 = 8.0;

impl RaysConfig {
    /// The benchmark proper: 1024 × 768 rays per figure; five timed runs after one warm-up,
    /// fewer for figures that exceed their time budget; one thread per hardware thread.
    pub fn full() -> Self {
        Self {
            width: 1024,
            height: 768,
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

    /// A smoke test: 64 × 48 rays, one run without warm-up.
    pub fn quick() -> Self {
        Self {
            width: 64,
            height: 48,
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

    /// Rays per measurement.
    pub fn ray_count(&self) -> usize {
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
            .start_handler(|_| {
                #[cfg(feature = "embree")]
                crate::accel::embree::set_denormal_modes();
            })
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
            robust_flags
                .iter()
                .map(move |&robust| BuildOptions { quality, robust })
        })
        .collect()
}

/// The rays of one scene and the buffers their answers go to.
struct Workloads {
    camera: Vec<Ray>,
    random: Vec<Ray>,
    /// `random` cut to finite lengths, for occlusion.
    random_segments: Vec<Ray>,
    hits: Vec<Option<Hit>>,
    occluded: Vec<bool>,
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

/// One backend's built structure and what is being measured on it.
struct Subject<'a> {
    structure: &'a Structure,
    kind: BackendKind,
    runs: Runs,
}

impl Subject<'_> {
    /// Times one query of one workload with `method` on `pool`; the answers stay in `work`'s
    /// buffers for the caller to check.
    fn trace(
        &self,
        method: Method,
        workload: Workload,
        query: Query,
        work: &mut Workloads,
        pool: &Pool,
    ) -> QueryReport {
        let coherence = match workload {
            Workload::Coherent => Coherence::Coherent,
            Workload::Incoherent => Coherence::Incoherent,
        };
        // Split the borrows: the rays are read while the answers are written.
        let Workloads {
            camera,
            random,
            random_segments,
            hits,
            occluded,
        } = work;
        let rays = match (workload, query) {
            (Workload::Coherent, _) => camera,
            (Workload::Incoherent, Query::Closest) => random,
            (Workload::Incoherent, Query::Occluded) => random_segments,
        };
        let structure = self.structure;
        let (timing, positives) = match query {
            Query::Closest => {
                let hits = &mut hits[..rays.len()];
                let timed = pool.pool.install(|| {
                    measure(self.runs, || {
                        structure.closest(method, rays, hits, coherence)
                    })
                });
                (timed.timing, hits.iter().filter(|h| h.is_some()).count())
            }
            Query::Occluded => {
                let out = &mut occluded[..rays.len()];
                let timed = pool.pool.install(|| {
                    measure(self.runs, || {
                        structure.occluded(method, rays, out, coherence)
                    })
                });
                (timed.timing, out.iter().filter(|&&o| o).count())
            }
        };
        QueryReport {
            backend: self.kind.name().to_string(),
            method,
            workload,
            query,
            threads: pool.threads,
            rays: rays.len(),
            positives,
            seconds: timing,
            mrays_per_s: timing.rate(rays.len() as f64).in_millions(),
        }
    }

    /// Every method, workload, query and thread count; and, per method and workload, the
    /// check that occlusion agrees with the closest hits of the same rays.
    fn trace_matrix(
        &self,
        work: &mut Workloads,
        pools: &Pools,
    ) -> (Vec<QueryReport>, Vec<ConsistencyReport>) {
        let mut queries = Vec::new();
        let mut checks = Vec::new();
        for &method in self.structure.methods() {
            for workload in Workload::ALL {
                let mut check = ConsistencyReport {
                    backend: self.kind.name().to_string(),
                    method,
                    workload,
                    rays: work.rays(workload, Query::Closest).len(),
                    closest_hits: 0,
                    closest_hits_within_tfar: 0,
                    occluded: 0,
                };
                for pool in pools.iter() {
                    let closest = self.trace(method, workload, Query::Closest, work, pool);
                    // What occlusion must find: the closest hits no farther than the
                    // occlusion ray's end.
                    check.closest_hits = closest.positives;
                    check.closest_hits_within_tfar = work
                        .hits
                        .iter()
                        .zip(work.rays(workload, Query::Occluded))
                        .filter(|(hit, ray)| hit.is_some_and(|h| h.t <= ray.tfar))
                        .count();
                    queries.push(closest);
                    let occluded = self.trace(method, workload, Query::Occluded, work, pool);
                    check.occluded = occluded.positives;
                    queries.push(occluded);
                }
                checks.push(check);
            }
        }
        (queries, checks)
    }
}

/// Builds a one-triangle structure, so that a backend's one-time start-up (Embree creates its
/// device and thread pool on first use) is not counted in the first timed build.
fn warm_up_backend(kind: BackendKind, scene: &BenchScene, pool: &Pool) -> Result<(), BenchError> {
    let positions = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let indices = [[0, 1, 2]];
    let triangle = [TriangleMesh {
        positions: &positions,
        indices: &indices,
    }];
    pool.pool
        .install(|| Structure::build(kind, &triangle, BuildOptions::default()))
        .map(drop)
        .map_err(|source| BenchError::Build {
            scene: scene.name.clone(),
            backend: kind,
            source,
        })
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
    let n = config.ray_count();
    let mut work = Workloads {
        camera: rays::camera_rays(&camera, config.width, config.height),
        random: rays::random_rays(&bounds, n, config.seed),
        random_segments: rays::random_segments(&bounds, n, config.seed),
        hits: vec![None; n],
        occluded: vec![false; n],
    };
    let widest = pools.widest();
    let mut builds = Vec::new();
    let mut queries = Vec::new();
    let mut consistency = Vec::new();
    for &kind in BackendKind::available() {
        for options in build_variants(kind) {
            let label = format!(
                "{name}: {kind} {}{}",
                options.quality.name(),
                if options.robust { " robust" } else { "" }
            );
            if options == build_variants(kind)[0] {
                warm_up_backend(kind, scene, widest)?;
            }
            progress(&format!("{label}: building"));
            // obvhs builds on the current rayon pool, so on the widest; Embree on its own
            // threads, one per hardware thread, whatever the pool.
            let built = widest.pool.install(|| {
                measure(config.build_runs, || {
                    Structure::build(kind, &meshes, options)
                })
            });
            let structure = built.last.map_err(|source| BenchError::Build {
                scene: name.clone(),
                backend: kind,
                source,
            })?;
            let subject = Subject {
                structure: &structure,
                kind,
                runs: config.runs,
            };
            let method = structure.default_method();
            let is_default = options == BuildOptions::default();
            let trade = if is_default {
                progress(&format!(
                    "{label}: tracing every method with {:?} threads",
                    config.thread_counts()
                ));
                let (matrix, checks) = subject.trace_matrix(&mut work, pools);
                let trade = matrix
                    .iter()
                    .filter(|q| q.method == method && q.threads == widest.threads)
                    .cloned()
                    .collect();
                queries.extend(matrix);
                consistency.extend(checks);
                trade
            } else {
                progress(&format!("{label}: tracing"));
                Workload::ALL
                    .into_iter()
                    .flat_map(|w| Query::ALL.into_iter().map(move |q| (w, q)))
                    .map(|(w, q)| subject.trace(method, w, q, &mut work, widest))
                    .collect()
            };
            builds.push(BuildReport {
                backend: kind.name().to_string(),
                quality: options.quality.name().to_string(),
                robust: options.robust,
                is_default,
                build_s: built.timing,
                queries: trade,
            });
        }
    }
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
