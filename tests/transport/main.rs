//! Integration tests, one binary: light transport: closed forms, furnaces, light sampling, MIS, guiding, adaptive sampling, volumes, alpha, extremes.
//! Which binary holds what, and how to run the fast set: docs/testing.md.

#[path = "../support/mod.rs"]
mod support;

mod alpha;
mod analytic;
mod clamp_indirect;
mod direct_bsdf;
mod extremes;
mod volume;

/// The slow and statistical tests: `cargo test -- --skip slow::` leaves them out.
mod slow;
