//! The KHR_materials layer textures at a hit: `clearcoatTexture` (R) and
//! `clearcoatRoughnessTexture` (G), `sheenColorTexture` (RGB) and `sheenRoughnessTexture` (A),
//! `transmissionTexture` (R), each multiplying its factor as the extensions specify. Looked up
//! only in texture kernels, and only for materials whose layers have such textures
//! ([`ShadingLayers::has_textures`]); others keep their prepared layers untouched. And
//! `clearcoatNormalTexture`: the coat's own shading normal (normal-map kernels only).

use super::integrator::{Footprint, TileContext, texture_value};
use crate::bsdf::Frame;
use crate::geometry::SurfaceInteraction;
use crate::material::ShadingMaterial;
use crate::material::layers::ShadingLayers;
use crate::material::normal_map::{keep_reflection_above, perturbed_normal};
use crate::scene::Mesh;
use glam::Vec3;

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

/// The clear coat's normal-mapped shading normal at the hit, in the local frame of `frame`
/// (the BSDF's), or `None` when the material's coat has no normal map or the mesh no
/// tangents (the coat then uses the shading normal).
///
/// As for the base's normal map ([`super::normal_maps::apply`]): the map perturbs the
/// interpolated vertex normal `vertex_ns` (on the incoming side) in the front face's frame,
/// is negated for a back face, and is bent so that it reflects `si.wo` above the geometric
/// surface.
#[inline]
pub(super) fn coat_normal(
    ctx: &TileContext<'_>,
    mesh: &Mesh,
    si: &SurfaceInteraction,
    vertex_ns: Vec3,
    footprint: Option<&Footprint>,
    material: &ShadingMaterial,
    frame: &Frame,
) -> Option<Vec3> {
    let normal = material.layers?.clearcoat?.normal_texture?;
    let tangent = si.tangent_to_world(si.interpolate(mesh.tangents.as_deref()?)?);
    let side = if si.front_face { 1.0 } else { -1.0 };
    let texel = texture_value(ctx, mesh, si, footprint, &normal.texture).truncate();
    let (n, _) = perturbed_normal(texel, normal.scale, side * vertex_ns, tangent)?;
    let n = keep_reflection_above(side * n, si.ng, si.wo);
    Some(frame.to_local(n))
}
