//! glint: a native CPU renderer for glTF 2.0 scenes.
//!
//! Ray queries go to Intel Embree (through the C shim in `ffi/`) or to a pure-Rust BVH; the
//! light transport above them is safe Rust. See the README for the command line.

#![deny(unsafe_code)]

pub mod accel;
pub mod batch;
#[cfg(feature = "bench")]
pub mod bench;
pub mod bsdf;
pub mod cli;
pub mod color;
pub mod converge;
pub mod denoise;
pub mod geometry;
pub mod gt_check;
pub mod guiding;
pub mod job;
pub mod light;
pub mod material;
pub mod output;
pub mod panics;
pub mod procedural;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod texture;
