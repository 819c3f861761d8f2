//! The renderer's own ray mix, recorded and replayed raw (`glint bench render --integrator
//! path`).
//!
//! A path tracer's rays are not a fixed pattern that a synthetic trace could imitate: bounce
//! directions follow the BSDFs, shadow rays the light sampler, Russian roulette ends paths.
//! So the benchmark records them. [`RecordingAccel`] wraps the scene's [`Accel`] and keeps
//! every batch a render asks of it (closest-hit or occlusion, coherent or not, the rays
//! themselves); [`replay`] then traces exactly those batches again with no shading, on the
//! same threads. The renderer's end-to-end rays per second over the replay's is the share of
//! time spent tracing: what shading, sampling and bookkeeping cost on top of the rays.

use crate::accel::{Accel, BackendKind, Coherence, Hit, Ray};
use rayon::prelude::*;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Rays a recording keeps at most (32 bytes each: 512 MiB); a render that traces more is
/// reported as too large rather than recorded in part.
pub const MAX_RECORDED_RAYS: usize = 1 << 24;

/// What a recorded batch asked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Query {
    /// Closest hit (camera and bounce rays).
    Closest,
    /// Any hit (shadow rays).
    Any,
}

/// One batch of rays as the renderer traced it.
#[derive(Clone, Debug)]
pub struct RecordedBatch {
    /// Closest or any hit.
    pub query: Query,
    /// The coherence hint the renderer gave.
    pub coherence: Coherence,
    /// The rays.
    pub rays: Vec<Ray>,
}

/// An [`Accel`] that answers through another and records every query.
pub struct RecordingAccel<'a> {
    inner: &'a dyn Accel,
    batches: Mutex<Vec<RecordedBatch>>,
    rays: AtomicUsize,
    overflowed: AtomicBool,
}

impl<'a> RecordingAccel<'a> {
    /// Wraps `inner`.
    pub fn new(inner: &'a dyn Accel) -> Self {
        Self {
            inner,
            batches: Mutex::new(Vec::new()),
            rays: AtomicUsize::new(0),
            overflowed: AtomicBool::new(false),
        }
    }

    fn record(&self, query: Query, coherence: Coherence, rays: &[Ray]) {
        let before = self.rays.fetch_add(rays.len(), Ordering::Relaxed);
        if before + rays.len() > MAX_RECORDED_RAYS {
            self.overflowed.store(true, Ordering::Relaxed);
            return;
        }
        let batch = RecordedBatch {
            query,
            coherence,
            rays: rays.to_vec(),
        };
        // A poisoned lock means a render thread panicked mid-push; the list itself is intact.
        self.batches
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .push(batch);
    }

    /// The recorded batches, or `None` if the render traced more than
    /// [`MAX_RECORDED_RAYS`].
    pub fn into_batches(self) -> Option<Vec<RecordedBatch>> {
        if self.overflowed.load(Ordering::Relaxed) {
            return None;
        }
        Some(
            self.batches
                .into_inner()
                .unwrap_or_else(std::sync::PoisonError::into_inner),
        )
    }
}

impl Accel for RecordingAccel<'_> {
    fn kind(&self) -> BackendKind {
        self.inner.kind()
    }

    fn intersect(&self, ray: &Ray) -> Option<Hit> {
        self.record(
            Query::Closest,
            Coherence::Incoherent,
            std::slice::from_ref(ray),
        );
        self.inner.intersect(ray)
    }

    fn occluded(&self, ray: &Ray) -> bool {
        self.record(Query::Any, Coherence::Incoherent, std::slice::from_ref(ray));
        self.inner.occluded(ray)
    }

    fn intersect_many(&self, rays: &[Ray], hits: &mut [Option<Hit>], coherence: Coherence) {
        self.record(Query::Closest, coherence, rays);
        self.inner.intersect_many(rays, hits, coherence);
    }

    fn occluded_many(&self, rays: &[Ray], occluded: &mut [bool], coherence: Coherence) {
        self.record(Query::Any, coherence, rays);
        self.inner.occluded_many(rays, occluded, coherence);
    }

    fn all_hits(&self, ray: &Ray, out: &mut Vec<Hit>) {
        // Not a query the path tracer makes (annotations only): passed through unrecorded.
        self.inner.all_hits(ray, out);
    }

    fn triangle_count(&self) -> usize {
        self.inner.triangle_count()
    }
}

/// Rays of a recording by query.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MixCounts {
    /// Closest-hit rays in coherent batches (camera rays).
    pub coherent_closest: u64,
    /// Closest-hit rays in incoherent batches (bounce rays).
    pub incoherent_closest: u64,
    /// Occlusion rays (shadow rays).
    pub any: u64,
}

impl MixCounts {
    /// Every ray.
    pub fn total(&self) -> u64 {
        self.coherent_closest + self.incoherent_closest + self.any
    }

    /// Counts the rays of `batches`.
    pub fn of(batches: &[RecordedBatch]) -> Self {
        let mut counts = Self::default();
        for b in batches {
            let n = b.rays.len() as u64;
            match (b.query, b.coherence) {
                (Query::Closest, Coherence::Coherent) => counts.coherent_closest += n,
                (Query::Closest, Coherence::Incoherent) => counts.incoherent_closest += n,
                (Query::Any, _) => counts.any += n,
            }
        }
        counts
    }
}

/// Traces `batches` through `accel` on `pool` with no shading and returns the wall time.
/// Batches are spread over the pool's threads as the render's tiles were.
pub fn replay(accel: &dyn Accel, batches: &[RecordedBatch], pool: &rayon::ThreadPool) -> Duration {
    let start = Instant::now();
    pool.install(|| {
        batches.par_iter().for_each_init(
            || (Vec::new(), Vec::new()),
            |(hits, occluded): &mut (Vec<Option<Hit>>, Vec<bool>), b| match b.query {
                Query::Closest => {
                    hits.clear();
                    hits.resize(b.rays.len(), None);
                    accel.intersect_many(&b.rays, hits, b.coherence);
                }
                Query::Any => {
                    occluded.clear();
                    occluded.resize(b.rays.len(), false);
                    accel.occluded_many(&b.rays, occluded, b.coherence);
                }
            },
        )
    });
    start.elapsed()
}

/// Result of [`path_mix_bench`].
#[derive(Clone, Copy, Debug)]
pub struct PathMixReport {
    /// Median end-to-end render time (camera rays to resolved film).
    pub render: Duration,
    /// Median time to trace the same rays with no shading.
    pub raw: Duration,
    /// The rays of one render, by query.
    pub rays: MixCounts,
    /// Renders (and replays) measured.
    pub runs: usize,
}

impl PathMixReport {
    /// The renderer's rays per second as a share of the raw rate on the same rays.
    pub fn share_of_raw(&self) -> f64 {
        self.raw.as_secs_f64() / self.render.as_secs_f64().max(1e-12)
    }

    /// Millions of rays per second of a time over this mix.
    pub fn mrays(&self, d: Duration) -> f64 {
        self.rays.total() as f64 / d.as_secs_f64().max(1e-12) / 1e6
    }
}

impl std::fmt::Display for PathMixReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} rays a render ({} camera, {} bounce, {} shadow): renderer {:.3} s ({:.1} Mrays/s), \
             the same rays unshaded {:.3} s ({:.1} Mrays/s): renderer reaches {:.0}% of it \
             (median of {})",
            self.rays.total(),
            self.rays.coherent_closest,
            self.rays.incoherent_closest,
            self.rays.any,
            self.render.as_secs_f64(),
            self.mrays(self.render),
            self.raw.as_secs_f64(),
            self.mrays(self.raw),
            100.0 * self.share_of_raw(),
            self.runs
        )
    }
}

/// Renders `inputs` once through a [`RecordingAccel`], then alternately renders it normally
/// and replays the recorded rays raw, `runs` times each, and reports the medians. The
/// render's ray counts equal the recording's (the same seed gives the same paths).
pub fn path_mix_bench(
    inputs: &crate::render::RenderInputs<'_>,
    settings: &crate::render::RenderSettings,
    runs: usize,
) -> Result<PathMixReport, crate::render::RenderError> {
    let recorder = RecordingAccel::new(inputs.accel);
    let recording = crate::render::RenderInputs {
        accel: &recorder,
        ..*inputs
    };
    crate::render::render_film(&recording, settings, 0..settings.spp, None)?;
    let batches = recorder.into_batches().ok_or_else(|| {
        crate::render::RenderError::Settings(format!(
            "the render traces more than {MAX_RECORDED_RAYS} rays, too many to record: give a \
             smaller --width, --height or --spp"
        ))
    })?;
    let pool = crate::render::thread_pool(settings.threads, inputs.accel.kind())?;
    let own_pool = crate::render::RenderInputs {
        pool: Some(&pool),
        ..*inputs
    };
    let (mut renders, mut raws) = (Vec::new(), Vec::new());
    for _ in 0..runs.max(1) {
        let (_, stats) = crate::render::render_film(&own_pool, settings, 0..settings.spp, None)?;
        renders.push(stats.elapsed);
        raws.push(replay(inputs.accel, &batches, &pool));
    }
    Ok(PathMixReport {
        render: super::timing::median_duration(&renders),
        raw: super::timing::median_duration(&raws),
        rays: MixCounts::of(&batches),
        runs: runs.max(1),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::{BuildOptions, TriangleMesh, build};
    use glam::Vec3;

    #[test]
    fn recording_answers_like_the_inner_accel_and_keeps_every_ray() {
        let positions = [
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let indices = [[0u32, 1, 2]];
        let mesh = TriangleMesh {
            positions: &positions,
            indices: &indices,
            instances: &[],
        };
        let inner = build(BackendKind::Bvh, &[mesh], BuildOptions::default()).unwrap();
        let recorder = RecordingAccel::new(inner.as_ref());
        let hit = Ray::new(Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 0.0, -1.0));
        let miss = Ray::new(Vec3::new(5.0, 0.0, 1.0), Vec3::new(0.0, 0.0, -1.0));
        let mut hits = vec![None; 2];
        recorder.intersect_many(&[hit, miss], &mut hits, Coherence::Coherent);
        assert!(hits[0].is_some() && hits[1].is_none());
        assert!(recorder.occluded(&hit));
        assert!(recorder.intersect(&miss).is_none());
        let batches = recorder.into_batches().unwrap();
        let counts = MixCounts::of(&batches);
        assert_eq!(
            counts,
            MixCounts {
                coherent_closest: 2,
                incoherent_closest: 1,
                any: 1
            }
        );
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let _ = replay(inner.as_ref(), &batches, &pool);
    }

    #[test]
    fn the_path_mix_is_the_renders_own_rays() {
        use crate::render::{Integrator, RenderInputs, RenderSettings, render_film};
        let (scene, camera) =
            crate::bench::render::procedural_scene(crate::procedural::Builtin::ALL[0], 1);
        let accel = build(
            BackendKind::Bvh,
            &scene.triangle_meshes(),
            BuildOptions::default(),
        )
        .unwrap();
        let environment = crate::light::environment::EnvironmentLight::constant(Vec3::ONE);
        let inputs = RenderInputs {
            environment: Some(&environment),
            ..RenderInputs::of_scene(&scene, accel.as_ref(), &camera)
        };
        let settings = RenderSettings {
            width: 24,
            height: 16,
            spp: 2,
            threads: 2,
            integrator: Integrator::Path,
            max_depth: 4,
            ..RenderSettings::default()
        };
        let report = path_mix_bench(&inputs, &settings, 1).unwrap();
        let (_, stats) = render_film(&inputs, &settings, 0..2, None).unwrap();
        assert_eq!(report.rays.coherent_closest, 24 * 16 * 2);
        assert_eq!(report.rays.coherent_closest, stats.rays.camera);
        assert_eq!(report.rays.incoherent_closest, stats.rays.reflection);
        assert_eq!(report.rays.any, stats.rays.shadow);
        assert!(report.rays.incoherent_closest > 0 && report.rays.any > 0);
        assert!(report.render > Duration::ZERO && report.raw > Duration::ZERO);
    }
}
