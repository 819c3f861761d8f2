//! Sampling building blocks shared by BSDFs and lights.
//!
//! - [`warp`]: maps from the unit square to directions and points (cosine hemisphere, sphere,
//!   disk), each with its density.
//! - [`triangle`]: uniform points on a triangle by area.
//! - [`distribution`]: discrete and piecewise-constant distributions (1D, 2D) for choosing
//!   lights by power and environment texels by radiance.

pub mod distribution;
pub mod triangle;
pub mod warp;
