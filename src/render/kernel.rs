//! What per-hit work a render does, from the scene's features: texture lookups (and so MIP
//! chains and ray differentials), vertex colours, shading normals, normal maps, area-light and
//! environment sampling, alpha tests and back-face culling ([`KernelFlags`]). The summary line
//! names what was left out.
//!
//! There is one shading kernel (`path::render_tile`). Until issue 21 it was compiled in 12
//! instances (and the classic direct kernel in 24) with const switches for textures, vertex
//! colours, shading normals and normal maps; `glint bench render` measured the general
//! instance within noise of the specialised ones (Suzanne 0.98×, 2CylinderEngine 0.91×,
//! DamagedHelmet 1.07× with alpha tests and culling also on), the per-hit checks being
//! branches on data the hit reads anyway, so the instances went. [`KernelChoice::General`]
//! still turns every flag on (textures, alpha tests and culling for every mesh): it gives the
//! same image and measures what deciding per scene buys (`bench::render::kernel_bench`).

use crate::scene::SceneFeatures;

/// Which kernel renders.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum KernelChoice {
    /// The kernel specialised for the scene's features (the default).
    #[default]
    Specialised,
    /// Every feature on.
    General,
}

/// The work a kernel does per hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct KernelFlags {
    /// Interpolates texture coordinates and samples textures.
    pub textures: bool,
    /// Interpolates vertex colours.
    pub vertex_colors: bool,
    /// Interpolates vertex normals.
    pub shading_normals: bool,
    /// Reads normal maps and builds tangent frames (only with `textures`).
    pub normal_maps: bool,
    /// Area lights are sampled (the scene has emissive triangles): set by the scheduler once
    /// it knows the render's lights.
    pub area_lights: bool,
    /// The environment is sampled.
    pub environment: bool,
    /// Hits on MASK and BLEND materials are alpha-tested, and rays continue past rejected
    /// ones (see [`super::visibility`]).
    pub alpha: bool,
    /// Camera rays skip back faces of single-sided materials.
    pub cull_back_faces: bool,
}

impl KernelFlags {
    /// The flags of `choice` for a scene with `features`.
    pub fn for_scene(features: &SceneFeatures, choice: KernelChoice) -> Self {
        match choice {
            KernelChoice::Specialised => Self {
                textures: features.textures,
                vertex_colors: features.vertex_colors,
                shading_normals: features.shading_normals,
                normal_maps: features.normal_maps,
                area_lights: false,
                environment: false,
                alpha: features.alpha,
                cull_back_faces: features.single_sided,
            },
            KernelChoice::General => Self {
                textures: true,
                vertex_colors: true,
                shading_normals: true,
                normal_maps: true,
                area_lights: false,
                environment: false,
                alpha: true,
                cull_back_faces: true,
            },
        }
    }
}
