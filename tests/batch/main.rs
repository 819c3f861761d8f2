//! Integration tests, one binary: `glint batch`: shards, claims, resumes and faults.
//! Which binary holds what, and how to run the fast set: docs/testing.md.

#[path = "../support/mod.rs"]
mod support;

mod batch;
mod batch_claims;
mod batch_faults;
