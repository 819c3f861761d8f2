//! Integration tests, one binary: the structure of the repository: ARCHITECTURE.md's layers.
//! Which binary holds what, and how to run the fast set: docs/testing.md.

mod layering;
mod links;
