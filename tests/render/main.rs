//! Integration tests, one binary: the render loop and its outputs: pixel sampling, filters, determinism, progressive rendering, the command line, denoising, annotations, the geometric ground truth, image hashes and the Cycles goldens.
//! Which binary holds what, and how to run the fast set: docs/testing.md.

#[path = "../support/mod.rs"]
mod support;

mod converge;
mod determinism;
mod filters;
mod job_defaults;
mod output;
mod progressive;
mod render_cli;

/// The slow and statistical tests: `cargo test -- --skip slow::` leaves them out.
mod slow;
