//! Integration tests, one binary: textures: lookups and filters, compact texels, KTX2, texture layers, normal maps, ray differentials.
//! Which binary holds what, and how to run the fast set: docs/testing.md.

#[path = "../support/mod.rs"]
mod support;

mod compact_textures;
mod differentials;
mod ktx2;
mod layer_textures;
mod normal_maps;
mod smooth_normals;
mod texture_lookup_exact;

/// The slow and statistical tests: `cargo test -- --skip slow::` leaves them out.
mod slow;
