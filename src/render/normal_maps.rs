//! Per-hit material textures beyond colour, for the kernels: normal mapping in both (the
//! normal texture looked up with the hit's footprint, the perturbed normal from the mesh's
//! tangents, [`crate::material::normal_map`], and the horizon rule that keeps it usable;
//! compiled only into kernel instances whose scene has normal maps, see [`super::kernel`]),
//! and the metallic-roughness texture in the path tracer (texture kernels only).

use super::integrator::{Footprint, TileContext, texture_value};
use crate::geometry::SurfaceInteraction;
use crate::material::ShadingMaterial;
use crate::material::normal_map::{keep_reflection_above, perturbed_normal};
use crate::scene::Mesh;
use glam::Vec3;

/// Replaces `si.ns` by the material's normal-mapped shading normal, bent so that it reflects
/// `si.wo` above the geometric surface, and returns the tangent of the new frame. Leaves `si`
/// alone (and returns `None`) when the material has no normal map or the mesh no tangents.
///
/// `si.ns` must be the interpolated vertex normal (or `ng`) on the incoming side, as the
/// kernels compute it; the map is applied in the front face's frame and negated for a back
/// face, as glTF reverses back-face normals.
#[inline]
pub(super) fn apply(
    ctx: &TileContext<'_>,
    mesh: &Mesh,
    si: &mut SurfaceInteraction,
    footprint: Option<&Footprint>,
    material: &ShadingMaterial,
) -> Option<Vec3> {
    let normal = material.normal_texture.as_ref()?;
    let tangent = si.tangent_to_world(si.interpolate(mesh.tangents.as_deref()?)?);
    let side = if si.front_face { 1.0 } else { -1.0 };
    let texel = texture_value(ctx, mesh, si, footprint, &normal.texture).truncate();
    let (ns, t) = perturbed_normal(texel, normal.scale, side * si.ns, tangent)?;
    si.ns = keep_reflection_above(side * ns, si.ng, si.wo);
    Some(side * t)
}

/// The hit's metallic and roughness for the path tracer's BRDF: the material's factors times
/// its metallic-roughness texture's blue and green channels (glTF), clamped to [0, 1]; the
/// factors alone without a texture.
#[inline]
pub(super) fn metallic_roughness(
    ctx: &TileContext<'_>,
    mesh: &Mesh,
    si: &SurfaceInteraction,
    footprint: Option<&Footprint>,
    material: &ShadingMaterial,
) -> (f32, f32) {
    match &material.metallic_roughness_texture {
        Some(t) => {
            let texel = texture_value(ctx, mesh, si, footprint, t);
            (
                (material.metallic * texel.z).clamp(0.0, 1.0),
                (material.roughness * texel.y).clamp(0.0, 1.0),
            )
        }
        None => (material.metallic, material.roughness),
    }
}
