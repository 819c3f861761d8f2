//! Directional albedo of single-scattering GGX reflection, tabulated at first use, for the
//! energy compensation of the metallic-roughness BRDF (Kulla & Conty 2017; Turquin 2019).
//!
//! For the isotropic GGX lobe `f_ss = D(h) G2(wo, wi) / (4 |n·wo| |n·wi|)` of roughness `α`
//! and a view direction at `μ = n·wo`, with `w(c) = (1 − c)⁵` Schlick's weight:
//!
//! ```text
//! E0(μ, α) = ∫ f_ss cos θi dωi                  (the albedo with F = 1)
//! E1(μ, α) = ∫ w(wo·h) f_ss cos θi dωi          (its Schlick-weighted part)
//! E_spec(μ) = f0 (E0 − E1) + f90 E1             (albedo of the lobe with Schlick's
//!                                                F = f0 + (f90 − f0) w, exact since F is
//!                                                linear in f0 and f90)
//! A0(α) = 2 ∫ E0 μ dμ,  A1(α) = 2 ∫ E1 μ dμ                          (cosine averages)
//! ```
//!
//! The table (`MU_NODES` rows of `μ = (i/(N_μ − 1))²`, `ROUGHNESS_NODES` columns of
//! perceptual roughness `r = √α` at `j/(N_r − 1)`: both squares pack nodes where the albedo
//! changes fastest, near grazing, where rough GGX's albedo climbs back towards 1 as
//! `G2/G1 → 1`, and at small α) is integrated by [`albedo_quadrature`](super::albedo_quadrature)
//! in the build script; lookups are bilinear in `(√μ, r)`. Smooth surfaces
//! (`α <` [`SMOOTH_ALPHA`]) use the delta limit exactly: `E0 = 1`, `E1 = w(μ)`, `A0 = 1`,
//! `A1 = 2 ∫ (1 − μ)⁵ μ dμ = 1/21`.
//!
//! The table is deterministic (the same numbers on every build and thread count) and costs a
//! render nothing: integrated at start-up it took about 0.2 CPU s of every process.

use super::albedo_quadrature::schlick_weight;
pub use super::albedo_quadrature::{MU_NODES, ROUGHNESS_NODES};
use super::microfacet::SMOOTH_ALPHA;
use glam::Vec3;

include!(concat!(env!("OUT_DIR"), "/ggx_albedo_table.rs"));
/// `2 ∫₀¹ (1 − μ)⁵ μ dμ = 2 · 1!·5!/7!`: the cosine average of Schlick's weight.
const SCHLICK_WEIGHT_AVERAGE: f32 = 1.0 / 21.0;

/// The directional albedos `(E0, E1)` of the single-scatter GGX lobe at one `(μ, α)`, and
/// the cosine averages `(A0, A1)` at one `α` (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GgxAlbedo {
    /// `E0(μ, α)`: the albedo with a Fresnel of 1.
    pub e0: f32,
    /// `E1(μ, α)`: the part of it weighted by Schlick's `(1 − wo·h)⁵`.
    pub e1: f32,
}

/// Cosine averages of the albedos at one roughness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GgxAlbedoAverage {
    /// `A0(α) = 2 ∫ E0 μ dμ`.
    pub a0: f32,
    /// `A1(α) = 2 ∫ E1 μ dμ`.
    pub a1: f32,
}

/// `(E0, E1)` at `(μ, α)` by quasi-Monte Carlo over visible normals, as the table's cells
/// were integrated (for tests that compare the table with other integrals).
pub fn integrate_albedo(mu: f32, alpha: f32) -> GgxAlbedo {
    let [e0, e1] = super::albedo_quadrature::integrate_albedo(mu, alpha);
    GgxAlbedo { e0, e1 }
}

/// Column index and weight of the upper neighbour for `α`.
#[inline]
fn roughness_position(alpha: f32) -> (usize, f32) {
    let x = alpha.max(0.0).sqrt().min(1.0) * (ROUGHNESS_NODES - 1) as f32;
    let j = (x as usize).min(ROUGHNESS_NODES - 2);
    (j, (x - j as f32).clamp(0.0, 1.0))
}

/// `(E0, E1)` at `μ = n·wo` and roughness `α`, bilinear in the table (exact delta limit below
/// [`SMOOTH_ALPHA`]).
#[inline]
pub fn ggx_albedo(mu: f32, alpha: f32) -> GgxAlbedo {
    if alpha.is_nan() || alpha < SMOOTH_ALPHA {
        return GgxAlbedo {
            e0: 1.0,
            e1: schlick_weight(mu.abs()),
        };
    }
    let (j, tj) = roughness_position(alpha);
    let y = mu.abs().min(1.0).sqrt() * (MU_NODES - 1) as f32;
    let i = (y as usize).min(MU_NODES - 2);
    let ti = y - i as f32;
    let at = |jj: usize, ii: usize| ALBEDO[jj * MU_NODES + ii];
    let lerp2 =
        |a: [f32; 2], b: [f32; 2], s: f32| [a[0] + (b[0] - a[0]) * s, a[1] + (b[1] - a[1]) * s];
    let lo = lerp2(at(j, i), at(j, i + 1), ti);
    let hi = lerp2(at(j + 1, i), at(j + 1, i + 1), ti);
    let e = lerp2(lo, hi, tj);
    GgxAlbedo { e0: e[0], e1: e[1] }
}

/// `(A0, A1)` at roughness `α`, linear in the table's roughness axis (exact delta limit
/// below [`SMOOTH_ALPHA`]).
#[inline]
pub fn ggx_albedo_average(alpha: f32) -> GgxAlbedoAverage {
    if alpha.is_nan() || alpha < SMOOTH_ALPHA {
        return GgxAlbedoAverage {
            a0: 1.0,
            a1: SCHLICK_WEIGHT_AVERAGE,
        };
    }
    let (j, tj) = roughness_position(alpha);
    let (a, b) = (AVERAGE[j], AVERAGE[j + 1]);
    let l = |k: usize| a[k] + (b[k] - a[k]) * tj;
    GgxAlbedoAverage { a0: l(0), a1: l(1) }
}

/// The albedo of the single-scatter lobe with Schlick's Fresnel `(f0, f90)`, per channel:
/// `E_F(μ) = f0 (E0 − E1) + f90 E1`.
#[inline]
pub fn schlick_albedo(e: GgxAlbedo, f0: Vec3, f90: Vec3) -> Vec3 {
    f0 * (e.e0 - e.e1) + f90 * e.e1
}

/// The cosine average `2 ∫ E_F(μ) μ dμ = f0 (A0 − A1) + f90 A1` of [`schlick_albedo`].
#[inline]
pub fn schlick_albedo_average(a: GgxAlbedoAverage, f0: Vec3, f90: Vec3) -> Vec3 {
    f0 * (a.a0 - a.a1) + f90 * a.a1
}

/// The factor `1 + F_ms (1/E0 − 1)` on a single-scatter specular lobe (Turquin's scaling,
/// with Kulla & Conty's Fresnel weight `F_ms`, see [`multiple_scattering_fresnel`]): it adds
/// the energy single scattering loses, `1 − E0` of it for a white lobe (`F_ms = 1`, whose
/// albedo is then exactly 1), less for a coloured one.
#[inline]
pub fn multiple_scattering_factor(e: GgxAlbedo, f_ms: Vec3) -> Vec3 {
    Vec3::ONE + f_ms * (1.0 / e.e0.max(MIN_ALBEDO) - 1.0)
}

/// Kulla & Conty's Fresnel weight of the multiply scattered light for a lobe whose
/// cosine-averaged Fresnel is `f_avg` and whose white albedo averages `e_avg = A0(α)`:
/// light that leaves after `k + 1` bounces between microfacets has met the Fresnel `k + 1`
/// times and escaped with probability `E_avg` after each, so its share relative to a white
/// lobe is the geometric series
///
/// ```text
/// F_ms = Σₖ F_avg^(k+1) (1 − E_avg)^k E_avg / Σₖ (1 − E_avg)^k E_avg
///      = F_avg E_avg / (1 − F_avg (1 − E_avg))
/// ```
///
/// `F_ms = 1` for `F_avg = 1` and `F_ms ≤ F_avg` always: a coloured rough metal is darker and
/// more saturated than Turquin's `F_ms = f0` makes it. (Cycles' Principled BSDF scales its
/// lobes by the same term.)
#[inline]
pub fn multiple_scattering_fresnel(f_avg: Vec3, e_avg: f32) -> Vec3 {
    let f = f_avg.clamp(Vec3::ZERO, Vec3::ONE);
    let e = e_avg.clamp(0.0, 1.0);
    let denominator = (Vec3::ONE - f * (1.0 - e)).max(Vec3::splat(MIN_ALBEDO));
    f * e / denominator
}

/// The cosine average `2 ∫ F(μ) μ dμ = f0 + (f90 − f0)/21` of Schlick's Fresnel.
#[inline]
pub fn schlick_fresnel_average(f0: Vec3, f90: Vec3) -> Vec3 {
    f0 + (f90 - f0) * SCHLICK_WEIGHT_AVERAGE
}

/// A floor on `E0` before dividing by it: the smallest tabulated `E0` (α = 1, grazing) is
/// about 0.3, so this only guards against a corrupted lookup.
const MIN_ALBEDO: f32 = 1e-2;

/// Turquin's factor `1/E` for a white lobe whose single-scatter albedo is `e` (the clear
/// coat's `E0`, a rough dielectric's `R + T`): the compensated lobe then reflects (and
/// transmits) all the power it receives. `e` is floored like `E0` above.
#[inline]
pub fn white_lobe_scale(e: f32) -> f32 {
    1.0 / e.max(MIN_ALBEDO)
}

#[cfg(test)]
mod tests {
    use super::super::microfacet::integrate_over_normals;
    use super::super::microfacet::{TrowbridgeReitz, reflect};
    use super::*;

    /// The build script's table is the crate's own quadrature, cell for cell (the same code
    /// compiled twice; a few columns, since each costs a few milliseconds), and its averages
    /// are that quadrature's Simpson sums.
    #[test]
    fn built_table_is_the_quadrature() {
        for j in [1, 9, 31, 50, ROUGHNESS_NODES - 1] {
            let (column, average) = super::super::albedo_quadrature::column(j);
            for (i, e) in column.iter().enumerate() {
                let built = ALBEDO[j * MU_NODES + i];
                assert!(
                    (built[0] - e[0]).abs() <= 1e-6 && (built[1] - e[1]).abs() <= 1e-6,
                    "column {j}, row {i}: built {built:?}, quadrature {e:?}"
                );
            }
            let built = AVERAGE[j];
            assert!(
                (built[0] - average[0]).abs() <= 1e-6 && (built[1] - average[1]).abs() <= 1e-6,
                "column {j}: built {built:?}, quadrature {average:?}"
            );
        }
    }

    /// The tabulated (interpolated) albedos at points between the table's nodes agree with an
    /// independent quadrature of `D G2 F (wo·m)/μo` over microfacet normals (the
    /// single-scatter BSDF times cos θi, moved to the half-vector domain by the Jacobian
    /// `4 |wo·m|`) to 10⁻³.
    #[test]
    fn table_matches_an_independent_integral_of_the_single_scatter_lobe() {
        for &roughness in &[0.2f32, 0.37, 0.5, 0.73, 1.0] {
            let alpha = roughness * roughness;
            let tr = TrowbridgeReitz::isotropic(alpha);
            for &mu in &[0.05f32, 0.21, 0.5, 0.77, 0.99] {
                let wo = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
                let lobe = |m: Vec3, schlick: bool| {
                    let om = wo.dot(m);
                    let wi = reflect(wo, m);
                    if om <= 0.0 || wi.z <= 0.0 {
                        return 0.0;
                    }
                    let f = if schlick { schlick_weight(om) } else { 1.0 };
                    f64::from(tr.d(m) * tr.g2(wo, wi) * f * om / mu)
                };
                let e0 = integrate_over_normals(f64::from(alpha), (1200, 256), |m| lobe(m, false));
                let e1 = integrate_over_normals(f64::from(alpha), (1200, 256), |m| lobe(m, true));
                let t = ggx_albedo(mu, alpha);
                assert!(
                    (f64::from(t.e0) - e0).abs() < 1e-3 && (f64::from(t.e1) - e1).abs() < 1e-3,
                    "r = {roughness}, μ = {mu}: table ({}, {}) vs quadrature ({e0}, {e1})",
                    t.e0,
                    t.e1
                );
            }
        }
    }

    #[test]
    fn averages_and_limits() {
        // Smooth: the delta limit. Rough: white GGX at α = 1 keeps only about a third at
        // normal incidence.
        let s = ggx_albedo(0.5, 0.0);
        assert_eq!(s.e0, 1.0);
        assert!((s.e1 - 0.5f32.powi(5)).abs() < 1e-7);
        let r = ggx_albedo(0.9, 1.0);
        assert!(r.e0 > 0.25 && r.e0 < 0.5, "{r:?}");
        // The averages of the delta limit, by the table's own midpoint rule at α just above
        // the smooth threshold.
        let a = ggx_albedo_average(1.1e-3);
        assert!((a.a0 - 1.0).abs() < 2e-3, "{a:?}");
        assert!((a.a1 - SCHLICK_WEIGHT_AVERAGE).abs() < 2e-3, "{a:?}");
        // A white compensated lobe reflects 1 at every angle.
        for &mu in &[0.05, 0.5, 1.0] {
            let e = ggx_albedo(mu, 0.6);
            let albedo =
                schlick_albedo(e, Vec3::ONE, Vec3::ONE) * multiple_scattering_factor(e, Vec3::ONE);
            assert!((albedo - Vec3::ONE).abs().max_element() < 1e-5, "{albedo}");
        }
    }
}
