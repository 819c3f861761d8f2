//! The sheen lobe of KHR_materials_sheen: the "Charlie" distribution of Estevez & Kulla (2017,
//! "Production Friendly Microfacet Sheen BRDF") with Ashikhmin's visibility term.
//!
//! Parameters: `sheenColor` `C` (linear RGB) and `sheenRoughness` `r` (perceptual;
//! `α = r²`). With `h = normalize(wo + wi)`, `sin θh` its sine to the normal, both directions
//! above the surface:
//!
//! ```text
//! D(h)        = (2 + 1/α) sin(θh)^(1/α) / (2π)                 (∫ D(h) cos θh dh = 1)
//! V(wo, wi)   = 1 / ((1 + Λ(cos θo) + Λ(cos θi)) · 4 cos θo cos θi)   (Estevez & Kulla)
//! f_sheen     = C · D(h) · V(wo, wi)
//! ```
//!
//! with the extension's fitted `Λ(μ) = exp(L(μ))` for `μ < ½`, `exp(2 L(½) − L(1 − μ))`
//! above, `L(x) = a/(1 + b x^c) + d x + e`, whose five coefficients are interpolated in
//! `(1 − α)²` between the extension's two sets ([`charlie_lambda`]).
//!
//! The extension layers it over the material with its albedo scaling,
//! `f = f_sheen + f_base · min(1 − max(C) E(cos θo), 1 − max(C) E(cos θi))`, where `E(μ, r)`
//! is the directional albedo of `D · V` for `C = 1`; [`sheen_albedo`] tabulates it once
//! (32 × 32 in (μ, r), by quadrature) and interpolates bilinearly. The extension defines the
//! visibility as this "Charlie" term and allows Ashikhmin & Premoze's cheaper
//! `1 / (4 (cos θi + cos θo − cos θi cos θo))` as a substitute that "will make the BRDF not
//! energy conserving when using the albedo-scaling technique"; glint takes the defined
//! term (docs/bsdf.md compares the two). Both are symmetric in `wo`, `wi`, so `f_sheen` is
//! reciprocal.
//!
//! **Sampling.** Cosine-weighted hemisphere, `pdf = cos θi / π` (the lobe is broad; the spec
//! asks for nothing sharper).

use super::{Bsdf, BsdfFlags, BsdfSample};
use crate::sampling::warp::{cosine_hemisphere, cosine_hemisphere_pdf};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;
use std::sync::OnceLock;

/// Smallest α: below it `sin^(1/α)` underflows everywhere but at grazing half vectors and
/// the lobe is black in practice (the spec clamps similarly, to 0.07 in its sample code).
const MIN_ALPHA: f32 = 1e-3;

/// The sheen lobe alone (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SheenBsdf {
    /// Sheen colour `C`.
    pub color: Vec3,
    /// Perceptual sheen roughness `r` in [0, 1].
    pub roughness: f32,
}

/// The Charlie distribution `D(h)` for roughness `α` (`α = r²`), for a unit `h`.
#[inline]
pub fn charlie_d(alpha: f32, h: Vec3) -> f32 {
    if h.z <= 0.0 {
        return 0.0;
    }
    let a = alpha.max(MIN_ALPHA);
    let inv = 1.0 / a;
    let sin2 = (1.0 - h.z * h.z).max(0.0);
    (2.0 + inv) * sin2.powf(0.5 * inv) / (2.0 * PI)
}

/// The extension's fitted `L(x)` for roughness `α` (module documentation): its coefficients
/// at `α = 0` and `α = 1`, interpolated in `(1 − α)²`.
#[inline]
fn charlie_l(x: f32, alpha: f32) -> f32 {
    let t = (1.0 - alpha) * (1.0 - alpha);
    let mix = |at_one: f32, at_zero: f32| at_one + (at_zero - at_one) * t;
    let a = mix(21.5473, 25.3245);
    let b = mix(3.82987, 3.32435);
    let c = mix(0.19823, 0.16801);
    let d = mix(-1.97760, -1.27393);
    let e = mix(-4.32054, -4.85967);
    a / (1.0 + b * x.powf(c)) + d * x + e
}

/// Estevez & Kulla's `Λ(μ)` for the Charlie distribution of roughness `α` (the extension's
/// fit: `exp L(μ)` below `μ = ½`, mirrored about ½ above it so that it falls to 0 at the
/// normal).
#[inline]
pub fn charlie_lambda(mu: f32, alpha: f32) -> f32 {
    let mu = mu.abs().min(1.0);
    if mu < 0.5 {
        charlie_l(mu, alpha).exp()
    } else {
        (2.0 * charlie_l(0.5, alpha) - charlie_l(1.0 - mu, alpha)).exp()
    }
}

/// The Charlie visibility `1 / ((1 + Λ(cos θo) + Λ(cos θi)) · 4 cos θo cos θi)`.
#[inline]
fn visibility(co: f32, ci: f32, alpha: f32) -> f32 {
    let d = (1.0 + charlie_lambda(co, alpha) + charlie_lambda(ci, alpha)) * 4.0 * co * ci;
    if d > 0.0 && d.is_finite() {
        1.0 / d
    } else {
        0.0
    }
}

impl SheenBsdf {
    /// The lobe; colour clamped to [0, 1], roughness to [0, 1] (non-finite: 0).
    pub fn new(color: Vec3, roughness: f32) -> Self {
        Self {
            color: color.clamp(Vec3::ZERO, Vec3::ONE),
            roughness: if roughness.is_finite() {
                roughness.clamp(0.0, 1.0)
            } else {
                0.0
            },
        }
    }

    /// `D · V` for `C = 1`, both directions above the surface.
    #[inline]
    fn dv(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let h = (wo + wi).normalize_or_zero();
        if h == Vec3::ZERO {
            return 0.0;
        }
        let alpha = (self.roughness * self.roughness).max(MIN_ALPHA);
        charlie_d(alpha, h) * visibility(wo.z, wi.z, alpha)
    }

    /// The spec's scaling of the layer below,
    /// `min(1 − max(C) E(cos θo), 1 − max(C) E(cos θi))` (cosines as absolute values, so a
    /// transmitted `wi` is scaled by its mirror image's albedo).
    #[inline]
    pub fn albedo_scaling(&self, cos_o: f32, cos_i: f32) -> f32 {
        let c = self.color.max_element();
        let eo = sheen_albedo(cos_o.abs(), self.roughness);
        let ei = sheen_albedo(cos_i.abs(), self.roughness);
        (1.0 - c * eo.max(ei)).max(0.0)
    }

    /// How much the lobe reflects toward `wo` (for lobe selection): `max(C) E(cos θo)`.
    #[inline]
    pub fn albedo(&self, cos_o: f32) -> f32 {
        self.color.max_element() * sheen_albedo(cos_o.abs(), self.roughness)
    }
}

impl Bsdf for SheenBsdf {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::REFLECTION | BsdfFlags::GLOSSY
    }

    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        self.color * self.dv(wo, wi)
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        cosine_hemisphere_pdf(wi.z)
    }

    fn sample(&self, wo: Vec3, _u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = cosine_hemisphere(u);
        let pdf = self.pdf(wo, wi);
        if pdf.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
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
}

/// Table resolution in `μ = cos θo` and in perceptual roughness.
const TABLE: usize = 32;

/// The directional albedo `E(μ, r) = ∫ D V cos θi dwi` of the sheen lobe with `C = 1`,
/// bilinear in a table computed on first use (midpoint quadrature, 64 × 64 cells in
/// (cos θi, φ) per entry; its error is below 10⁻³ of the table's values).
pub fn sheen_albedo(mu: f32, roughness: f32) -> f32 {
    static ALBEDO: OnceLock<Vec<f32>> = OnceLock::new();
    let table = ALBEDO.get_or_init(|| {
        let mut t = Vec::with_capacity(TABLE * TABLE);
        for ri in 0..TABLE {
            let r = ri as f32 / (TABLE - 1) as f32;
            let lobe = SheenBsdf::new(Vec3::ONE, r);
            for mi in 0..TABLE {
                let mu = (mi as f32 / (TABLE - 1) as f32).max(1e-3);
                t.push(directional_albedo(&lobe, mu, 64));
            }
        }
        t
    });
    let x = mu.clamp(0.0, 1.0) * (TABLE - 1) as f32;
    let y = if roughness.is_finite() {
        roughness.clamp(0.0, 1.0)
    } else {
        0.0
    } * (TABLE - 1) as f32;
    let (x0, y0) = (
        (x.floor() as usize).min(TABLE - 2),
        (y.floor() as usize).min(TABLE - 2),
    );
    let (fx, fy) = (x - x0 as f32, y - y0 as f32);
    let at = |i: usize, j: usize| table.get(j * TABLE + i).copied().unwrap_or(0.0);
    let a = at(x0, y0) * (1.0 - fx) + at(x0 + 1, y0) * fx;
    let b = at(x0, y0 + 1) * (1.0 - fx) + at(x0 + 1, y0 + 1) * fx;
    a * (1.0 - fy) + b * fy
}

/// `∫ D V cos θi dwi` for `wo` at `cos θo = mu`, by the midpoint rule on `n × n` cells in
/// (cos θi, φ).
pub fn directional_albedo(lobe: &SheenBsdf, mu: f32, n: usize) -> f32 {
    let wo = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    let mut sum = 0.0f64;
    for i in 0..n {
        let c = (i as f32 + 0.5) / n as f32;
        let s = (1.0 - c * c).max(0.0).sqrt();
        for j in 0..n {
            let phi = (j as f32 + 0.5) / n as f32 * 2.0 * PI;
            let wi = Vec3::new(s * phi.cos(), s * phi.sin(), c);
            sum += (lobe.dv(wo, wi) * c) as f64;
        }
    }
    (sum * (2.0 * std::f64::consts::PI) / (n * n) as f64) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Estevez & Kulla's normalisation: `∫ D(h) cos θh dh = 1` over the hemisphere.
    #[test]
    fn charlie_d_is_normalised() {
        for &r in &[0.3f32, 0.5, 0.8, 1.0] {
            let alpha = r * r;
            let n = 4000;
            let mut sum = 0.0f64;
            for i in 0..n {
                // ∫ D cos dω = 2π ∫ D(μ) μ dμ.
                let mu = (i as f64 + 0.5) / n as f64;
                let s = (1.0 - mu * mu).sqrt() as f32;
                let d = charlie_d(alpha, Vec3::new(s, 0.0, mu as f32)) as f64;
                sum += d * mu / n as f64;
            }
            let total = sum * std::f64::consts::TAU;
            assert!((total - 1.0).abs() < 2e-3, "r = {r}: ∫ D cos = {total}");
        }
    }

    #[test]
    fn albedo_table_matches_direct_quadrature_and_stays_below_one() {
        for &(mu, r) in &[(0.9f32, 0.5f32), (0.3, 0.8), (0.05, 1.0), (0.6, 0.2)] {
            let direct = directional_albedo(&SheenBsdf::new(Vec3::ONE, r), mu, 128);
            let table = sheen_albedo(mu, r);
            assert!(direct <= 1.0 && table <= 1.0, "{direct} {table}");
            assert!(
                (direct - table).abs() < 0.02 * direct.max(0.05),
                "μ = {mu}, r = {r}: table {table} vs {direct}"
            );
        }
    }
}
