//! A material's KHR_materials layers prepared for shading, and the [`LayeredBsdf`] they make
//! at a hit.

use crate::bsdf::{ClearcoatBsdf, DielectricBsdf, LayeredBsdf, MetallicRoughnessBsdf, SheenBsdf};
use crate::scene::Material;
use crate::scene::layers::{Clearcoat, DiffuseTransmission, Sheen, Transmission};
use glam::Vec3;

/// The layers of one material (present only on materials with at least one of them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingLayers {
    /// KHR_materials_clearcoat.
    pub clearcoat: Option<Clearcoat>,
    /// KHR_materials_sheen.
    pub sheen: Option<Sheen>,
    /// KHR_materials_transmission.
    pub transmission: Option<Transmission>,
    /// KHR_materials_diffuse_transmission.
    pub diffuse_transmission: Option<DiffuseTransmission>,
    /// Whether KHR_materials_volume makes the transmitting surface the boundary of a volume
    /// (refracting, with attenuation inside) rather than thin-walled. A diffusely
    /// transmitting surface does not refract either way; with a volume what it transmits
    /// travels through the volume's medium.
    pub volume: bool,
    /// The volume's Beer-Lambert attenuation coefficient σ (zero: clear, or no volume).
    pub sigma: Vec3,
    /// The clear coat's own normal at the hit, in the BSDF's local frame (set per hit by
    /// [`coat_normal`]: `clearcoatNormalTexture`'s, or the unmapped vertex normal under a
    /// normal-mapped base; `None`: the shading normal).
    pub coat_normal: Option<Vec3>,
}

impl ShadingLayers {
    /// The layers of `material`, `None` when it has none (its shading is then unchanged).
    pub fn of(material: &Material) -> Option<Self> {
        // Strength 0 transmits nothing whatever its texture says: such a material shades as
        // one without the extension, bit for bit.
        let diffuse_transmission = material
            .diffuse_transmission
            .filter(|d| d.factor.is_finite() && d.factor > 0.0);
        if material.clearcoat.is_none()
            && material.sheen.is_none()
            && material.transmission.is_none()
            && diffuse_transmission.is_none()
        {
            return None;
        }
        // KHR_materials_volume without transmission or diffuse transmission changes nothing
        // (the spec ties the volume to a transmitting or translucent surface).
        let transmits = material.transmission.is_some() || diffuse_transmission.is_some();
        let volume = material.volume.filter(|_| transmits);
        Some(Self {
            clearcoat: material.clearcoat,
            sheen: material.sheen,
            transmission: material.transmission,
            diffuse_transmission,
            volume: volume.is_some(),
            sigma: volume.map_or(Vec3::ZERO, |v| v.sigma()),
            coat_normal: None,
        })
    }

    /// Whether any layer reads a texture (the kernels then look them up at each hit, see
    /// `render::layer_textures`).
    #[inline]
    pub fn has_textures(&self) -> bool {
        crate::scene::layers::any_texture(
            self.clearcoat.as_ref(),
            self.sheen.as_ref(),
            self.transmission.as_ref(),
            self.diffuse_transmission.as_ref(),
        )
    }

    /// These layers without texture references to textures the scene lacks (`texture_count`
    /// of them): the loader reports those, and the renderer must not index out of bounds.
    pub fn with_valid_textures(mut self, texture_count: usize) -> Self {
        let valid = |t: &mut Option<crate::scene::TextureRef>| {
            *t = t.filter(|r| r.texture < texture_count);
        };
        if let Some(c) = &mut self.clearcoat {
            valid(&mut c.texture);
            valid(&mut c.roughness_texture);
            c.normal_texture = c
                .normal_texture
                .filter(|n| n.texture.texture < texture_count);
        }
        if let Some(s) = &mut self.sheen {
            valid(&mut s.color_texture);
            valid(&mut s.roughness_texture);
        }
        if let Some(t) = &mut self.transmission {
            valid(&mut t.texture);
        }
        if let Some(d) = &mut self.diffuse_transmission {
            valid(&mut d.texture);
            valid(&mut d.color_texture);
        }
        self
    }

    /// Whether light may pass through the surface (then back faces are shaded whatever
    /// `doubleSided` says: a ray leaving a glass object meets them from inside).
    #[inline]
    pub fn transmits(&self) -> bool {
        self.transmission.is_some() || self.diffuse_transmission.is_some()
    }

    /// The BSDF at a hit: `base` (the material's metallic-roughness BRDF at the hit) with
    /// these layers (diffuse transmission goes into `base`'s diffuse lobe); `base_color` tints transmission, `roughness` is the base's perceptual
    /// roughness, `ior` the material's, and `front_face` says whether the ray arrived from
    /// outside (entering the volume) or inside.
    #[inline]
    pub fn bsdf(
        &self,
        base: MetallicRoughnessBsdf,
        base_color: Vec3,
        roughness: f32,
        ior: f32,
        front_face: bool,
    ) -> LayeredBsdf {
        // ior 0 (KHR_materials_ior's compatibility value) or nonsense: glass's 1.5.
        let ior = if ior.is_finite() && ior >= 1.0 {
            ior
        } else {
            1.5
        };
        let transmission = self.transmission.map(|t| {
            let eta = if self.volume && !front_face {
                1.0 / ior
            } else {
                ior
            };
            (
                t.factor,
                DielectricBsdf::new(eta, roughness, base_color, !self.volume)
                    .with_model(base.model),
            )
        });
        let base = match self.diffuse_transmission {
            Some(d) => base.with_diffuse_transmission(d.factor, d.color),
            None => base,
        };
        LayeredBsdf::new(
            base,
            transmission,
            self.sheen.map(|s| SheenBsdf::new(s.color, s.roughness)),
            self.clearcoat.map(|c| {
                let coat = ClearcoatBsdf::new(c.factor, c.roughness).with_model(base.model);
                match self.coat_normal {
                    Some(n) => coat.with_normal(n),
                    None => coat,
                }
            }),
        )
    }
}

/// `layers` with each textured factor multiplied by its texture's channel at `at` (clamped
/// to [0, 1], as the factors are): `clearcoatTexture` (R), `clearcoatRoughnessTexture` (G),
/// `sheenColorTexture` (RGB), `sheenRoughnessTexture` (A), `transmissionTexture` (R),
/// `diffuseTransmissionTexture` (A), `diffuseTransmissionColorTexture` (RGB).
#[inline]
pub fn at_hit(
    textures: &crate::texture::TextureEvaluator<'_>,
    at: &crate::texture::TexturePoint<'_>,
    layers: &ShadingLayers,
) -> ShadingLayers {
    let mut out = *layers;
    let lookup = |t| textures.value(at, t);
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
            s.color = (s.color * lookup(t).truncate()).clamp(Vec3::ZERO, Vec3::ONE);
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
    if let Some(d) = &mut out.diffuse_transmission {
        if let Some(t) = &d.texture {
            d.factor = (d.factor * lookup(t).w).clamp(0.0, 1.0);
        }
        if let Some(t) = &d.color_texture {
            d.color = (d.color * lookup(t).truncate()).clamp(Vec3::ZERO, Vec3::ONE);
        }
    }
    out
}

/// The clear coat's shading normal at `at`, in the local frame of `frame` (the BSDF's), or
/// `None` when it is the BSDF's own normal. With a `clearcoatNormalTexture` it is that map's
/// normal: as for the base's normal map ([`super::normal_map::at_hit`]) the map perturbs the
/// interpolated vertex normal `vertex_ns` (on the incoming side) in the mesh's tangent frame.
/// Without one it is `vertex_ns` itself when the base was normal-mapped (`base_mapped`): the
/// extension applies no normal mapping to a coat without its own texture, "even if normal
/// mapping is applied to the base material". Either is bent to reflect `si.wo` above the
/// surface. A coat map on a mesh without tangents leaves the coat on `vertex_ns` as well.
#[inline]
pub fn coat_normal(
    textures: &crate::texture::TextureEvaluator<'_>,
    at: &crate::texture::TexturePoint<'_>,
    vertex_ns: Vec3,
    base_mapped: bool,
    material: &super::ShadingMaterial,
    frame: &crate::bsdf::Frame,
) -> Option<Vec3> {
    use super::normal_map::{keep_reflection_above, perturbed_normal};
    let coat = material.layers?.clearcoat?;
    let si = at.si;
    let mapped = coat.normal_texture.and_then(|normal| {
        let tangent = si.tangent_to_world(si.interpolate(at.mesh.tangents.as_deref()?)?);
        let side = if si.front_face { 1.0 } else { -1.0 };
        let texel = textures.value(at, &normal.texture).truncate();
        let (n, _) = perturbed_normal(texel, normal.scale, side * vertex_ns, tangent)?;
        Some(side * n)
    });
    let n = match mapped {
        Some(n) => n,
        None if base_mapped => vertex_ns,
        // The BSDF's normal is the (bent) vertex normal already.
        None => return None,
    };
    Some(frame.to_local(keep_reflection_above(n, si.ng, si.wo)))
}
