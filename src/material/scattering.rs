//! The BSDF a glint material presents to the integrators, behind the [`Bsdf`] interface.
//!
//! Today's mapping of glTF's metallic-roughness model (see the module docs of
//! [`crate::material`]): a Lambertian lobe `f = ρ_d / π` plus a perfect mirror of reflectance
//! `R`. Sampling picks the mirror with probability `P_m = lum(R) / (lum(R) + lum(ρ_d))` and
//! the diffuse lobe otherwise (cosine-weighted), so each lobe's sample weight is its
//! reflectance over its selection probability; `pdf` is `(1 − P_m) · cos θ / π`, the density of
//! the only non-delta lobe. With `delta_only` (the direct integrator) the diffuse lobe is never
//! sampled: it is lit by light sampling alone and the mirror is chosen with probability 1.
//!
//! The path tracer uses the glTF metallic-roughness BRDF instead
//! ([`MetallicRoughnessBsdf`]): [`SurfaceBsdf`] is the one type both kernels hand to their
//! light sampling and continuation code.

use crate::bsdf::{
    Bsdf, BsdfSample, LambertBsdf, LayeredBsdf, MetallicRoughnessBsdf, same_hemisphere,
};
use crate::material::reflect;
use glam::{Vec2, Vec3};

/// Diffuse plus mirror, in the local shading frame (+Z the shading normal).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseMirror {
    /// Diffuse albedo ρ_d.
    pub diffuse: Vec3,
    /// Mirror reflectance R.
    pub mirror: Vec3,
    /// Probability of sampling the mirror lobe.
    p_mirror: f32,
}

/// Relative luminance (Rec. 709), the weight lobes are chosen by.
#[inline]
pub fn luminance(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

impl DiffuseMirror {
    /// The BSDF with these lobes; `delta_only` never samples the diffuse lobe.
    #[inline]
    pub fn new(diffuse: Vec3, mirror: Vec3, delta_only: bool) -> Self {
        let (ld, lm) = (luminance(diffuse).max(0.0), luminance(mirror).max(0.0));
        let p_mirror = if delta_only || ld <= 0.0 {
            if lm > 0.0 { 1.0 } else { 0.0 }
        } else {
            lm / (lm + ld)
        };
        Self {
            diffuse,
            mirror,
            p_mirror,
        }
    }

    /// Whether the diffuse lobe reflects anything (light sampling is worth a shadow ray).
    #[inline]
    pub fn has_diffuse(&self) -> bool {
        self.diffuse != Vec3::ZERO
    }
}

impl Bsdf for DiffuseMirror {
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        LambertBsdf {
            albedo: self.diffuse,
        }
        .eval(wo, wi)
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        (1.0 - self.p_mirror)
            * LambertBsdf {
                albedo: self.diffuse,
            }
            .pdf(wo, wi)
    }

    #[inline]
    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        if u_lobe < self.p_mirror {
            let wi = reflect(wo, Vec3::Z);
            return Some(BsdfSample {
                wi,
                weight: self.mirror / self.p_mirror,
                pdf: self.p_mirror,
                delta: true,
                transmission: false,
            });
        }
        let p_diffuse = 1.0 - self.p_mirror;
        if p_diffuse <= 0.0 {
            return None;
        }
        let mut s = LambertBsdf {
            albedo: self.diffuse,
        }
        .sample(wo, u_lobe, u)?;
        if !same_hemisphere(wo, s.wi) {
            return None;
        }
        s.weight /= p_diffuse;
        s.pdf *= p_diffuse;
        Some(s)
    }

    fn is_delta(&self) -> bool {
        self.diffuse == Vec3::ZERO
    }
}

/// The BSDF at a hit, as the integrators see it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SurfaceBsdf {
    /// Lambert plus perfect mirror (the direct integrator's mapping).
    DiffuseMirror(DiffuseMirror),
    /// The glTF metallic-roughness BRDF (the path tracer).
    MetallicRoughness(MetallicRoughnessBsdf),
    /// The metallic-roughness BRDF with KHR_materials layers (both integrators).
    Layered(LayeredBsdf),
}

impl SurfaceBsdf {
    /// The BSDF of a glint material at a hit with base colour `base_color`: the glTF
    /// metallic-roughness BRDF, or (`delta_only`, the direct integrator) the Lambert and mirror
    /// mapping whose diffuse part is never sampled.
    #[inline]
    pub fn for_material(
        base_color: Vec3,
        material: &crate::material::ShadingMaterial,
        delta_only: bool,
    ) -> Self {
        Self::for_material_at(
            base_color,
            (material.metallic, material.roughness),
            material,
            delta_only,
        )
    }

    /// [`SurfaceBsdf::for_material`] with the hit's own metallic and roughness (the factors
    /// times the metallic-roughness texture) for the path tracer's BRDF; the direct
    /// integrator's mapping keeps the material's factors.
    #[inline]
    pub fn for_material_at(
        base_color: Vec3,
        (metallic, roughness): (f32, f32),
        material: &crate::material::ShadingMaterial,
        delta_only: bool,
    ) -> Self {
        if delta_only {
            SurfaceBsdf::DiffuseMirror(DiffuseMirror::new(
                base_color * material.diffuse_weight,
                base_color * material.mirror_weight,
                true,
            ))
        } else {
            SurfaceBsdf::MetallicRoughness(
                MetallicRoughnessBsdf::new(base_color, metallic, roughness)
                    .with_dielectric_fresnel(
                        material.ior,
                        material.specular,
                        material.specular_color,
                    ),
            )
        }
    }
}

impl SurfaceBsdf {
    /// The BSDF at a hit: [`SurfaceBsdf::for_material`] for materials without
    /// KHR_materials layers; with layers, the [`LayeredBsdf`] in both integrators (the
    /// direct one lights its non-delta lobes by light sampling and follows its delta lobes).
    /// `front_face` says whether the ray arrived from outside (for a volume's ior ratio);
    /// `(metallic, roughness)` are the hit's own (factors times the metallic-roughness
    /// texture).
    #[inline]
    pub fn for_hit(
        base_color: Vec3,
        metallic_roughness: (f32, f32),
        material: &crate::material::ShadingMaterial,
        delta_only: bool,
        front_face: bool,
    ) -> Self {
        Self::for_hit_with_layers(
            base_color,
            metallic_roughness,
            material,
            material.layers.as_ref(),
            delta_only,
            front_face,
        )
    }

    /// [`SurfaceBsdf::for_hit`] with the hit's own `layers` (the material's, with their
    /// textures applied at the hit) in place of the material's.
    #[inline]
    pub fn for_hit_with_layers(
        base_color: Vec3,
        (metallic, roughness): (f32, f32),
        material: &crate::material::ShadingMaterial,
        layers: Option<&crate::material::layers::ShadingLayers>,
        delta_only: bool,
        front_face: bool,
    ) -> Self {
        let Some(layers) = layers else {
            return Self::for_material_at(base_color, (metallic, roughness), material, delta_only);
        };
        let base = MetallicRoughnessBsdf::new(base_color, metallic, roughness)
            .with_dielectric_fresnel(material.ior, material.specular, material.specular_color);
        SurfaceBsdf::Layered(layers.bsdf(base, base_color, roughness, material.ior, front_face))
    }

    /// Whether the BSDF may transmit (light samples and continuations below the surface are
    /// then allowed).
    #[inline]
    pub fn transmits(&self) -> bool {
        matches!(self, SurfaceBsdf::Layered(b) if b.transmission.is_some())
    }
}

impl Bsdf for SurfaceBsdf {
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        match self {
            SurfaceBsdf::DiffuseMirror(b) => b.eval(wo, wi),
            SurfaceBsdf::MetallicRoughness(b) => b.eval(wo, wi),
            SurfaceBsdf::Layered(b) => b.eval(wo, wi),
        }
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            SurfaceBsdf::DiffuseMirror(b) => b.pdf(wo, wi),
            SurfaceBsdf::MetallicRoughness(b) => b.pdf(wo, wi),
            SurfaceBsdf::Layered(b) => b.pdf(wo, wi),
        }
    }

    #[inline]
    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        match self {
            SurfaceBsdf::DiffuseMirror(b) => b.sample(wo, u_lobe, u),
            SurfaceBsdf::MetallicRoughness(b) => b.sample(wo, u_lobe, u),
            SurfaceBsdf::Layered(b) => b.sample(wo, u_lobe, u),
        }
    }

    #[inline]
    fn is_delta(&self) -> bool {
        match self {
            SurfaceBsdf::DiffuseMirror(b) => b.is_delta(),
            SurfaceBsdf::MetallicRoughness(b) => b.is_delta(),
            SurfaceBsdf::Layered(b) => b.is_delta(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sample weights average to the total reflectance (ρ_d + R at normal incidence), and
    /// a diffuse sample's weight equals eval · cos / pdf.
    #[test]
    fn sampling_is_consistent_with_eval_and_pdf() {
        let b = DiffuseMirror::new(Vec3::new(0.5, 0.3, 0.1), Vec3::new(0.2, 0.2, 0.4), false);
        let wo = Vec3::new(0.3, -0.2, 0.9).normalize();
        let n = 200_000;
        let mut sum = Vec3::ZERO;
        for i in 0..n {
            let u_lobe = (i as f32 + 0.5) / n as f32;
            let u = Vec2::new(
                ((i as u64 * 7919) % n as u64) as f32 / n as f32,
                ((i as u64 * 104_729) % n as u64) as f32 / n as f32,
            );
            let Some(s) = b.sample(wo, u_lobe, u) else {
                continue;
            };
            if !s.delta {
                let expect = b.eval(wo, s.wi) * s.wi.z / b.pdf(wo, s.wi);
                assert!((s.weight - expect).abs().max_element() < 1e-4);
            }
            sum += s.weight;
        }
        let mean = sum / n as f32;
        let total = b.diffuse + b.mirror;
        assert!(
            (mean - total).abs().max_element() < 5e-3,
            "{mean} vs {total}"
        );
    }

    #[test]
    fn delta_only_always_takes_the_mirror() {
        let b = DiffuseMirror::new(Vec3::ONE * 0.5, Vec3::ONE * 0.5, true);
        let s = b.sample(Vec3::Z, 0.99, Vec2::splat(0.5)).unwrap();
        assert!(s.delta && s.weight == Vec3::ONE * 0.5);
        assert_eq!(b.pdf(Vec3::Z, Vec3::Z), 0.0);
    }
}
