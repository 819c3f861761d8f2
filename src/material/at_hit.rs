//! The surface front end: one call turns a material at a ray hit into everything shading
//! needs ([`SurfaceAtHit`]): the shading point with its final shading normal, the frame the
//! BSDF works in, the base colour (for the albedo AOV), the emitted radiance and the BSDF.
//!
//! Everything a hit's appearance depends on is applied here and nowhere else, in this order:
//! 1. the hit point and geometric normal (`geometry::SurfaceInteraction`);
//! 2. the interpolated vertex normal (meshes with NORMAL);
//! 3. the footprint of the ray's differential (texture filtering; camera rays only);
//! 4. the base colour: factor × COLOR_0 × base colour texture × procedural texture;
//! 5. the normal map and its tangent frame; the shading normal, mapped or interpolated, is
//!    bent so that it reflects `ωo` above the geometric surface (`normal_map::keep_reflection_above`);
//! 6. emission: factor × emissive texture (read only where the factor is not black), from a
//!    front face or either face of a double-sided material (a single-sided material's back
//!    face scatters like its front but emits nothing);
//! 7. metallic and roughness: factors × metallic-roughness texture (or, converted from
//!    KHR_materials_pbrSpecularGlossiness, the specular colour and glossiness texture);
//! 8. KHR_materials_anisotropy: strength and direction ([`super::anisotropy`]), which
//!    becomes the X axis of the BSDF's frame;
//! 9. the KHR_materials layers (their textures at the hit, the coat's own normal map;
//!    diffuse transmission's strength and colour);
//! 10. the BSDF: glTF's metallic-roughness BRDF, or the layered BSDF over it.
//!
//! The result does not depend on the integrator: the direct integrator and the path tracer
//! shade the same BSDF and differ only in which lobes they continue through. This is
//! pbrt-v4's `SurfaceInteraction::GetBSDF` and Mitsuba's `si.bsdf()` in glint's terms.
//!
//! Work a hit does not need is skipped where it is decided: a mesh without NORMAL or COLOR_0
//! interpolates neither, a material without a texture reads none, a ray without a
//! differential has no footprint.

use super::scattering::SurfaceBsdf;
use super::{ShadingMaterial, anisotropy, layers, normal_map};
use crate::accel::Hit;
use crate::bsdf::Frame;
use crate::geometry::{SurfaceInteraction, shading_normal};
use crate::scene::Mesh;
use crate::texture::{Footprint, RayDifferential, TextureEvaluator, TexturePoint};
use glam::{Vec3, Vec4};

/// A ray's hit to be shaded.
#[derive(Clone, Copy)]
pub struct HitQuery<'a> {
    /// The mesh hit.
    pub mesh: &'a Mesh,
    /// Its material, prepared.
    pub material: &'a ShadingMaterial,
    /// The hit.
    pub hit: &'a Hit,
    /// The ray's direction (need not be unit).
    pub dir: Vec3,
    /// The ray's differential, for the texture footprint (`None`: finest texture level).
    pub differential: Option<RayDifferential>,
    /// Whether the caller will scatter or light the hit (`false`: emission and AOVs only, so
    /// the metallic-roughness and layer textures are not read and no BSDF is built).
    pub scatters: bool,
}

/// What a hit presents to shading.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceAtHit {
    /// The shading point; `si.ns` is the final shading normal (interpolated, normal-mapped).
    pub si: SurfaceInteraction,
    /// The BSDF's frame: `si.ns` and the normal map's tangent (an arbitrary one without).
    pub frame: Frame,
    /// Whether this side emits (the emissive, or an unlit material's base colour): a front
    /// face or a double-sided material, the sides the light sampler samples. Every side
    /// scatters: a back face of a single-sided material (met only by bounce and shadow rays,
    /// camera rays cull it) reflects and transmits as its front does, seen from its own side.
    pub emits: bool,
    /// KHR_materials_unlit: `albedo` leaves the surface as radiance and nothing scatters.
    pub unlit: bool,
    /// Base colour ρ at the hit (factor × vertex colour × textures), linear RGB.
    pub albedo: Vec3,
    /// Emitted radiance `Le` toward `si.wo` (W/(m²·sr)); zero on a side that does not emit.
    pub emission: Vec3,
    /// The BSDF in `frame`; `None` for unlit materials, or when the query did not ask for it.
    pub bsdf: Option<SurfaceBsdf>,
}

/// The surface at `q`'s hit (see the module doc); `None` when the hit cannot be shaded (a
/// triangle outside the mesh, or one without a normal).
#[inline(always)]
pub fn at_hit(textures: &TextureEvaluator<'_>, q: &HitQuery<'_>) -> Option<SurfaceAtHit> {
    let (mesh, material) = (q.mesh, q.material);
    let mut si = SurfaceInteraction::from_hit(mesh, q.hit, q.dir)?;
    if let Some(normals) = &mesh.normals {
        si.ns = shading_normal(&si, normals);
    }
    let emits = si.front_face || material.double_sided;
    let footprint = q
        .differential
        .filter(|_| material.textured())
        .and_then(|rd| Footprint::at(mesh, &si, &rd));
    // The interpolated normal, before the base's normal map: a clear coat's normal map
    // perturbs this one, and a coat without one uses it as it is (KHR_materials_clearcoat).
    let vertex_ns = si.ns;
    let mapped_tangent = {
        let at = TexturePoint {
            mesh,
            si: &si,
            footprint: footprint.as_ref(),
        };
        normal_map::at_hit(textures, &at, material).map(|(ns, tangent)| {
            si.ns = ns;
            tangent
        })
    };
    if mapped_tangent.is_none() && si.ns != si.ng {
        // Interpolated vertex normals follow the normal map's rule too: near a silhouette of
        // a smooth mesh they reflect `ωo` below the geometric surface, where every mirror
        // reflection would be lost (Cycles bends them the same way).
        si.ns = normal_map::keep_reflection_above(si.ns, si.ng, si.wo);
    }
    let at = TexturePoint {
        mesh,
        si: &si,
        footprint: footprint.as_ref(),
    };

    let mut albedo = material.base_color;
    if let Some(colors) = &mesh.colors {
        albedo *= si.interpolate(colors).unwrap_or(Vec4::ONE).truncate();
    }
    if let Some(t) = &material.base_color_texture {
        albedo *= textures.value(&at, t).truncate();
    }
    let emission = emitted(textures, &at, material, emits);
    if let Some(procedural) = &material.procedural {
        albedo *= textures.procedural(&at, procedural);
    }
    // KHR_materials_anisotropy: the frame's X axis is the anisotropy direction.
    let anisotropy = material
        .anisotropy
        .as_ref()
        .filter(|_| q.scatters && !material.unlit)
        .and_then(|a| anisotropy::at_hit(textures, &at, a, si.ns));
    let frame = match (anisotropy, mapped_tangent) {
        (Some(a), _) => Frame::from_normal_tangent(si.ns, a.direction),
        (None, Some(t)) => Frame::from_normal_tangent(si.ns, t),
        (None, None) => Frame::from_normal(si.ns),
    };
    let bsdf = (q.scatters && !material.unlit).then(|| {
        let (metallic_roughness, specular_tint) = metallic_roughness(textures, &at, material);
        let base_mapped = mapped_tangent.is_some();
        let layers = match &material.layers {
            Some(l) if l.has_textures() || (base_mapped && l.clearcoat.is_some()) => {
                let mut l = layers::at_hit(textures, &at, l);
                l.coat_normal =
                    layers::coat_normal(textures, &at, vertex_ns, base_mapped, material, &frame);
                Some(l)
            }
            other => *other,
        };
        SurfaceBsdf::anisotropic(
            albedo,
            metallic_roughness,
            specular_tint,
            anisotropy.map_or(0.0, |a| a.strength),
            material,
            layers.as_ref(),
            si.front_face,
        )
    });
    Some(SurfaceAtHit {
        si,
        frame,
        emits,
        unlit: material.unlit,
        albedo,
        emission,
        bsdf,
    })
}

/// The emission rule, the one place it is decided: the radiance a point of `material` at `at`
/// sends toward `at.si.wo`, on a side that `emits` (a front face, or either face of a
/// double-sided material): the emissive factor times the emissive texture (read only where the
/// factor is not black). Zero on other sides and for unlit materials, which ignore their
/// emissive factor (their ρ is what leaves them). Used for hits ([`at_hit`]) and for points
/// the light sampler draws on emissive triangles (the integrator's light samples), so both
/// strategies of MIS see the same `Le`.
#[inline]
pub fn emitted(
    textures: &TextureEvaluator<'_>,
    at: &TexturePoint<'_>,
    material: &ShadingMaterial,
    emits: bool,
) -> Vec3 {
    if !emits || material.unlit || material.emissive == Vec3::ZERO {
        return Vec3::ZERO;
    }
    match &material.emissive_texture {
        Some(t) => material.emissive * textures.value(at, t).truncate(),
        None => material.emissive,
    }
}

/// The hit's metallic and roughness: the material's factors times its metallic-roughness
/// texture's blue and green channels (glTF), clamped to [0, 1]; the factors alone without a
/// texture. With a specular-glossiness texture, also the tint its RGB puts on the specular
/// colour, and the roughness `1 − glossiness · A` (white without one).
#[inline]
fn metallic_roughness(
    textures: &TextureEvaluator<'_>,
    at: &TexturePoint<'_>,
    material: &ShadingMaterial,
) -> ((f32, f32), Vec3) {
    let (metallic, mut roughness) = match &material.metallic_roughness_texture {
        Some(t) => {
            let texel = textures.value(at, t);
            (
                (material.metallic * texel.z).clamp(0.0, 1.0),
                (material.roughness * texel.y).clamp(0.0, 1.0),
            )
        }
        None => (material.metallic, material.roughness),
    };
    let mut tint = Vec3::ONE;
    if let Some(t) = &material.specular_glossiness_texture {
        let texel = textures.value(at, t);
        tint = texel.truncate().max(Vec3::ZERO);
        roughness = (1.0 - (1.0 - roughness) * texel.w).clamp(0.0, 1.0);
    }
    ((metallic, roughness), tint)
}
