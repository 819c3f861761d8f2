//! The KHR_materials layer textures at a hit: `clearcoatTexture` (R) and
//! `clearcoatRoughnessTexture` (G), `sheenColorTexture` (RGB) and `sheenRoughnessTexture` (A),
//! `transmissionTexture` (R), each multiplying its factor as the extensions specify. Looked up
//! only in texture kernels, and only for materials whose layers have such textures
//! ([`ShadingLayers::has_textures`]); others keep their prepared layers untouched.

use super::integrator::{Footprint, TileContext, texture_value};
use crate::geometry::SurfaceInteraction;
use crate::material::layers::ShadingLayers;
use crate::scene::Mesh;

/// `layers` with each textured factor multiplied by its texture's channel at the hit
/// (clamped to [0, 1], as the factors are).
#[inline]
pub(super) fn at_hit(
    ctx: &TileContext<'_>,
    mesh: &Mesh,
    si: &SurfaceInteraction,
    footprint: Option<&Footprint>,
    layers: &ShadingLayers,
) -> ShadingLayers {
    let mut out = *layers;
    let lookup = |t| texture_value(ctx, mesh, si, footprint, t);
    if let Some(c) = &mut out.clearcoat {
        if let Some(t) = &c.texture {
            c.factor = (c.factor * lookup(t).x).clamp(0.0, 1.0);
        }
        if let Some(t) = &c.roughness_texture {
            c.roughness = (c.roughness * lookup(t).y).clamp(0.0, 1.0);
        }
    }
    if let Some(s) = &mut out.sheen {
        if let Some(t) = &s.color_texture {
            s.color = (s.color * lookup(t).truncate()).clamp(glam::Vec3::ZERO, glam::Vec3::ONE);
        }
        if let Some(t) = &s.roughness_texture {
            s.roughness = (s.roughness * lookup(t).w).clamp(0.0, 1.0);
        }
    }
    if let Some(tr) = &mut out.transmission
        && let Some(t) = &tr.texture
    {
        tr.factor = (tr.factor * lookup(t).x).clamp(0.0, 1.0);
    }
    out
}
