//! Integration tests, one binary: loading glTF: the Khronos models, Draco, the shared assets rendered on both backends.
//! Which binary holds what, and how to run the fast set: docs/testing.md.

#[path = "../support/mod.rs"]
mod support;

mod assets_render;
mod diffuse_transmission;
mod draco;
mod gltf_coverage;
mod gltf_load;
mod material_variants;
mod specular_glossiness;
