//! The slow and statistical tests of this binary (over about two CPU-seconds a module, or
//! a statistical test at a stated confidence), kept as they are and grouped here so that
//! `cargo test -- --skip slow::` runs the fast set (docs/testing.md). The files stay beside
//! `main.rs`.

#[path = "adaptive.rs"]
mod adaptive;
#[path = "anisotropy.rs"]
mod anisotropy;
#[path = "area_lights.rs"]
mod area_lights;
#[path = "diffuse_transmission.rs"]
mod diffuse_transmission;
#[path = "environment.rs"]
mod environment;
#[path = "furnace_gltf.rs"]
mod furnace_gltf;
#[path = "guiding.rs"]
mod guiding;
#[path = "light_sampler.rs"]
mod light_sampler;
#[path = "mirror.rs"]
mod mirror;
#[path = "mis_compensation.rs"]
mod mis_compensation;
#[path = "path_tracing.rs"]
mod path_tracing;
#[path = "single_sided_furnace.rs"]
mod single_sided_furnace;
