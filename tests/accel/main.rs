//! Integration tests, one binary: ray queries: Embree against obvhs, the Embree shim and its lifetimes, instancing, the benchmark's structure.
//! Which binary holds what, and how to run the fast set: docs/testing.md.

#[path = "../support/mod.rs"]
mod support;

mod backend_agreement;
mod bench_smoke;
mod embree_shim;
mod embree_version;
mod instancing;
