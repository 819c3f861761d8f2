//! The clear coat of KHR_materials_clearcoat: a second GGX specular layer over the material.
//!
//! Parameters: `clearcoat` `c` ∈ [0, 1] (factor × texture R), `clearcoatRoughness` `r`
//! (factor × texture G; `α = r²`), the coat's index 1.5 (`f0 = 0.04`). The extension's layering
//! (its `fresnel_coat`, with Schlick's Fresnel at the view angle), for `wo` above the
//! surface:
//!
//! ```text
//! Fc(wo)   = 0.04 + 0.96 (1 − |n·wo|)⁵
//! f_coat   = c · Fc(wo) · D(h) G2(wo, wi) / (4 |n·wo| |n·wi|)          (h = normalize(wo + wi))
//! f        = f_coat + (1 − c · Fc(wo)) · f_base
//! ```
//!
//! Because `Fc` is taken at `n·wo` rather than at the half vector, the spec's coated material
//! is not reciprocal (it is a rasteriser's formula); glint follows the spec. The energy rule
//! holds: the coat takes `c Fc` of the light and the base gets the rest, so a base with
//! `∫ f_base cos ≤ 1` stays ≤ 1 coated.
//!
//! The coat normal is the shading normal: `clearcoatNormalTexture` is not applied yet (the
//! loader warns once per material that has one).
//!
//! **Sampling.** A visible normal for `wo`, reflected (`pdf = Dv(wo, h)/(4|wo·h|)`); below
//! [`SMOOTH_ALPHA`](super::microfacet::SMOOTH_ALPHA) a delta mirror of reflectance `c Fc(wo)`.

use super::microfacet::{TrowbridgeReitz, reflect};
use super::{Bsdf, BsdfSample};
use glam::{Vec2, Vec3};

/// The clear-coat lobe alone, `c · Fc(wo) · D · V` (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClearcoatBsdf {
    /// Coat strength `c` in [0, 1].
    pub factor: f32,
    /// The coat's GGX distribution.
    pub distribution: TrowbridgeReitz,
}

/// The coat's Fresnel reflectance at normal incidence (index 1.5 against air).
pub const COAT_F0: f32 = 0.04;

impl ClearcoatBsdf {
    /// A coat of strength `factor` and perceptual `roughness` (both clamped to [0, 1]).
    pub fn new(factor: f32, roughness: f32) -> Self {
        Self {
            factor: if factor.is_finite() {
                factor.clamp(0.0, 1.0)
            } else {
                0.0
            },
            distribution: TrowbridgeReitz::from_roughness(roughness),
        }
    }

    /// `c · Fc(n·wo)`: the share of light the coat takes, and the weight of its lobe.
    #[inline]
    pub fn weight(&self, cos_o: f32) -> f32 {
        let w = (1.0 - cos_o.abs()).clamp(0.0, 1.0);
        let w5 = w * w * w * w * w;
        self.factor * (COAT_F0 + (1.0 - COAT_F0) * w5)
    }

    /// The factor on the base layer, `1 − c · Fc(n·wo)`.
    #[inline]
    pub fn base_attenuation(&self, cos_o: f32) -> f32 {
        1.0 - self.weight(cos_o)
    }
}

impl Bsdf for ClearcoatBsdf {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 || self.distribution.is_smooth() {
            return Vec3::ZERO;
        }
        let h = (wo + wi).normalize_or_zero();
        if h == Vec3::ZERO {
            return Vec3::ZERO;
        }
        let tr = &self.distribution;
        Vec3::splat(self.weight(wo.z) * tr.d(h) * tr.g2(wo, wi) / (4.0 * wo.z * wi.z))
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 || self.distribution.is_smooth() {
            return 0.0;
        }
        let h = (wo + wi).normalize_or_zero();
        if h == Vec3::ZERO {
            return 0.0;
        }
        self.distribution.reflection_pdf(wo, h)
    }

    fn sample(&self, wo: Vec3, _u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        if self.distribution.is_smooth() {
            return Some(BsdfSample {
                wi: Vec3::new(-wo.x, -wo.y, wo.z),
                weight: Vec3::splat(self.weight(wo.z)),
                pdf: 1.0,
                delta: true,
                transmission: false,
            });
        }
        let wi = reflect(wo, self.distribution.sample_visible(wo, u));
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf(wo, wi);
        if !pdf.is_finite() || pdf.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.eval(wo, wi) * (wi.z / pdf),
            pdf,
            delta: false,
            transmission: false,
        })
    }

    fn is_delta(&self) -> bool {
        self.distribution.is_smooth()
    }
}
