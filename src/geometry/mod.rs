//! Robust surface geometry: where a ray hit, how far the computed point may be from the true
//! one, and how to leave the surface again without hitting it a second time.
//!
//! This module is the only place in glint that offsets ray origins. It follows pbrt-v4's
//! design (the book's section on "Robust Spawned Ray Origins"): the hit point is reconstructed
//! from barycentric coordinates together with a conservative bound on its floating-point error
//! ([`error::triangle_point`]); a spawned ray's origin is pushed along the geometric normal just
//! past that bound and rounded away from the surface ([`offset::offset_ray_origin`]). No fixed
//! epsilon is involved, so the method holds at any scene scale and any distance from the origin.
//!
//! - [`float`]: rounding-error constants (γ(n)).
//! - [`error`]: the hit point and its error bound.
//! - [`offset`]: spawning reflection and shadow rays.
//! - [`interaction`]: the per-hit record the shading step reads.

pub mod error;
pub mod float;
pub mod interaction;
pub mod offset;

pub use error::triangle_point;
pub use interaction::{SurfaceInteraction, shading_normal};
pub use offset::{SHADOW_EPSILON, offset_ray_origin, spawn_ray, spawn_ray_to};
