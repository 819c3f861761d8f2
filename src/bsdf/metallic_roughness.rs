//! The glTF 2.0 metallic-roughness BRDF, as the glTF specification's Appendix B defines it,
//! with the Fresnel parameters of KHR_materials_ior and KHR_materials_specular.
//!
//! With `h = normalize(wo + wi)`, `c = |wo·h|`, `w = (1 − c)⁵`, both directions above the
//! surface, and `α = roughness²`:
//!
//! ```text
//! specular_brdf = D(h) · V(wo, wi),   V = G2(wo, wi) / (4 |n·wo| |n·wi|)    (GGX, Smith
//!                                                                           height-correlated)
//! F_metal  = baseColor + (1 − baseColor) · w                           (conductor_fresnel)
//! F_diel   = f0 + (f90 − f0) · w                                       (fresnel_mix)
//!   f0     = min(((ior − 1)/(ior + 1))² · specularColor, 1) · specular, f90 = specular
//! dielectric_brdf = F_diel · specular_brdf + (1 − max(F_diel)) · baseColor / π
//! metal_brdf      = F_metal · specular_brdf
//! f = (1 − metallic) · dielectric_brdf + metallic · metal_brdf
//! ```
//!
//! Without the extensions (`ior = 1.5`, `specular = 1`, `specularColor = 1`) this is Appendix
//! B's `mix(diffuse_brdf, specular_brdf, 0.04 + 0.96 w)` for the dielectric. `ior = 0` (the
//! specular-glossiness compatibility mode of KHR_materials_ior) gives `f0 = 1`, a Fresnel of 1.
//! The model is not energy conserving in general: the spec says so itself (its `fresnel_mix`
//! weights the diffuse by `1 − F(h)` while the specular lobe loses energy to masking), and
//! it may reflect a little more than it receives for a white base at grazing angles.
//!
//! **Sampling.** A lobe is chosen with probabilities proportional to estimated lobe albedos,
//! taking Schlick's Fresnel at `n·wo` in place of `wo·h`:
//! `s = (1 − metallic) · mean(F_diel(n·wo)) + metallic · mean(F_metal(n·wo))`,
//! `d = (1 − metallic) · (1 − max(F_diel(n·wo))) · mean(baseColor)`, `P(specular) = s/(s + d)`.
//! The specular lobe draws a visible normal (see [`microfacet`](super::microfacet)) and
//! reflects `wo` about it; the diffuse lobe draws a cosine-weighted direction. `pdf` is the
//! mixture `P(specular)·Dv(wo, h)/(4|wo·h|) + P(diffuse)·cos θi/π` and the sample weight is
//! `f · cos θi / pdf` with that mixture, so `sample` and `pdf` agree whatever lobe drew `wi`.
//! Under [`BrdfModel::Compensated`] the specular lobe folds the reflections that fall below
//! the horizon back above it and mixes in cosine-weighted draws, a share `α²/2`
//! ([`compensated_sampling`](super::compensated_sampling)), with the mixture's exact density:
//! same expectation, no lost draws, so the compensated rough metal's path weights stay near 1
//! (see `docs/bsdf.md`).
//!
//! **Smooth surfaces.** Below [`SMOOTH_ALPHA`](super::microfacet::SMOOTH_ALPHA) the specular
//! lobe is a delta: the α → 0 limit of `∫ F · specular_brdf · cos dwi` is `F(n·wo)` in the
//! mirror direction, so a delta sample has `weight = ((1 − metallic)·F_diel(n·wo) + metallic ·
//! F_metal(n·wo)) / P(specular)` and `pdf = P(specular)`; `eval` and `pdf` carry only the
//! diffuse lobe. glint's former mirror (metallic 1, roughness 0) is this BRDF's metallic,
//! smooth end, now with Schlick's Fresnel.
//!
//! **Energy compensation** ([`BrdfModel::Compensated`], glint's default; [`BrdfModel::Spec`]
//! is the formulas above exactly). Single-scatter GGX loses the light that bounces between
//! microfacets (a white metal of roughness 1 reflects 0.3-0.7), and the spec's dielectric
//! mix gains energy at grazing angles. With `E0, E1` the tabulated albedos of the GGX lobe
//! ([`energy`](super::energy)) at `α` and `E_c` the albedo of a compensated lobe:
//!
//! ```text
//! F_avg     = baseColor + (1 − baseColor)/21             (cosine average of F_metal)
//! F_ms      = F_avg A0 / (1 − F_avg (1 − A0))            (Kulla & Conty 2017)
//! k(μo)     = 1 + F_ms (1/E0(μo) − 1)                    (Turquin 2019's scaling)
//! metal     = F_metal · specular_brdf · k(μo)
//! dspec     = F_diel · specular_brdf                   (single scattering, as in the spec)
//! E_d(μ)    = f0 (E0 − E1)(μ) + f90 E1(μ)              (albedo of dspec, per channel)
//! diffuse   = baseColor/π · (1 − E_d(μo))                (albedo scaling, as in OpenPBR)
//! f = (1 − metallic)(dspec + diffuse) + metallic · metal
//! ```
//!
//! A white metal then reflects `E0 · (1/E0) = 1` at every angle; a coloured one reflects its
//! single-scatter albedo plus about `F_avg F_ms (1 − E0)`: the light that bounced between
//! microfacets met the Fresnel once per bounce (Kulla & Conty's geometric series), which
//! Turquin's `F_ms = F0` overstates (a grey metal of base colour 0.6 at roughness 1 rendered
//! brighter than Cycles, whose Principled BSDF uses the same `F_ms`).
//!
//! The diffuse part reflects `baseColor (1 − E_d(μo))`, so a white dielectric reflects
//! `E_d + 1 − E_d = 1` (what the dielectric's specular lobe does not reflect, masking
//! included, goes to the base, which is what albedo scaling means), and with `specular = 0`
//! the diffuse is exactly `baseColor/π`. Neither factor is reciprocal (both depend on `μo`
//! only, as Turquin's and OpenPBR's do). Kulla & Conty's reciprocal base
//! `(1 − E_d(μo))(1 − E_d(μi))/(1 − avg E_d)` reflects the same energy in a furnace but
//! weights light arriving near the normal by `(1 − f0)/(1 − avg E_d)`, 5 % more for f0 = 0.04
//! when smooth: front-lit dielectrics rendered 4-7 % brighter than Cycles (NormalTangentTest).
//!
//! `pdf` and `sample` draw the same lobes with the same probabilities; the weights are `eval · cos θi / pdf` of the compensated `eval`, so the
//! estimator is unbiased for the compensated BRDF. Smooth surfaces: `E0 = 1`, `E1 = (1−μ)⁵`,
//! so the mirror is unchanged and `E_d` is Schlick's Fresnel at `μ`.
//!
//! **Diffuse transmission** (KHR_materials_diffuse_transmission). With `t` the strength
//! (`diffuseTransmissionFactor × texture A`) and `C_t` its colour, the diffuse base becomes
//! the extension's `mix(diffuse_brdf(baseColor), diffuse_btdf(C_t), t)` under the same
//! Fresnel weight:
//!
//! ```text
//! diffuse reflection   (wi above) = (1 − m) · w(wo, wi) · (1 − t) · baseColor / π
//! diffuse transmission (wi below) = (1 − m) · w(wo, wi) · t · C_t / π
//!   w = 1 − max F_diel(wo·h)   (spec; below the surface h is the half vector of wo and wi
//!                               mirrored to wo's side, so w is reciprocal and the pair
//!                               transmits exactly what the reflection gave up)
//!   w = 1 − E_d(n·wo)          (compensated)
//! ```
//!
//! The specular lobes and the Fresnel weight are untouched, as the extension says; so a white
//! compensated dielectric with `t = 1` and a white `C_t` sends `E_d` back and `1 − E_d`
//! through. The diffuse lobe's selection weight becomes `(1 − t) mean(baseColor) + t
//! mean(C_t)`, split between a cosine-weighted draw above (reflection) and one below
//! (transmission) in that ratio. The surface is thin here: what is transmitted leaves from
//! the other side at the same point (the path tracer puts it into the volume's medium when
//! KHR_materials_volume makes the surface a volume's boundary). With `t = 0` (every material
//! without the extension) every formula above is the reflection-only one, bit for bit.
//!
//! Reflection only without diffuse transmission: `wo` below the surface (`wo.z ≤ 0`)
//! reflects nothing; the caller orients the shading frame toward `wo` for two-sided surfaces.

use super::anisotropic_albedo;
use super::compensated_sampling;
use super::energy::{
    GgxAlbedo, ggx_albedo, ggx_albedo_average, multiple_scattering_factor,
    multiple_scattering_fresnel, schlick_albedo, schlick_fresnel_average,
};
use super::microfacet::{TrowbridgeReitz, reflect, schlick};
use super::{Bsdf, BsdfFlags, BsdfSample};
use crate::sampling::warp::{cosine_hemisphere, cosine_hemisphere_pdf};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;
use std::fmt;
use std::str::FromStr;

/// Which metallic-roughness model a surface uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BrdfModel {
    /// Energy-compensated (the default): multiple-scattering GGX by Turquin's factor and a
    /// diffuse base that receives what the specular lobe does not reflect, so a white surface
    /// reflects 1 at every angle and roughness (see the module documentation).
    #[default]
    Compensated,
    /// The glTF specification's Appendix B exactly (single-scatter GGX, `fresnel_mix`).
    Spec,
}

impl BrdfModel {
    /// Every model, in the order the command line lists them.
    pub const ALL: [BrdfModel; 2] = [BrdfModel::Compensated, BrdfModel::Spec];

    /// The name the command line, job files, Python and output headers use.
    pub fn name(self) -> &'static str {
        match self {
            BrdfModel::Compensated => "compensated",
            BrdfModel::Spec => "spec",
        }
    }
}

impl fmt::Display for BrdfModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for BrdfModel {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        BrdfModel::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                format!("unknown BRDF model '{s}': expected 'compensated' (energy-conserving, the default) or 'spec' (glTF Appendix B exactly)")
            })
    }
}

/// The glTF metallic-roughness BRDF (see the module documentation for the formulas).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetallicRoughnessBsdf {
    /// Linear base colour (glTF `baseColorFactor × texture × COLOR_0`, RGB).
    pub base_color: Vec3,
    /// Metalness in [0, 1].
    pub metallic: f32,
    /// The GGX distribution, `α = roughness²`.
    pub distribution: TrowbridgeReitz,
    /// Dielectric Fresnel at normal incidence (`0.04` by default).
    pub dielectric_f0: Vec3,
    /// Dielectric Fresnel at grazing incidence (KHR_materials_specular's `specular`, 1 by
    /// default).
    pub dielectric_f90: f32,
    /// Appendix B exactly, or energy-compensated.
    pub model: BrdfModel,
    /// KHR_materials_diffuse_transmission's strength `t` in [0, 1]: the share of the diffuse
    /// base transmitted to the other side (0: reflection only).
    pub diffuse_transmission: f32,
    /// KHR_materials_diffuse_transmission's colour `C_t`, linear RGB in [0, 1].
    pub diffuse_transmission_color: Vec3,
}

/// Dielectric Fresnel `f0` of an index of refraction against air, `((ior − 1)/(ior + 1))²`.
#[inline]
pub fn f0_from_ior(ior: f32) -> f32 {
    let r = (ior - 1.0) / (ior + 1.0);
    if r.is_finite() { r * r } else { 1.0 }
}

#[inline]
fn mean(v: Vec3) -> f32 {
    (v.x + v.y + v.z) * (1.0 / 3.0)
}

impl MetallicRoughnessBsdf {
    /// The core glTF model: `base_color` linear RGB, `metallic` and perceptual `roughness`
    /// clamped to [0, 1] (α = roughness²), dielectric `ior = 1.5`.
    pub fn new(base_color: Vec3, metallic: f32, roughness: f32) -> Self {
        let unit = |x: f32| {
            if x.is_finite() {
                x.clamp(0.0, 1.0)
            } else {
                0.0
            }
        };
        Self {
            base_color: base_color.max(Vec3::ZERO),
            metallic: unit(metallic),
            distribution: TrowbridgeReitz::from_roughness(roughness),
            dielectric_f0: Vec3::splat(0.04),
            dielectric_f90: 1.0,
            model: BrdfModel::Spec,
            diffuse_transmission: 0.0,
            diffuse_transmission_color: Vec3::ONE,
        }
    }

    /// The same BRDF with KHR_materials_diffuse_transmission: a share `strength` (clamped to
    /// [0, 1]; non-finite is 0) of the diffuse base transmitted with colour `color` (clamped
    /// to [0, 1]) into the lower hemisphere (see the module documentation). Strength 0
    /// changes nothing.
    pub fn with_diffuse_transmission(mut self, strength: f32, color: Vec3) -> Self {
        let t = if strength.is_finite() {
            strength.clamp(0.0, 1.0)
        } else {
            0.0
        };
        if t > 0.0 {
            self.diffuse_transmission = t;
            self.diffuse_transmission_color = if color.is_finite() {
                color.clamp(Vec3::ZERO, Vec3::ONE)
            } else {
                Vec3::ONE
            };
        }
        self
    }

    /// Whether the diffuse base transmits (KHR_materials_diffuse_transmission).
    #[inline]
    fn transmits_diffusely(&self) -> bool {
        self.diffuse_transmission > 0.0
    }

    /// The same BRDF under `model` ([`new`](Self::new) gives [`BrdfModel::Spec`], the
    /// formulas of Appendix B; the renderer's default is [`BrdfModel::Compensated`]).
    pub fn with_model(mut self, model: BrdfModel) -> Self {
        self.model = model;
        self
    }

    /// The same BRDF with KHR_materials_anisotropy's `strength` (see
    /// [`TrowbridgeReitz::from_roughness_anisotropy`]) for perceptual `roughness`: the
    /// specular lobes (metal and dielectric) stretch along the local X axis. Strength 0
    /// changes nothing.
    pub fn with_anisotropy(mut self, roughness: f32, strength: f32) -> Self {
        if strength > 0.0 {
            self.distribution = TrowbridgeReitz::from_roughness_anisotropy(roughness, strength);
        }
        self
    }

    /// The dielectric Fresnel of KHR_materials_ior (`ior`, 1.5 by default; 0 means f0 = 1) and
    /// KHR_materials_specular (`specular` scales f0 and f90, `specular_color` tints f0):
    /// `f0 = min(f0(ior) · specular_color, 1) · specular`, `f90 = specular`.
    pub fn with_dielectric_fresnel(
        mut self,
        ior: f32,
        specular: f32,
        specular_color: Vec3,
    ) -> Self {
        let s = if specular.is_finite() {
            specular.clamp(0.0, 1.0)
        } else {
            1.0
        };
        let tint = specular_color.max(Vec3::ZERO);
        self.dielectric_f0 = (f0_from_ior(ior) * tint).min(Vec3::ONE) * s;
        self.dielectric_f90 = s;
        self
    }

    #[inline]
    fn dielectric_fresnel(&self, cos: f32) -> Vec3 {
        schlick(self.dielectric_f0, Vec3::splat(self.dielectric_f90), cos)
    }

    #[inline]
    fn metal_fresnel(&self, cos: f32) -> Vec3 {
        schlick(self.base_color, Vec3::ONE, cos)
    }

    /// The probability of choosing the specular lobe for `wo` (see the module documentation).
    pub fn specular_probability(&self, wo: Vec3) -> f32 {
        let m = self.metallic;
        let fd = self.dielectric_fresnel(wo.z);
        let s = (1.0 - m) * mean(fd) + m * mean(self.metal_fresnel(wo.z));
        let d = (1.0 - m) * (1.0 - fd.max_element()).max(0.0) * self.diffuse_selection_weight();
        if s + d > 0.0 { s / (s + d) } else { 1.0 }
    }

    /// The diffuse lobes' selection weight: `(1 − t) mean(baseColor) + t mean(C_t)` (exactly
    /// `mean(baseColor)` without diffuse transmission).
    #[inline]
    fn diffuse_selection_weight(&self) -> f32 {
        if self.transmits_diffusely() {
            let t = self.diffuse_transmission;
            (1.0 - t) * mean(self.base_color) + t * mean(self.diffuse_transmission_color)
        } else {
            mean(self.base_color)
        }
    }

    /// The probability that a diffuse draw goes below the surface (transmission): `t
    /// mean(C_t)` over [`diffuse_selection_weight`](Self::diffuse_selection_weight); 0
    /// without diffuse transmission.
    #[inline]
    fn diffuse_transmission_probability(&self) -> f32 {
        if !self.transmits_diffusely() {
            return 0.0;
        }
        let through = self.diffuse_transmission * mean(self.diffuse_transmission_color);
        let all = self.diffuse_selection_weight();
        if all > 0.0 {
            (through / all).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    /// The diffuse term: `(1 − metallic)(1 − max F_diel(wo·h)) baseColor/π` (spec), or
    /// `(1 − metallic)(1 − E_d(n·wo)) baseColor/π` (compensated), for both directions above
    /// the surface.
    /// With diffuse transmission the reflected share is `(1 − t)`.
    #[inline]
    fn diffuse(&self, wo: Vec3, wo_h: f32) -> Vec3 {
        // (1 − 0) is exactly 1: without diffuse transmission the product is unchanged.
        let tint = self.base_color
            * ((1.0 - self.metallic) * (1.0 - self.diffuse_transmission) * FRAC_1_PI);
        self.diffuse_weighted(tint, wo, wo_h)
    }

    /// The diffuse transmission term for `wi` below the surface: `(1 − m) w t C_t / π`, with
    /// the spec's `w` at the half vector of `wo` and `wi` mirrored above (see the module
    /// documentation); zero without diffuse transmission.
    #[inline]
    fn diffuse_transmitted(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if !self.transmits_diffusely() {
            return Vec3::ZERO;
        }
        let tint = self.diffuse_transmission_color
            * ((1.0 - self.metallic) * self.diffuse_transmission * FRAC_1_PI);
        let mirrored = Vec3::new(wi.x, wi.y, -wi.z);
        let wo_h = Self::half(wo, mirrored).map_or(1.0, |h| wo.dot(h));
        self.diffuse_weighted(tint, wo, wo_h)
    }

    /// `tint` under the Fresnel weight of the diffuse base: `1 − max F_diel(wo·h)` (spec) or
    /// `1 − E_d(n·wo)` (compensated).
    #[inline]
    fn diffuse_weighted(&self, tint: Vec3, wo: Vec3, wo_h: f32) -> Vec3 {
        match self.model {
            BrdfModel::Spec => {
                let fd = self.dielectric_fresnel(wo_h).max_element();
                tint * (1.0 - fd).max(0.0)
            }
            BrdfModel::Compensated => tint * self.compensated_diffuse_scale(wo),
        }
    }

    /// `1 − E_d(μo)` per channel, where `E_d` is the albedo of the dielectric specular lobe:
    /// the diffuse base receives what that lobe does not reflect towards `wo` (albedo
    /// scaling, as OpenPBR and Cycles' Principled BSDF layer it; not reciprocal).
    #[inline]
    fn compensated_diffuse_scale(&self, wo: Vec3) -> Vec3 {
        let (f0, f90) = (self.dielectric_f0, Vec3::splat(self.dielectric_f90));
        let e_o = schlick_albedo(self.lobe_albedo(wo), f0, f90);
        (Vec3::ONE - e_o).max(Vec3::ZERO)
    }

    /// The isotropic α the energy tables are read at.
    #[inline]
    fn alpha(&self) -> f32 {
        (self.distribution.alpha_x * self.distribution.alpha_y).sqrt()
    }

    /// Whether the distribution is anisotropic (KHR_materials_anisotropy) and rough: its
    /// albedo then comes from [`anisotropic_albedo`], which depends on `wo`'s azimuth.
    #[inline]
    fn anisotropic(&self) -> bool {
        self.distribution.alpha_x != self.distribution.alpha_y && !self.distribution.is_smooth()
    }

    /// `(E0, E1)` of the single-scatter specular lobe seen from `wo`.
    #[inline]
    fn lobe_albedo(&self, wo: Vec3) -> GgxAlbedo {
        if self.anisotropic() {
            anisotropic_albedo::albedo(&self.distribution, wo)
        } else {
            ggx_albedo(wo.z, self.alpha())
        }
    }

    /// `A0` of the single-scatter specular lobe (its white albedo's cosine average).
    #[inline]
    fn lobe_albedo_average(&self) -> f32 {
        if self.anisotropic() {
            anisotropic_albedo::albedo_average(&self.distribution).a0
        } else {
            ggx_albedo_average(self.alpha()).a0
        }
    }

    /// The rough specular term `(1 − m) F_diel D V + m F_metal D V` at half vector `h`.
    #[inline]
    fn specular(&self, wo: Vec3, wi: Vec3, h: Vec3) -> Vec3 {
        let tr = &self.distribution;
        let vis = tr.g2(wo, wi) / (4.0 * wo.z * wi.z);
        let c = wo.dot(h);
        let (diel, metal) = (self.dielectric_fresnel(c), self.metal_fresnel(c));
        let f = match self.model {
            BrdfModel::Spec => (1.0 - self.metallic) * diel + self.metallic * metal,
            BrdfModel::Compensated => {
                let e = self.lobe_albedo(wo);
                let f_ms = multiple_scattering_fresnel(
                    schlick_fresnel_average(self.base_color, Vec3::ONE),
                    self.lobe_albedo_average(),
                );
                (1.0 - self.metallic) * diel
                    + self.metallic * metal * multiple_scattering_factor(e, f_ms)
            }
        };
        f * (tr.d(h) * vis)
    }

    /// The smooth (delta) lobe's reflectance at `n·wo`.
    #[inline]
    fn mirror_reflectance(&self, cos_o: f32) -> Vec3 {
        (1.0 - self.metallic) * self.dielectric_fresnel(cos_o)
            + self.metallic * self.metal_fresnel(cos_o)
    }

    /// The density of the specular lobe's sampler at `wi` (both directions above the
    /// surface): plain visible-normal reflection for [`BrdfModel::Spec`] (draws below the
    /// horizon are lost, as before), the folded sampler mixed with cosine draws for
    /// [`BrdfModel::Compensated`] (see [`compensated_sampling`](super::compensated_sampling)).
    #[inline]
    fn specular_pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self.model {
            BrdfModel::Spec => {
                Self::half(wo, wi).map_or(0.0, |h| self.distribution.reflection_pdf(wo, h))
            }
            BrdfModel::Compensated => compensated_sampling::pdf(&self.distribution, wo, wi),
        }
    }

    /// The half vector of two upper directions, or `None` when they are opposite.
    #[inline]
    fn half(wo: Vec3, wi: Vec3) -> Option<Vec3> {
        let h = (wo + wi).normalize_or_zero();
        (h != Vec3::ZERO).then_some(h)
    }
}

impl Bsdf for MetallicRoughnessBsdf {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        if wi.z <= 0.0 {
            return if wi.z < 0.0 {
                self.diffuse_transmitted(wo, wi)
            } else {
                Vec3::ZERO
            };
        }
        let Some(h) = Self::half(wo, wi) else {
            return Vec3::ZERO;
        };
        let diffuse = self.diffuse(wo, wo.dot(h));
        if self.distribution.is_smooth() {
            return diffuse;
        }
        diffuse + self.specular(wo, wi, h)
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z == 0.0 || (wi.z < 0.0 && !self.transmits_diffusely()) {
            return 0.0;
        }
        let ps = self.specular_probability(wo);
        let pt = self.diffuse_transmission_probability();
        if wi.z < 0.0 {
            return (1.0 - ps) * pt * cosine_hemisphere_pdf(-wi.z);
        }
        // (1 − 0) is exactly 1: without diffuse transmission the product is unchanged.
        let diffuse = (1.0 - ps) * (1.0 - pt) * cosine_hemisphere_pdf(wi.z);
        if self.distribution.is_smooth() {
            return diffuse;
        }
        diffuse + ps * self.specular_pdf(wo, wi)
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let ps = self.specular_probability(wo);
        let choose_specular = u_lobe < ps;
        if choose_specular && self.distribution.is_smooth() {
            let weight = self.mirror_reflectance(wo.z) / ps;
            return Some(BsdfSample {
                wi: Vec3::new(-wo.x, -wo.y, wo.z),
                weight,
                pdf: ps,
                delta: true,
                transmission: false,
            });
        }
        let wi = if choose_specular {
            match self.model {
                BrdfModel::Spec => reflect(wo, self.distribution.sample_visible(wo, u)),
                BrdfModel::Compensated => {
                    let u_choice = (u_lobe / ps).clamp(0.0, 1.0);
                    compensated_sampling::sample(&self.distribution, wo, u_choice, u)
                }
            }
        } else if self.transmits_diffusely() {
            // The diffuse draw goes below with probability `pt`, reusing the rest of `u_lobe`.
            let u_diffuse = ((u_lobe - ps) / (1.0 - ps)).clamp(0.0, 1.0);
            let wi = cosine_hemisphere(u);
            if u_diffuse < self.diffuse_transmission_probability() {
                Vec3::new(wi.x, wi.y, -wi.z)
            } else {
                wi
            }
        } else {
            cosine_hemisphere(u)
        };
        let transmission = wi.z < 0.0 && !choose_specular;
        if wi.z == 0.0 || (wi.z < 0.0 && !transmission) {
            return None;
        }
        let pdf = self.pdf(wo, wi);
        // Also rejects NaN.
        if !pdf.is_finite() || pdf.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let weight = self.eval(wo, wi) * (wi.z.abs() / pdf);
        Some(BsdfSample {
            wi,
            weight,
            pdf,
            delta: false,
            transmission,
        })
    }

    fn flags(&self) -> BsdfFlags {
        let specular = BsdfFlags::REFLECTION | BsdfFlags::microfacet(self.distribution.is_smooth());
        let diffuse = (1.0 - self.metallic) * (1.0 - self.diffuse_transmission);
        let mut flags = if diffuse * self.base_color.max_element() > 0.0 {
            specular | BsdfFlags::DIFFUSE
        } else {
            specular
        };
        let through = (1.0 - self.metallic) * self.diffuse_transmission;
        if through * self.diffuse_transmission_color.max_element() > 0.0 {
            flags |= BsdfFlags::TRANSMISSION | BsdfFlags::DIFFUSE;
        }
        flags
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_metal_is_a_delta_mirror_with_schlick_fresnel() {
        let b = MetallicRoughnessBsdf::new(Vec3::new(0.9, 0.6, 0.3), 1.0, 0.0);
        assert!(b.is_delta());
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let s = b
            .sample(wo, 0.3, Vec2::new(0.2, 0.7))
            .expect("a mirror sample");
        assert!(s.delta && !s.transmission);
        assert!((s.wi - Vec3::new(-0.6, 0.0, 0.8)).length() < 1e-6);
        let w = 0.2f32.powi(5);
        let expect = b.base_color + (Vec3::ONE - b.base_color) * w;
        assert!((s.weight * s.pdf - expect).abs().max_element() < 1e-6);
        assert_eq!(b.eval(wo, s.wi), Vec3::ZERO);
        assert_eq!(b.pdf(wo, s.wi), 0.0);
    }

    #[test]
    fn below_the_horizon_reflects_nothing() {
        let b = MetallicRoughnessBsdf::new(Vec3::ONE, 0.3, 0.5);
        let below = Vec3::new(0.0, 0.6, -0.8);
        assert_eq!(b.eval(below, Vec3::Z), Vec3::ZERO);
        assert_eq!(b.eval(Vec3::Z, below), Vec3::ZERO);
        assert_eq!(b.pdf(below, Vec3::Z), 0.0);
        assert!(b.sample(below, 0.5, Vec2::splat(0.5)).is_none());
    }

    #[test]
    fn ior_and_specular_set_the_dielectric_fresnel() {
        let b = MetallicRoughnessBsdf::new(Vec3::ONE, 0.0, 0.5);
        assert!((b.dielectric_f0 - Vec3::splat(0.04)).abs().max_element() < 1e-7);
        let c = b.with_dielectric_fresnel(1.5, 1.0, Vec3::ONE);
        assert!((c.dielectric_f0 - Vec3::splat(0.04)).abs().max_element() < 1e-7);
        let zero = b.with_dielectric_fresnel(0.0, 1.0, Vec3::ONE);
        assert_eq!(zero.dielectric_f0, Vec3::ONE);
        let tinted = b.with_dielectric_fresnel(2.0, 0.5, Vec3::new(100.0, 1.0, 0.0));
        assert!(
            (tinted.dielectric_f0 - Vec3::new(0.5, 0.5 / 9.0, 0.0))
                .abs()
                .max_element()
                < 1e-6
        );
        assert_eq!(tinted.dielectric_f90, 0.5);
    }
}
