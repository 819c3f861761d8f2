//! The one support module of the integration tests, included by every test binary under
//! `tests/` (`#[path = "../support/mod.rs"] mod support;`). Tests import its items flat:
//! `use crate::support::{lambert, quad, Fixture, chi_square};`.
//!
//! - [`cli`]: running the `glint` binary;
//! - [`fixture`]: hand-built glTF documents, data URIs, temporary folders, the shared scenes;
//! - [`rays`]: seeded ray generators and bounds, for the ray-query tests;
//! - [`render`]: materials, quads, cameras, renders and closed forms for the renderer's tests;
//! - [`stats`]: χ² and mean ± standard error, for the statistical tests.

#![allow(dead_code, unused_imports)] // Each binary uses a different subset.

pub mod cli;
pub mod fixture;
pub mod rays;
pub mod render;
pub mod stats;

pub use cli::*;
pub use fixture::*;
pub use rays::*;
pub use render::*;
pub use stats::*;
