//! Sampling building blocks shared by BSDFs and lights.
//!
//! - [`warp`]: maps from the unit square to directions and points (cosine hemisphere, sphere,
//!   disk, triangle), each with its density.
//! - [`distribution`]: discrete and piecewise-constant distributions (1D, 2D) for choosing
//!   lights by power and environment texels by radiance.

pub mod distribution;
pub mod warp;
