//! The glTF material stack with its KHR_materials layers: clear coat over sheen over the base,
//! whose dielectric part may transmit.
//!
//! With `m` the metalness, `T` the transmission (`transmissionFactor × texture R`), `f_mr` the
//! metallic-roughness BRDF ([`MetallicRoughnessBsdf`]) and `f_d` the dielectric interface
//! ([`DielectricBsdf`], tinted by the base colour):
//!
//! ```text
//! base   = (1 − (1 − m) T) · f_mr[metallic = m / (1 − (1 − m) T)]  +  (1 − m) T · f_d
//!        = m · metal + (1 − m)(1 − T) · opaque dielectric + (1 − m) T · transmitting dielectric
//! sheened = f_sheen + base · min(1 − max(C) E(n·wo), 1 − max(C) E(n·wi))   (KHR_materials_sheen)
//! f       = f_coat + (1 − c Fc(n·wo)) · sheened                            (KHR_materials_clearcoat)
//! ```
//!
//! which is KHR_materials_transmission's `mix(diffuse, specular_btdf, T)` under the dielectric's
//! Fresnel layer, and the sheen and clear-coat extensions' layering rules, in the order the
//! glTF PBR "next" model stacks them. The transmitting dielectric uses the exact dielectric
//! Fresnel (so that total internal reflection leaving a volume is right) where the opaque
//! part keeps Appendix B's Schlick `fresnel_mix`.
//!
//! **Sampling.** One of the lobes — coat, sheen, metallic-roughness, transmitting dielectric —
//! is chosen with probability proportional to its weight seen from `wo`: `c Fc(n·wo)`,
//! `max(C) E(n·wo)`, and the rest `(1 − c Fc)(1 − max(C) E)` split as `1 − (1 − m)T : (1 − m)T`.
//! The chosen lobe draws `wi`; a non-delta draw is weighted by the whole stack,
//! `f · |cos θi| / Σ_k P_k pdf_k(wi)`, and `pdf` returns that same mixture. A delta draw
//! (smooth coat, smooth specular, smooth glass) gets its lobe's delta weight times the layer
//! factors at its mirror/refracted direction over `P_k`, and its discrete probability as
//! `pdf`; `eval` and `pdf` never contain delta lobes.
//!
//! `wo` must be above the surface (the integrators orient the shading frame toward `wo`);
//! `wi` may be below it (transmission).

use super::{
    Bsdf, BsdfFlags, BsdfSample, ClearcoatBsdf, DielectricBsdf, MetallicRoughnessBsdf, SheenBsdf,
};
use glam::{Vec2, Vec3};

/// The layered glTF BSDF (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayeredBsdf {
    /// The metallic-roughness part, with its metalness renormalised.
    pub base: MetallicRoughnessBsdf,
    /// The transmitting dielectric and its weight `(1 − m) T`.
    pub transmission: Option<(f32, DielectricBsdf)>,
    /// The sheen lobe.
    pub sheen: Option<SheenBsdf>,
    /// The clear coat.
    pub clearcoat: Option<ClearcoatBsdf>,
}

/// The lobes of the stack, in selection order.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Lobe {
    Coat,
    Sheen,
    Base,
    Transmission,
}

const LOBES: [Lobe; 4] = [Lobe::Coat, Lobe::Sheen, Lobe::Base, Lobe::Transmission];

impl LayeredBsdf {
    /// The stack over `base` (whose `metallic` is the material's `m`), transmitting a share
    /// `transmission` ∈ [0, 1] of its dielectric part through `dielectric`.
    pub fn new(
        mut base: MetallicRoughnessBsdf,
        transmission: Option<(f32, DielectricBsdf)>,
        sheen: Option<SheenBsdf>,
        clearcoat: Option<ClearcoatBsdf>,
    ) -> Self {
        let transmission = transmission.and_then(|(t, d)| {
            let t = if t.is_finite() {
                t.clamp(0.0, 1.0)
            } else {
                0.0
            };
            let w = (1.0 - base.metallic) * t;
            (w > 0.0).then_some((w, d))
        });
        if let Some((w, _)) = transmission {
            let rest = 1.0 - w;
            base.metallic = if rest > 0.0 {
                (base.metallic / rest).clamp(0.0, 1.0)
            } else {
                0.0
            };
        }
        Self {
            base,
            transmission,
            sheen,
            clearcoat,
        }
    }

    /// Weight of the metallic-roughness part, `1 − (1 − m) T`.
    #[inline]
    fn base_weight(&self) -> f32 {
        1.0 - self.transmission.map_or(0.0, |(w, _)| w)
    }

    /// The factor the coat and the sheen put on the base lobes for `(wo, wi)`.
    #[inline]
    fn base_factor(&self, wo: Vec3, wi: Vec3) -> f32 {
        let coat = self.clearcoat.map_or(1.0, |c| c.base_attenuation_at(wo));
        let sheen = self.sheen.map_or(1.0, |s| s.albedo_scaling(wo.z, wi.z));
        coat * sheen
    }

    /// Unnormalised selection weights of the lobes for `wo`.
    #[inline]
    fn weights(&self, wo: Vec3) -> [f32; 4] {
        let coat = self.clearcoat.map_or(0.0, |c| c.weight_at(wo));
        let sheen = self.sheen.map_or(0.0, |s| s.albedo(wo.z));
        let rest = (1.0 - coat) * (1.0 - sheen).max(0.0);
        let t = self.transmission.map_or(0.0, |(w, _)| w);
        [coat, sheen, rest * (1.0 - t), rest * t]
    }

    /// Selection probabilities for `wo` (all zero when nothing reflects).
    #[inline]
    fn probabilities(&self, wo: Vec3) -> [f32; 4] {
        let w = self.weights(wo);
        let sum: f32 = w.iter().sum();
        if sum > 0.0 && sum.is_finite() {
            w.map(|x| x / sum)
        } else {
            [0.0; 4]
        }
    }

    #[inline]
    fn lobe_eval(&self, lobe: Lobe, wo: Vec3, wi: Vec3) -> Vec3 {
        match lobe {
            Lobe::Coat => self.clearcoat.map_or(Vec3::ZERO, |c| c.eval(wo, wi)),
            Lobe::Sheen => self.sheen.map_or(Vec3::ZERO, |s| s.eval(wo, wi)),
            Lobe::Base => self.base.eval(wo, wi) * self.base_weight(),
            Lobe::Transmission => self
                .transmission
                .map_or(Vec3::ZERO, |(w, d)| d.eval(wo, wi) * w),
        }
    }

    #[inline]
    fn lobe_pdf(&self, lobe: Lobe, wo: Vec3, wi: Vec3) -> f32 {
        match lobe {
            Lobe::Coat => self.clearcoat.map_or(0.0, |c| c.pdf(wo, wi)),
            Lobe::Sheen => self.sheen.map_or(0.0, |s| s.pdf(wo, wi)),
            Lobe::Base => self.base.pdf(wo, wi),
            Lobe::Transmission => self.transmission.map_or(0.0, |(_, d)| d.pdf(wo, wi)),
        }
    }

    #[inline]
    fn lobe_sample(&self, lobe: Lobe, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        match lobe {
            Lobe::Coat => self.clearcoat?.sample(wo, u_lobe, u),
            Lobe::Sheen => self.sheen?.sample(wo, u_lobe, u),
            Lobe::Base => self.base.sample(wo, u_lobe, u),
            Lobe::Transmission => self.transmission?.1.sample(wo, u_lobe, u),
        }
    }
}

impl Bsdf for LayeredBsdf {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        let base = self.lobe_eval(Lobe::Base, wo, wi) + self.lobe_eval(Lobe::Transmission, wo, wi);
        let top = self.lobe_eval(Lobe::Coat, wo, wi) + self.lobe_eval(Lobe::Sheen, wo, wi);
        top + base * self.base_factor(wo, wi)
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 {
            return 0.0;
        }
        let p = self.probabilities(wo);
        LOBES
            .iter()
            .zip(p)
            .filter(|(_, q)| *q > 0.0)
            .map(|(&lobe, q)| q * self.lobe_pdf(lobe, wo, wi))
            .sum()
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let p = self.probabilities(wo);
        // Pick the lobe and reuse the rest of u_lobe inside it (rounding past the last
        // cumulative bound falls to the last lobe that can be chosen).
        let mut lo = 0.0;
        let mut chosen = None;
        let mut last = None;
        for (k, &q) in p.iter().enumerate() {
            if q <= 0.0 {
                continue;
            }
            if u_lobe < lo + q {
                chosen = Some((k, ((u_lobe - lo) / q).clamp(0.0, 1.0 - f32::EPSILON)));
                break;
            }
            lo += q;
            last = Some((k, 1.0 - f32::EPSILON));
        }
        let chosen = chosen.or(last);
        let (k, u_inner) = chosen?;
        let lobe = LOBES[k];
        let q = p[k];
        let s = self.lobe_sample(lobe, wo, u_inner, u)?;
        if s.delta {
            let factor = match lobe {
                Lobe::Coat | Lobe::Sheen => 1.0,
                Lobe::Base => self.base_weight() * self.base_factor(wo, s.wi),
                Lobe::Transmission => {
                    self.transmission.map_or(0.0, |(w, _)| w) * self.base_factor(wo, s.wi)
                }
            };
            return Some(BsdfSample {
                weight: s.weight * (factor / q),
                pdf: s.pdf * q,
                ..s
            });
        }
        let pdf = self.pdf(wo, s.wi);
        if !pdf.is_finite() || pdf.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        Some(BsdfSample {
            weight: self.eval(wo, s.wi) * (s.wi.z.abs() / pdf),
            pdf,
            ..s
        })
    }

    fn flags(&self) -> BsdfFlags {
        let mut flags = BsdfFlags::empty();
        if self.base_weight() > 0.0 {
            flags |= self.base.flags();
        }
        if let Some((_, d)) = self.transmission {
            flags |= d.flags();
        }
        if let Some(s) = self.sheen {
            flags |= s.flags();
        }
        if let Some(c) = self.clearcoat {
            flags |= c.flags();
        }
        flags
    }
}
