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
//! The coat normal `n` is the coat's own (`clearcoatNormalTexture`), else the interpolated
//! vertex normal: the extension says that without a texture of its own "no normal mapping is
//! applied to the clear coat layer, even if normal mapping is applied to the base material".
//! When it differs from the base's shading normal, [`ClearcoatBsdf::with_normal`] gives it in
//! the base's local frame, and every `n·` above, `D`, `G2` and the sampling are taken in a
//! frame around it (the base layer keeps its own normal). The integrator multiplies every
//! lobe by the base frame's cosine `wi·z`; the coat's lobe is the coat's `f · (n·wi)`, so
//! [`Bsdf::eval`] returns it times `(n·wi)/(wi·z)`: the coat's light then follows its own
//! normal alone, and a normal-mapped base does not modulate a smooth coat's highlight.
//!
//! **Sampling.** A visible normal for `wo`, reflected (`pdf = Dv(wo, h)/(4|wo·h|)`); below
//! [`SMOOTH_ALPHA`](super::microfacet::SMOOTH_ALPHA) a delta mirror of reflectance `c Fc(wo)`.
//!
//! **Energy compensation** ([`BrdfModel::Compensated`], the renderer's default). The spec's
//! coat lobe `D G2 / (4 |n·wo| |n·wi|)` carries no Fresnel (the layer's weight `c Fc(wo)`
//! does) and reflects only its single-scatter albedo `E0(n·wo, α)` of what the mix gives it,
//! so a coat over a base of albedo 1 reflects `1 − c Fc(wo) (1 − E0(wo))`. Compensated, the
//! lobe is scaled by `1/E0(n·wo)` (Turquin's factor for a white lobe): the coat then reflects
//! `c Fc(wo)` exactly, as the layering means it to, and a coat over a white compensated base
//! reflects 1. The sampler is the compensated lobes' mixture of folded reflection and cosine
//! draws ([`compensated_sampling`](super::compensated_sampling), `u_lobe` choosing).
//! [`BrdfModel::Spec`]: the formulas above, single scattering.

use super::compensated_sampling;
use super::energy::{ggx_albedo, white_lobe_scale};
use super::microfacet::{TrowbridgeReitz, reflect};
use super::{BrdfModel, Bsdf, BsdfFlags, BsdfSample, Frame};
use glam::{Vec2, Vec3};

/// The clear-coat lobe alone, `c · Fc(wo) · D · V` (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClearcoatBsdf {
    /// Coat strength `c` in [0, 1].
    pub factor: f32,
    /// The coat's GGX distribution.
    pub distribution: TrowbridgeReitz,
    /// The coat's own normal frame in the local frame of the BSDF (`None`: the local +Z).
    pub frame: Option<Frame>,
    /// Single scattering exactly ([`BrdfModel::Spec`]) or energy-compensated.
    pub model: BrdfModel,
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
            frame: None,
            model: BrdfModel::Spec,
        }
    }

    /// The same coat under `model` ([`new`](Self::new) gives [`BrdfModel::Spec`]).
    pub fn with_model(self, model: BrdfModel) -> Self {
        Self { model, ..self }
    }

    /// The factor on the coat lobe for `n·wo = cos_o` in the coat's frame: `1/E0(cos_o, α)`
    /// compensated, 1 for [`BrdfModel::Spec`].
    #[inline]
    fn energy_scale(&self, cos_o: f32) -> f32 {
        match self.model {
            BrdfModel::Spec => 1.0,
            BrdfModel::Compensated => {
                let a = &self.distribution;
                white_lobe_scale(ggx_albedo(cos_o, (a.alpha_x * a.alpha_y).sqrt()).e0)
            }
        }
    }

    /// This coat with its own unit normal `n`, given in the BSDF's local frame (a normal at
    /// or below the local horizon, or not finite, keeps the local +Z).
    pub fn with_normal(self, n: Vec3) -> Self {
        let n = n.normalize_or_zero();
        let frame = (n.is_finite() && n.z > 0.0 && n != Vec3::Z).then(|| Frame::from_normal(n));
        Self { frame, ..self }
    }

    /// `w` in the coat's frame.
    #[inline]
    fn local(&self, w: Vec3) -> Vec3 {
        self.frame.map_or(w, |f| f.to_local(w))
    }

    /// `c · Fc(n·wo)` for `wo` in the BSDF's local frame, with the coat's own normal.
    #[inline]
    pub fn weight_at(&self, wo: Vec3) -> f32 {
        self.weight(self.local(wo).z.max(0.0))
    }

    /// `1 − c · Fc(n·wo)` for `wo` in the BSDF's local frame, with the coat's own normal.
    #[inline]
    pub fn base_attenuation_at(&self, wo: Vec3) -> f32 {
        1.0 - self.weight_at(wo)
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
        if wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        match &self.frame {
            None => self.eval_local(wo, wi),
            Some(f) => {
                // The coat's cosine, not the base frame's (module documentation).
                let wi_coat = f.to_local(wi);
                self.eval_local(f.to_local(wo), wi_coat) * (wi_coat.z.max(0.0) / wi.z)
            }
        }
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wi.z <= 0.0 {
            return 0.0;
        }
        self.pdf_local(self.local(wo), self.local(wi))
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        let mut s = self.sample_local(self.local(wo), u_lobe, u)?;
        if let Some(f) = &self.frame {
            s.wi = f.to_world(s.wi);
            if s.wi.z <= 0.0 {
                return None;
            }
            // The weight stays the coat frame's `f · (n·wi) / pdf`: `eval` times the base
            // frame's cosine over the pdf is the same number.
        }
        Some(s)
    }

    fn flags(&self) -> BsdfFlags {
        BsdfFlags::REFLECTION | BsdfFlags::microfacet(self.distribution.is_smooth())
    }
}

impl ClearcoatBsdf {
    /// [`Bsdf::eval`] with `wo`, `wi` in the coat's frame.
    fn eval_local(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 || self.distribution.is_smooth() {
            return Vec3::ZERO;
        }
        let h = (wo + wi).normalize_or_zero();
        if h == Vec3::ZERO {
            return Vec3::ZERO;
        }
        let tr = &self.distribution;
        Vec3::splat(
            self.weight(wo.z) * self.energy_scale(wo.z) * tr.d(h) * tr.g2(wo, wi)
                / (4.0 * wo.z * wi.z),
        )
    }

    /// [`Bsdf::pdf`] with `wo`, `wi` in the coat's frame.
    fn pdf_local(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 || self.distribution.is_smooth() {
            return 0.0;
        }
        if self.model == BrdfModel::Compensated {
            return compensated_sampling::pdf(&self.distribution, wo, wi);
        }
        let h = (wo + wi).normalize_or_zero();
        if h == Vec3::ZERO {
            return 0.0;
        }
        self.distribution.reflection_pdf(wo, h)
    }

    /// [`Bsdf::sample`] in the coat's frame (weight with the coat frame's cosine).
    fn sample_local(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
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
        let wi = match self.model {
            BrdfModel::Spec => reflect(wo, self.distribution.sample_visible(wo, u)),
            BrdfModel::Compensated => {
                compensated_sampling::sample(&self.distribution, wo, u_lobe, u)
            }
        };
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf_local(wo, wi);
        if !pdf.is_finite() || pdf.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.eval_local(wo, wi) * (wi.z / pdf),
            pdf,
            delta: false,
            transmission: false,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A coat with its own normal `n` is the untilted coat rotated onto `n`: for directions
    /// `a`, `b` above both horizons, f_n(R a, R b) · (R b)·z = f(a, b) · b·z (the coat's
    /// cosine, whatever the base frame's) and p_n(R a, R b) = p(a, b), with R the coat frame's
    /// rotation; and a sample's direction lies in the rotated lobe.
    #[test]
    fn a_tilted_coat_normal_rotates_the_lobe() {
        let plain = ClearcoatBsdf::new(0.8, 0.4);
        let n = Vec3::new(0.3, -0.2, 1.0).normalize();
        let tilted = plain.with_normal(n);
        let frame = Frame::from_normal(n);
        let dirs = [
            Vec3::new(0.1, 0.2, 1.0),
            Vec3::new(-0.3, 0.1, 0.8),
            Vec3::new(0.2, -0.25, 0.9),
        ]
        .map(Vec3::normalize);
        for a in dirs {
            for b in dirs {
                let (ra, rb) = (frame.to_world(a), frame.to_world(b));
                assert!(ra.z > 0.0 && rb.z > 0.0);
                let (f, f_n) = (plain.eval(a, b).x * b.z, tilted.eval(ra, rb).x * rb.z);
                assert!((f - f_n).abs() <= 1e-4 * f.max(1e-3), "{f} vs {f_n}");
                let (p, p_n) = (plain.pdf(a, b), tilted.pdf(ra, rb));
                assert!((p - p_n).abs() <= 1e-4 * p.max(1e-3), "{p} vs {p_n}");
                assert!((plain.weight(a.z) - tilted.weight_at(ra)).abs() < 1e-5);
            }
        }
        // The untilted normal (or one below the horizon) leaves the coat as it was.
        assert_eq!(plain.with_normal(Vec3::Z), plain);
        assert_eq!(plain.with_normal(-Vec3::Z), plain);
        // Sampling in the tilted frame: the sample's pdf is the tilted pdf, and its weight
        // is f · cos(base) / pdf.
        let wo = frame.to_world(dirs[0]);
        let s = tilted
            .sample(wo, 0.5, Vec2::new(0.3, 0.6))
            .expect("a sample");
        let pdf = tilted.pdf(wo, s.wi);
        assert!((s.pdf - pdf).abs() <= 1e-4 * pdf);
        let w = tilted.eval(wo, s.wi).x * s.wi.z / pdf;
        assert!((s.weight.x - w).abs() <= 1e-4 * w.max(1e-3));
    }
}
