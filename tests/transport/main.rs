//! Integration tests, one binary: light transport: closed forms, furnaces, light sampling, MIS, guiding, adaptive sampling, volumes, alpha, extremes.
//! Which binary holds what, and how to run the fast set: docs/testing.md.

#[path = "../support/mod.rs"]
mod support;

mod adaptive;
mod alpha;
mod analytic;
mod anisotropy;
mod area_lights;
mod clamp_indirect;
mod direct_bsdf;
mod environment;
mod extremes;
mod furnace_gltf;
mod guiding;
mod light_sampler;
mod mirror;
mod mis_compensation;
mod path_tracing;
mod single_sided_furnace;
mod volume;
