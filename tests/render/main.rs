//! Integration tests, one binary: the render loop and its outputs: pixel sampling, filters, determinism, progressive rendering, the command line, denoising, annotations, the geometric ground truth, image hashes and the Cycles goldens.
//! Which binary holds what, and how to run the fast set: docs/testing.md.

#[path = "../support/mod.rs"]
mod support;

mod annotations;
mod converge;
mod cycles_goldens;
mod denoise;
mod determinism;
mod filters;
mod ground_truth;
mod image_hashes;
mod job_defaults;
mod output;
mod progressive;
mod render_cli;
mod sampling;
