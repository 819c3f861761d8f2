//! A dielectric interface that reflects and transmits: the BSDF of KHR_materials_transmission.
//!
//! Parameters: the relative index of refraction `η = η_below / η_above` (the medium on the
//! −Z side over the medium on the +Z side), the GGX distribution (`α = roughness²`), a
//! transmission tint `T_c` (glTF: the base colour) and whether the surface is **thin-walled**.
//!
//! **Rough, volumetric** (Walter et al. 2007, "Microfacet Models for Refraction through Rough
//! Surfaces"). With `η_o`, `η_i` the indices on the sides of `wo` and `wi`, the generalized
//! half vector `h = normalize(η_o wo + η_i wi)` (turned to +Z), `F` the exact dielectric
//! Fresnel reflectance at `wo·h` and `G2` Smith's height-correlated masking-shadowing:
//!
//! ```text
//! f_r = F(wo·h) D(h) G2 / (4 |n·wo| |n·wi|)                              (same side)
//! f_t = T_c (1 − F(wo·h)) D(h) G2 |wo·h| |wi·h| η_i²                     (opposite sides)
//!       / (|n·wo| |n·wi| (η_o wo·h + η_i wi·h)²) · (η_o/η_i)²
//! ```
//!
//! The last factor is the radiance scaling across the interface (transport of radiance, `wo`
//! toward the camera); it makes `f_t` obey the generalized reciprocity
//! `f(wo, wi)/η_o² = f(wi, wo)/η_i²`. Total internal reflection has `F = 1`.
//!
//! **Thin-walled** (KHR_materials_transmission without KHR_materials_volume: "the object is
//! thin"): light crosses the surface without bending. The transmitted lobe is the reflected
//! lobe mirrored through the tangent plane: with `wi' = (wi.x, wi.y, −wi.z)`,
//! `h = normalize(wo + wi')`, `f_t(wo, wi) = T_c (1 − F(wo·h)) D(h) G2(wo, wi') / (4 |n·wo|
//! |n·wi|)`. `η` enters only through `F`.
//!
//! **Smooth** (α below [`SMOOTH_ALPHA`](super::microfacet::SMOOTH_ALPHA)): two delta lobes, the
//! mirror direction with reflectance `F(n·wo)` and the refracted direction (thin: `−wo`) with
//! transmittance `T_c (1 − F)`, scaled by `(η_o/η_i)²` when the ray bends.
//!
//! **Index-matched** (volumetric, `|η − 1| <` [`MATCHED_INDEX`]): whatever the roughness, every
//! microfacet passes `wo` straight on to `−wo` and reflects nothing, so the interface is the
//! smooth one (delta lobes; `F = 0` makes it a pure pass-through of transmittance `T_c`). The
//! rough formulas cannot express it: `η_o wo + η_i wi` vanishes.
//!
//! **Sampling.** A visible normal `m` is drawn for `wo` (turned to +Z); reflection is chosen
//! with probability `P_r = F / (F + (1 − F) t̄)`, `t̄ = mean(T_c)`, transmission otherwise.
//! Reflection: `pdf = P_r Dv(wo, m) / (4 |wo·m|)`; transmission: `pdf = (1 − P_r) Dv(wo, m)
//! |wi·m| η_i² / (η_o wo·m + η_i wi·m)²` (thin: the mirrored reflection's density). `pdf`
//! recomputes `m` from `(wo, wi)` and gives the same value, so MIS sees one density.
//!
//! **Energy compensation** ([`BrdfModel::Compensated`], the renderer's default;
//! [`BrdfModel::Spec`] is the single-scatter BSDF above exactly). Single scattering loses the
//! light that meets a second microfacet: a white rough interface reflects plus transmits
//! `E(μo) < 1` of the power arriving from `wo` (the tabulated albedo of
//! [`dielectric_energy`](super::dielectric_energy); thin walls: the GGX reflection albedo
//! `E0(μo)`). The compensated BSDF is the single-scatter one scaled as a whole,
//!
//! ```text
//! f_c(wo, wi) = f(wo, wi) / E(|n·wo|, α, η_i/η_o)
//! ```
//!
//! (Turquin 2019's scaling with the Fresnel weight of a dielectric, 1: every multiply
//! scattered ray leaves reflected or transmitted), so a white interface conserves power at
//! every angle and roughness and the restored light keeps the single-scatter lobes' shapes
//! and their split between reflection and transmission. Separate tables for each side,
//! because total internal reflection makes the inside differ. Like the metals' scaling it
//! depends on `wo` only and is not reciprocal. `sample` and `pdf` are the single-scatter
//! ones, and a sample's weight is `f_c · |cos θi| / pdf`, so the estimator is unbiased for
//! the compensated BSDF. Smooth interfaces are unchanged (`E = 1`).

use super::dielectric_energy::dielectric_albedo;
use super::energy::{ggx_albedo, white_lobe_scale};
use super::microfacet::{TrowbridgeReitz, reflect};
use super::{BrdfModel, Bsdf, BsdfFlags, BsdfSample};
use glam::{Vec2, Vec3};

/// Largest `|η − 1|` at which a volumetric interface is treated as index-matched, a straight
/// pass-through (see [`DielectricBsdf::index_matched`]).
pub const MATCHED_INDEX: f32 = 1e-3;

/// The dielectric interface (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DielectricBsdf {
    /// Relative index of refraction, −Z side over +Z side (`ior` entering, `1/ior` leaving).
    pub eta: f32,
    /// The microfacet distribution.
    pub distribution: TrowbridgeReitz,
    /// Transmission tint `T_c` (glTF: base colour).
    pub tint: Vec3,
    /// Thin-walled: transmission does not bend the ray.
    pub thin: bool,
    /// Single scattering exactly ([`BrdfModel::Spec`]) or energy-compensated.
    pub model: BrdfModel,
}

/// Exact Fresnel reflectance of unpolarised light at a dielectric interface, for `cos_i` the
/// cosine on the side of the incoming direction (negative: the direction is below, the
/// relative index flips) and `eta` the relative index −Z over +Z. 1 at total internal
/// reflection.
#[inline]
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let (cos_i, eta) = if cos_i < 0.0 {
        (-cos_i, 1.0 / eta)
    } else {
        (cos_i, eta)
    };
    let cos_i = cos_i.min(1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let f = 0.5 * (r_par * r_par + r_perp * r_perp);
    if f.is_finite() {
        f.clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// Refracts `w` through the interface of normal `n` (on `w`'s side) with relative index
/// `eta` (`wi`'s side over `w`'s side): `None` at total internal reflection.
#[inline]
pub fn refract(w: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = n.dot(w);
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((-w / eta + n * (cos_i / eta - cos_t)).normalize_or_zero()).filter(|v| *v != Vec3::ZERO)
}

#[inline]
fn mean(v: Vec3) -> f32 {
    (v.x + v.y + v.z) * (1.0 / 3.0)
}

impl DielectricBsdf {
    /// A dielectric of relative index `eta` (non-finite or non-positive: 1.5), perceptual
    /// `roughness` (α = roughness²), transmission tint `tint` and thinness `thin`.
    pub fn new(eta: f32, roughness: f32, tint: Vec3, thin: bool) -> Self {
        Self {
            eta: if eta.is_finite() && eta > 0.0 {
                eta
            } else {
                1.5
            },
            distribution: TrowbridgeReitz::from_roughness(roughness),
            tint: tint.clamp(Vec3::ZERO, Vec3::ONE),
            thin,
            model: BrdfModel::Spec,
        }
    }

    /// The same interface under `model` ([`new`](Self::new) gives [`BrdfModel::Spec`], single
    /// scattering; the renderer's default is [`BrdfModel::Compensated`]).
    pub fn with_model(mut self, model: BrdfModel) -> Self {
        self.model = model;
        self
    }

    /// The factor on the whole rough BSDF for `wo`: `1/E(|n·wo|)` compensated (see the
    /// module documentation), 1 for [`BrdfModel::Spec`] and smooth interfaces.
    #[inline]
    pub fn energy_scale(&self, wo: Vec3) -> f32 {
        match self.model {
            BrdfModel::Spec => 1.0,
            BrdfModel::Compensated => {
                let alpha = self.alpha();
                let e = if self.thin {
                    ggx_albedo(wo.z, alpha).e0
                } else {
                    dielectric_albedo(wo.z.abs(), alpha, self.eta_across(wo))
                };
                white_lobe_scale(e)
            }
        }
    }

    /// Whether the interface scatters only into delta directions: a smooth surface, or a
    /// volumetric interface between matched indices ([`index_matched`](Self::index_matched)),
    /// whatever its roughness.
    #[inline]
    pub fn is_delta_interface(&self) -> bool {
        self.distribution.is_smooth() || self.index_matched()
    }

    /// Whether the two sides of a volumetric (not thin) interface have the same index within
    /// [`MATCHED_INDEX`]. Every microfacet then refracts `wo` into `−wo` and reflects nothing
    /// (the Fresnel reflectance is `((η − 1)/(η + 1))² ≤ 2.5·10⁻⁷`), so rough or not the
    /// interface is a straight pass-through: a delta lobe. The microfacet half vector
    /// `wo + η wi` of that pair is zero at η = 1 (every rough draw was rejected and the light
    /// lost) and ill-conditioned in single precision just beside it, while the true lobe is
    /// at most `|η − 1|` radians wide per radian of microfacet tilt: narrower than any pixel.
    #[inline]
    pub fn index_matched(&self) -> bool {
        !self.thin && (self.eta - 1.0).abs() < MATCHED_INDEX
    }

    /// The isotropic α the energy tables are read at.
    #[inline]
    fn alpha(&self) -> f32 {
        (self.distribution.alpha_x * self.distribution.alpha_y).sqrt()
    }

    /// The index ratio a refraction from `wo`'s side into the other side sees (`η_i/η_o`).
    #[inline]
    fn eta_across(&self, wo: Vec3) -> f32 {
        if wo.z > 0.0 { self.eta } else { 1.0 / self.eta }
    }

    /// The probability of choosing reflection given the Fresnel reflectance `f`.
    #[inline]
    fn reflect_probability(&self, f: f32) -> f32 {
        let t = (1.0 - f) * mean(self.tint);
        if f + t > 0.0 { f / (f + t) } else { 1.0 }
    }

    /// The microfacet normal (turned to +Z) that maps `wo` to `wi`, or `None` when none does
    /// (grazing directions, a back-facing microfacet).
    #[inline]
    fn half_vector(&self, wo: Vec3, wi: Vec3) -> Option<Vec3> {
        let reflection = wo.z * wi.z > 0.0;
        let h = if reflection {
            wo + wi
        } else if self.thin {
            wo + Vec3::new(wi.x, wi.y, -wi.z)
        } else {
            wo + wi * self.eta_across(wo)
        };
        let h = h.normalize_or_zero();
        if h == Vec3::ZERO || wo.z == 0.0 || wi.z == 0.0 {
            return None;
        }
        let h = if h.z < 0.0 { -h } else { h };
        // Both directions must see the microfacet from the side they are on (a thin wall's
        // transmitted direction through its mirror image).
        let wi_seen = if self.thin && !reflection {
            Vec3::new(wi.x, wi.y, -wi.z)
        } else {
            wi
        };
        if h.dot(wo) * wo.z <= 0.0 || h.dot(wi_seen) * wi_seen.z <= 0.0 {
            return None;
        }
        Some(h)
    }

    /// The visible-normal density of `m` seen from `wo` turned to +Z (the sampler draws `m`
    /// that way).
    #[inline]
    fn visible(&self, wo: Vec3, m: Vec3) -> f32 {
        let w = if wo.z < 0.0 { -wo } else { wo };
        self.distribution.visible_d(w, m)
    }

    /// The (non-thin) transmission Jacobian `|wi·m| / (wo·m + η wi·m)²` with η = η_i/η_o.
    #[inline]
    fn refraction_jacobian(&self, wo: Vec3, wi: Vec3, m: Vec3) -> f32 {
        let eta = self.eta_across(wo);
        let denom = wo.dot(m) + eta * wi.dot(m);
        let j = eta * eta * wi.dot(m).abs() / (denom * denom);
        if j.is_finite() { j } else { 0.0 }
    }
}

impl Bsdf for DielectricBsdf {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if self.is_delta_interface() {
            return Vec3::ZERO;
        }
        let Some(m) = self.half_vector(wo, wi) else {
            return Vec3::ZERO;
        };
        self.eval_single(wo, wi, m) * self.energy_scale(wo)
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if self.is_delta_interface() {
            return 0.0;
        }
        let Some(m) = self.half_vector(wo, wi) else {
            return 0.0;
        };
        let f = fresnel_dielectric(wo.dot(m) * wo.z.signum(), self.eta_side(wo));
        let pr = self.reflect_probability(f);
        let dv = self.visible(wo, m);
        let om = wo.dot(m).abs();
        if om == 0.0 {
            return 0.0;
        }
        if wo.z * wi.z > 0.0 {
            pr * dv / (4.0 * om)
        } else if self.thin {
            (1.0 - pr) * dv / (4.0 * om)
        } else {
            (1.0 - pr) * dv * self.refraction_jacobian(wo, wi, m)
        }
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let up = wo.z > 0.0;
        if self.is_delta_interface() {
            let f = fresnel_dielectric(wo.z.abs(), self.eta_side_up(up));
            let pr = self.reflect_probability(f);
            if u_lobe < pr {
                return Some(BsdfSample {
                    wi: Vec3::new(-wo.x, -wo.y, wo.z),
                    weight: Vec3::splat(f / pr),
                    pdf: pr,
                    delta: true,
                    transmission: false,
                });
            }
            let n = if up { Vec3::Z } else { -Vec3::Z };
            let (wi, scale) = if self.thin {
                (-wo, 1.0)
            } else {
                let eta = self.eta_across(wo);
                (refract(wo, n, eta)?, 1.0 / (eta * eta))
            };
            return Some(BsdfSample {
                wi,
                weight: self.tint * ((1.0 - f) * scale / (1.0 - pr)),
                pdf: 1.0 - pr,
                delta: true,
                transmission: true,
            });
        }
        let w = if up { wo } else { -wo };
        let m = self.distribution.sample_visible(w, u);
        // m is in the upper hemisphere; seen from wo's side it is m flipped when wo is below.
        let m_side = if up { m } else { -m };
        let f = fresnel_dielectric(wo.dot(m_side).abs(), self.eta_side_up(up));
        let pr = self.reflect_probability(f);
        let wi = if u_lobe < pr {
            reflect(wo, m_side)
        } else if self.thin {
            let r = reflect(wo, m_side);
            Vec3::new(r.x, r.y, -r.z)
        } else {
            refract(wo, m_side, self.eta_across(wo))?
        };
        let transmission = wo.z * wi.z < 0.0;
        if wi.z == 0.0 || (u_lobe < pr) == transmission {
            return None;
        }
        let pdf = self.pdf(wo, wi);
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
        BsdfFlags::REFLECTION
            | BsdfFlags::TRANSMISSION
            | BsdfFlags::microfacet(self.is_delta_interface())
    }
}

impl DielectricBsdf {
    /// The single-scatter `f(wo, wi)` for the half vector `m` of the pair (see the module
    /// documentation).
    #[inline]
    fn eval_single(&self, wo: Vec3, wi: Vec3, m: Vec3) -> Vec3 {
        let tr = &self.distribution;
        let f = fresnel_dielectric(wo.dot(m) * wo.z.signum(), self.eta_side(wo));
        let (co, ci) = (wo.z.abs(), wi.z.abs());
        if wo.z * wi.z > 0.0 {
            return Vec3::splat(f * tr.d(m) * tr.g2(wo, wi) / (4.0 * co * ci));
        }
        if self.thin {
            let wi_m = Vec3::new(wi.x, wi.y, -wi.z);
            return self.tint * ((1.0 - f) * tr.d(m) * tr.g2(wo, wi_m) / (4.0 * co * ci));
        }
        // Walter's f_t with the η² of the Jacobian and the radiance scaling 1/η².
        let eta = self.eta_across(wo);
        let denom = wo.dot(m) + eta * wi.dot(m);
        let ft = (1.0 - f) * tr.d(m) * tr.g2(wo, wi) * (wo.dot(m) * wi.dot(m)).abs()
            / (co * ci * denom * denom);
        if ft.is_finite() {
            self.tint * ft
        } else {
            Vec3::ZERO
        }
    }

    /// The relative index for Fresnel with a cosine measured on `wo`'s side (positive):
    /// `η_i/η_o`.
    #[inline]
    fn eta_side(&self, wo: Vec3) -> f32 {
        self.eta_side_up(wo.z > 0.0)
    }

    /// A thin wall has the same medium on both sides, so its Fresnel is that of entering
    /// from either side (no total internal reflection).
    #[inline]
    fn eta_side_up(&self, up: bool) -> f32 {
        if up || self.thin {
            self.eta
        } else {
            1.0 / self.eta
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_closed_forms() {
        // Normal incidence: ((η − 1)/(η + 1))².
        assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        // Matched index: no reflection.
        assert!(fresnel_dielectric(0.3, 1.0).abs() < 1e-7);
        // Beyond the critical angle from inside glass (sin θc = 1/1.5).
        assert_eq!(fresnel_dielectric(-0.5, 1.5), 1.0);
        // Grazing: total reflection.
        assert!((fresnel_dielectric(0.0, 1.5) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn refraction_obeys_snell() {
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let wi = refract(wo, Vec3::Z, 1.5).expect("no TIR entering glass");
        assert!((wi.length() - 1.0).abs() < 1e-6 && wi.z < 0.0);
        assert!((wo.x - 1.5 * -wi.x).abs() < 1e-6, "sin θo = η sin θi");
        assert!(refract(Vec3::new(0.8, 0.0, 0.6), Vec3::Z, 1.0 / 1.5).is_none());
    }

    #[test]
    fn smooth_glass_splits_into_fresnel_and_its_complement() {
        let b = DielectricBsdf::new(1.5, 0.0, Vec3::ONE, false);
        let wo = Vec3::new(0.0, 0.6, 0.8);
        let f = fresnel_dielectric(0.8, 1.5);
        let r = b.sample(wo, 0.0, Vec2::ZERO).expect("reflection");
        assert!(r.delta && !r.transmission);
        assert!((r.weight.x * r.pdf - f).abs() < 1e-6);
        let t = b.sample(wo, 0.999, Vec2::ZERO).expect("transmission");
        assert!(t.delta && t.transmission && t.wi.z < 0.0);
        // Radiance entering glass is scaled by 1/η².
        assert!((t.weight.x * t.pdf - (1.0 - f) / 2.25).abs() < 1e-6);
        let thin = DielectricBsdf::new(1.5, 0.0, Vec3::new(1.0, 0.5, 0.0), true);
        let t = thin
            .sample(wo, 0.999, Vec2::ZERO)
            .expect("thin transmission");
        assert!((t.wi + wo).length() < 1e-6, "thin walls do not bend rays");
        assert!((t.weight * t.pdf - Vec3::new(1.0, 0.5, 0.0) * (1.0 - f)).length() < 1e-6);
        assert_eq!(b.eval(wo, t.wi), Vec3::ZERO);
        assert_eq!(b.pdf(wo, t.wi), 0.0);
    }

    /// A rough volumetric interface between equal indices passes every ray straight through
    /// with the tint (it rejected every draw before, the half vector `wo + wi` being zero).
    #[test]
    fn rough_interface_of_matched_indices_passes_light_straight_through() {
        for eta in [
            1.0,
            1.0 + 0.5 * MATCHED_INDEX,
            1.0 / (1.0 + 0.5 * MATCHED_INDEX),
        ] {
            for roughness in [0.3, 1.0] {
                let tint = Vec3::new(1.0, 0.8, 0.5);
                let b = DielectricBsdf::new(eta, roughness, tint, false)
                    .with_model(BrdfModel::Compensated);
                assert!(b.is_delta() && b.flags().transmits());
                for wo in [
                    Vec3::Z,
                    Vec3::new(0.6, 0.0, 0.8),
                    Vec3::new(0.0, -0.6, -0.8),
                ] {
                    for u_lobe in [0.001, 0.5, 0.999] {
                        let s = b.sample(wo, u_lobe, Vec2::new(0.3, 0.7)).expect("a draw");
                        assert!(s.delta && s.transmission, "{eta} {wo} {u_lobe}: {s:?}");
                        assert!((s.wi + wo).length() < 1e-3, "straight on: {s:?}");
                        // The tint, with the radiance scaling (η_o/η_i)² within 2·|η − 1|.
                        assert!((s.weight * s.pdf - tint).abs().max_element() < 2.5e-3);
                    }
                }
            }
        }
        // Thin walls are not index-matched: their rough lobe spreads light at any η.
        let thin = DielectricBsdf::new(1.0, 0.5, Vec3::ONE, true);
        assert!(!thin.is_delta());
        // Just outside the tolerance the rough lobe is kept.
        assert!(!DielectricBsdf::new(1.0 + 2.0 * MATCHED_INDEX, 0.5, Vec3::ONE, false).is_delta());
    }
}
