//! Shading kernels specialised for what a scene uses.
//!
//! The path kernel ([`super::path`], which is also the direct integrator) is generic over
//! four compile-time switches: texture lookups, vertex colours, interpolated shading normals
//! and normal maps (tangent frames; only in instances with textures). `select` picks the
//! instance whose switches match the scene's [`SceneFeatures`], so per-hit work the scene
//! cannot need is not compiled into the loop that runs. The general kernel turns every
//! switch on: it gives the same image and exists to measure what the specialisation buys
//! (`bench::render::kernel_bench`).

use super::film::TileSums;
use super::path::PathScratch;
use super::stats::RayCounts;
use super::tiles::Tile;
use super::wavefront::{Pass, TileContext};
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

/// A tile renderer: one monomorphised instance of the path kernel.
pub(crate) type TileFn =
    fn(&TileContext<'_>, Pass, &Tile, &mut PathScratch) -> (TileSums, RayCounts);

/// The instance for `flags`. Normal maps are texture lookups, so their instances exist only
/// with textures on.
pub(crate) fn select(flags: &KernelFlags) -> TileFn {
    use super::path::render_tile_path;
    let normal_maps = flags.normal_maps && flags.textures;
    match (
        flags.textures,
        flags.vertex_colors,
        flags.shading_normals,
        normal_maps,
    ) {
        (false, false, false, _) => render_tile_path::<false, false, false, false>,
        (false, false, true, _) => render_tile_path::<false, false, true, false>,
        (false, true, false, _) => render_tile_path::<false, true, false, false>,
        (false, true, true, _) => render_tile_path::<false, true, true, false>,
        (true, false, false, false) => render_tile_path::<true, false, false, false>,
        (true, false, true, false) => render_tile_path::<true, false, true, false>,
        (true, true, false, false) => render_tile_path::<true, true, false, false>,
        (true, true, true, false) => render_tile_path::<true, true, true, false>,
        (true, false, false, true) => render_tile_path::<true, false, false, true>,
        (true, false, true, true) => render_tile_path::<true, false, true, true>,
        (true, true, false, true) => render_tile_path::<true, true, false, true>,
        (true, true, true, true) => render_tile_path::<true, true, true, true>,
    }
}
