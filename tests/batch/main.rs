//! Integration tests, one binary: `glint batch`: shards, claims, resumes and faults.
//! Which binary holds what, and how to run the fast set: docs/testing.md.

#[path = "../support/mod.rs"]
mod support;

mod batch;
mod batch_claims;

/// The slow and statistical tests: `cargo test -- --skip slow::` leaves them out.
mod slow;
