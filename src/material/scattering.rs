//! The BSDF a glint material presents at a hit, behind the [`Bsdf`] interface: glTF's
//! metallic-roughness BRDF ([`MetallicRoughnessBsdf`], with KHR_materials_ior and
//! KHR_materials_specular), or, for a material with KHR_materials layers (clear coat, sheen,
//! transmission, diffuse transmission, volume), the [`LayeredBsdf`] over it. Built only by the surface front end
//! ([`super::at_hit`](fn@super::at_hit)); the same for every integrator.

use crate::bsdf::{Bsdf, BsdfFlags, BsdfSample, LayeredBsdf, MetallicRoughnessBsdf};
use crate::material::ShadingMaterial;
use crate::material::layers::ShadingLayers;
use glam::{Vec2, Vec3};

/// The BSDF at a hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SurfaceBsdf {
    /// The glTF metallic-roughness BRDF.
    MetallicRoughness(MetallicRoughnessBsdf),
    /// The metallic-roughness BRDF under KHR_materials layers.
    Layered(LayeredBsdf),
}

impl SurfaceBsdf {
    /// The BSDF of `material` at a hit with base colour `base_color` and the hit's own
    /// `(metallic, roughness)` (factors times the metallic-roughness texture) and
    /// `specular_tint` (the specular-glossiness texture's RGB, white without); `layers` are
    /// the material's layers with their textures applied at the hit. `front_face` says
    /// whether the ray arrived from outside (a volume's ior ratio depends on it).
    #[inline]
    pub fn new(
        base_color: Vec3,
        (metallic, roughness): (f32, f32),
        specular_tint: Vec3,
        material: &ShadingMaterial,
        layers: Option<&ShadingLayers>,
        front_face: bool,
    ) -> Self {
        Self::anisotropic(
            base_color,
            (metallic, roughness),
            specular_tint,
            0.0,
            material,
            layers,
            front_face,
        )
    }

    /// [`new`](Self::new) with KHR_materials_anisotropy's strength at the hit (0: isotropic,
    /// exactly [`new`](Self::new)): the metal's and the opaque dielectric's specular lobes
    /// stretch along the local X axis of the BSDF's frame (see
    /// [`MetallicRoughnessBsdf::with_anisotropy`]). Transmission and the coat stay isotropic.
    #[inline]
    pub fn anisotropic(
        base_color: Vec3,
        (metallic, roughness): (f32, f32),
        specular_tint: Vec3,
        anisotropy: f32,
        material: &ShadingMaterial,
        layers: Option<&ShadingLayers>,
        front_face: bool,
    ) -> Self {
        let base = MetallicRoughnessBsdf::new(base_color, metallic, roughness)
            .with_anisotropy(roughness, anisotropy)
            .with_dielectric_fresnel(
                material.ior,
                material.specular,
                material.specular_color * specular_tint,
            )
            .with_model(material.brdf);
        match layers {
            None => SurfaceBsdf::MetallicRoughness(base),
            Some(layers) => SurfaceBsdf::Layered(layers.bsdf(
                base,
                base_color,
                roughness,
                material.ior,
                front_face,
            )),
        }
    }
}

impl Bsdf for SurfaceBsdf {
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        match self {
            SurfaceBsdf::MetallicRoughness(b) => b.eval(wo, wi),
            SurfaceBsdf::Layered(b) => b.eval(wo, wi),
        }
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            SurfaceBsdf::MetallicRoughness(b) => b.pdf(wo, wi),
            SurfaceBsdf::Layered(b) => b.pdf(wo, wi),
        }
    }

    #[inline]
    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        match self {
            SurfaceBsdf::MetallicRoughness(b) => b.sample(wo, u_lobe, u),
            SurfaceBsdf::Layered(b) => b.sample(wo, u_lobe, u),
        }
    }

    #[inline]
    fn flags(&self) -> BsdfFlags {
        match self {
            SurfaceBsdf::MetallicRoughness(b) => b.flags(),
            SurfaceBsdf::Layered(b) => b.flags(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Material;

    /// A layered material with transmission says so in its flags; a plain one reflects only.
    #[test]
    fn flags_say_whether_the_surface_transmits() {
        let plain = ShadingMaterial::new(&Material::default(), 0);
        let b = SurfaceBsdf::new(Vec3::ONE, (1.0, 1.0), Vec3::ONE, &plain, None, true);
        assert!(!b.flags().transmits() && b.flags().has_density());
        let glass = Material {
            transmission: Some(crate::scene::layers::Transmission {
                factor: 1.0,
                texture: None,
            }),
            ..Material::default()
        };
        let glass = ShadingMaterial::new(&glass, 0);
        assert!(glass.may_transmit());
        let b = SurfaceBsdf::new(
            Vec3::ONE,
            (0.0, 0.0),
            Vec3::ONE,
            &glass,
            glass.layers.as_ref(),
            true,
        );
        assert!(b.flags().transmits() && b.flags().is_specular_only());
    }
}
