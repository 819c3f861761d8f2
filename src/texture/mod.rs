//! Textures: MIP-mapped image textures with nearest, bilinear, bicubic, trilinear and
//! anisotropic filtering, ray differentials that give each hit its texture-space footprint,
//! and band-limited procedural textures.
//!
//! - [`image`]: one texel grid, glTF wrap modes and point reconstruction filters.
//! - [`mipmap`]: the MIP chain, built once per texture in linear space.
//! - [`filter`]: footprint-driven lookups ([`TextureFilter`]).
//! - [`differentials`]: camera ray differentials, their transfer to a surface and through
//!   mirror reflections.
//! - [`evaluator`]: reading a texture at a surface hit (footprint, coordinates, transform).
//! - [`noise`]: value and Perlin noise, mixed octaves, the checkerboard.

pub mod differentials;
pub mod evaluator;
pub mod filter;
pub mod image;
pub mod mipmap;
pub mod noise;

pub use differentials::RayDifferential;
pub use evaluator::{Footprint, TextureEvaluator, TexturePoint};
pub use filter::{TextureFilter, UvFootprint, lookup};
pub use mipmap::MipMap;
pub use noise::ProceduralTexture;
