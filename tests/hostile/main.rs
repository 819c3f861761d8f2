//! Integration tests, one binary: hostile input: bad and mutated files, the fuzz engine and its kept findings, panics, bad input through the binary.
//! Which binary holds what, and how to run the fast set: docs/testing.md.

#[path = "../support/mod.rs"]
mod support;

#[path = "../../examples/fuzz/engine.rs"]
mod engine;
#[path = "../mutate/mod.rs"]
mod mutate;
#[path = "../../examples/fuzz/targets.rs"]
mod targets;

mod bad_input_load;
mod fuzz_harness;
mod fuzz_regressions;
mod hostile_input;
mod panics;
mod render_bad_input;

/// The slow and statistical tests: `cargo test -- --skip slow::` leaves them out.
mod slow;
