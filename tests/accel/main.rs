//! Integration tests, one binary: ray queries: Embree against obvhs, the Embree shim and its lifetimes, instancing, the benchmark's structure.
//! Which binary holds what, and how to run the fast set: docs/testing.md.

#[path = "../support/mod.rs"]
mod support;

mod bench_smoke;
mod embree_shim;
mod embree_version;

/// The slow and statistical tests: `cargo test -- --skip slow::` leaves them out.
mod slow;
