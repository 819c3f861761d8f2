//! Benchmarks: how fast each ray backend builds and traces.
//!
//! - [`rays`]: deterministic ray generators (the renderer's camera rays in its tiles, incoherent random
//!   rays and segments), reusable by any benchmark that must trace the same rays twice.
//! - [`timing`]: medians and spreads of repeated runs after a discarded warm-up.
//! - [`cpu`]: the CPU time the process used, for throughput per CPU-second on a busy machine.
//! - [`scene`]: the scenes benchmarked (built-in procedural scenes or glTF files).
//! - [`structure`]: a built backend with its single-ray and packet entry points.
//! - [`run`]: `bench rays` itself, measuring every build setting and query.
//! - [`report`]: the figures as data, the ratios derived within one run, and the tables.
//! - [`render`]: `bench render`: the renderer's kernels, its raw-trace ceiling and its thread
//!   scaling, on the renderer's own camera rays and tiles.
//! - [`ray_mix`]: the path tracer's own rays, recorded during a render and replayed unshaded.
//! - [`instances`]: `bench instances`: build time and bytes of placed copies against baked ones.

pub mod cpu;
pub mod instances;
pub mod ray_mix;
pub mod rays;
pub mod render;
pub mod report;
pub mod run;
pub mod scene;
pub mod structure;
pub mod timing;

pub use report::RaysReport;
pub use run::{BenchError, RaysConfig, run_rays};
pub use scene::{BenchScene, SceneSize};
