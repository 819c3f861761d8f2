//! Directional albedo of the single-scattering rough dielectric interface (reflection plus
//! transmission, in power), tabulated at first use, for the energy compensation of
//! KHR_materials_transmission's rough glass ([`DielectricBsdf`](super::DielectricBsdf) under
//! [`BrdfModel::Compensated`](super::BrdfModel::Compensated)).
//!
//! For a white interface of roughness `α` with relative index `η = η_i/η_o` (the index on
//! the far side over the index on `wo`'s side: `η > 1` entering glass, `η < 1` leaving it), a
//! view direction at `μ = |n·wo|` and Walter et al.'s single-scatter BSDF:
//!
//! ```text
//! E(μ, α, η) = ∫ f_r cos θi dωi + η² ∫ f_t cos θi dωi
//! ```
//!
//! the fraction of the power arriving from `wo` that leaves reflected or transmitted after
//! one microfacet interaction (the `η²` undoes the radiance scaling `1/η²` of `f_t`, so that
//! the sum is power, which a smooth interface conserves exactly: `E = 1` at `α = 0`). It is
//! integrated over visible normals `m ~ Dv(wo, m)`: a normal reflects with weight
//! `F(wo·m) G2(wo, wr)/G1(wo)` when `wr = reflect(wo, m)` is above the surface and transmits
//! with weight `(1 − F(wo·m)) G2(wo, wt)/G1(wo)` when `wt = refract(wo, m, η)` is below it, so
//! `E ≈ (1/N) Σ [F G2(wo, wr) + (1 − F) G2(wo, wt)]/G1(wo)` over a 2-D Hammersley set of
//! visible normals. `F` is the exact dielectric Fresnel, 1 at total internal reflection (which
//! makes the leaving table differ from the entering one).
//!
//! Two tables, entering (`η ≥ 1`) and leaving (`1/η`), each over `(√μ, r = √α, s)` with
//! `s = (η − 1)/(η + 1)` (`√f0` of the interface at normal incidence): [`MU_NODES`] ×
//! [`ROUGHNESS_NODES`] × [`ETA_NODES`], `s` from 0 (η = 1) to [`S_MAX`] (η = 3; larger indices
//! read the last slice), trilinear lookups. Each η slice (1.7·10⁷ visible normals, about 0.6 CPU
//! seconds, its roughness rows in parallel) is built once per process on its first
//! lookup, so a scene's glass of one index builds two slices per side; deterministic. (A grid
//! half as fine in each axis was 2.8·10⁻³ off the quadrature where the albedo bends: across
//! the critical angle's sweep in η, at grazing μ for low roughness.) Smooth interfaces (`α <`
//! [`SMOOTH_ALPHA`]) return 1 exactly.
//!
//! A thin-walled interface mirrors its transmitted lobe through the tangent plane, so its
//! transmitted directions see the same `G2` as the reflected ones and its albedo is `E0(μ, α)`
//! of the GGX reflection table ([`super::energy::ggx_albedo`]) whatever `η`: it needs no table
//! of its own.

pub use super::albedo_quadrature::{MU_NODES, ROUGHNESS_NODES};
use super::albedo_quadrature::{alpha_of_node, radical_inverse_2, sqrt_mu_of_node};
use super::dielectric::{fresnel_dielectric, refract};
use super::microfacet::{SMOOTH_ALPHA, TrowbridgeReitz, reflect};
use glam::{Vec2, Vec3};
use rayon::prelude::*;
use std::sync::OnceLock;

/// Slices: `s = (η − 1)/(η + 1) = S_MAX · k/(ETA_NODES − 1)`.
pub const ETA_NODES: usize = 33;
/// The largest tabulated `s`: η = 3 (glTF's KHR_materials_ior lists 1–2.42 for common
/// materials; beyond 3 the last slice is read).
pub const S_MAX: f32 = 0.5;
/// Quasi-Monte Carlo points per cell (a power of two).
const SAMPLES_PER_CELL: u32 = 4096;

/// One slice of a table: `E` at `[j · MU_NODES + i]` for one η node and side.
type Slice = Vec<f32>;

/// The slice of node `k` entering (`leaving = false`) or leaving, built on first use: a
/// material of one index touches two slices per side, a tenth of the table.
fn slice(leaving: bool, k: usize) -> &'static Slice {
    static SLICES: [OnceLock<Slice>; 2 * ETA_NODES] = [const { OnceLock::new() }; 2 * ETA_NODES];
    SLICES[usize::from(leaving) * ETA_NODES + k].get_or_init(|| build_slice(leaving, k))
}

/// `η ≥ 1` of slice `k`.
#[inline]
fn eta_of_node(k: usize) -> f32 {
    let s = S_MAX * k as f32 / (ETA_NODES - 1) as f32;
    (1.0 + s) / (1.0 - s)
}

/// `E(μ, α, η)` (see the module documentation) by quasi-Monte Carlo over visible normals,
/// for `eta` the relative index `η_i/η_o` (below 1: leaving the denser medium). The tables'
/// cells; also what the tests compare with an independent quadrature.
pub fn integrate_dielectric_albedo(mu: f32, alpha: f32, eta: f32) -> f32 {
    if alpha < SMOOTH_ALPHA {
        return 1.0;
    }
    let tr = TrowbridgeReitz::isotropic(alpha);
    let mu = mu.clamp(1e-4, 1.0);
    let wo = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    let g1 = tr.g1(wo);
    if g1 <= 0.0 {
        return 1.0;
    }
    let mut sum = 0.0f64;
    for n in 0..SAMPLES_PER_CELL {
        let u = Vec2::new(
            (n as f32 + 0.5) / SAMPLES_PER_CELL as f32,
            radical_inverse_2(n),
        );
        let m = tr.sample_visible(wo, u);
        let f = fresnel_dielectric(wo.dot(m), eta);
        let wr = reflect(wo, m);
        if wr.z > 0.0 {
            sum += f64::from(f * tr.g2(wo, wr));
        }
        if f < 1.0
            && let Some(wt) = refract(wo, m, eta)
            && wt.z < 0.0
        {
            sum += f64::from((1.0 - f) * tr.g2(wo, wt));
        }
    }
    (sum / f64::from(SAMPLES_PER_CELL) / f64::from(g1)) as f32
}

/// The cells of one slice, `(j, i)` row-major, roughness rows in parallel.
fn build_slice(leaving: bool, k: usize) -> Slice {
    let eta = eta_of_node(k);
    let eta = if leaving { 1.0 / eta } else { eta };
    (0..ROUGHNESS_NODES)
        .into_par_iter()
        .flat_map_iter(|j| {
            let alpha = alpha_of_node(j);
            (0..MU_NODES).map(move |i| {
                let x = sqrt_mu_of_node(i);
                integrate_dielectric_albedo(x * x, alpha, eta)
            })
        })
        .collect()
}

/// Lower node index and weight of the upper neighbour for `x` in node units on `n` nodes.
#[inline]
fn position(x: f32, n: usize) -> (usize, f32) {
    let x = x.clamp(0.0, (n - 1) as f32);
    let i = (x as usize).min(n - 2);
    (i, (x - i as f32).clamp(0.0, 1.0))
}

/// `E(μ, α, η)` of the single-scatter rough dielectric, trilinear in the tables (1 for smooth
/// interfaces); `eta` is the relative index `η_i/η_o` seen from `wo`'s side, `mu = |n·wo|`.
#[inline]
pub fn dielectric_albedo(mu: f32, alpha: f32, eta: f32) -> f32 {
    if alpha.is_nan() || alpha < SMOOTH_ALPHA || !(eta.is_finite() && eta > 0.0) {
        return 1.0;
    }
    let (leaving, eta) = if eta >= 1.0 {
        (false, eta)
    } else {
        (true, 1.0 / eta)
    };
    let s = (eta - 1.0) / (eta + 1.0);
    let (k, tk) = position(s / S_MAX * (ETA_NODES - 1) as f32, ETA_NODES);
    let (j, tj) = position(
        alpha.sqrt().min(1.0) * (ROUGHNESS_NODES - 1) as f32,
        ROUGHNESS_NODES,
    );
    let (i, ti) = position(mu.abs().min(1.0).sqrt() * (MU_NODES - 1) as f32, MU_NODES);
    let lerp = |a: f32, b: f32, w: f32| a + (b - a) * w;
    let bilinear = |k: usize| {
        let cells = slice(leaving, k);
        let at = |j: usize, i: usize| cells[j * MU_NODES + i];
        lerp(
            lerp(at(j, i), at(j, i + 1), ti),
            lerp(at(j + 1, i), at(j + 1, i + 1), ti),
            tj,
        )
    };
    if tk == 0.0 {
        // On a node (η at a slice, or beyond the last): one slice.
        return bilinear(k);
    }
    lerp(bilinear(k), bilinear(k + 1), tk)
}

#[cfg(test)]
mod tests {
    use super::super::microfacet::integrate_over_normals;
    use super::*;

    /// The interpolated tables at points between their nodes (roughness, μ and η all off the
    /// grid) agree with an independent quadrature over microfacet normals of
    /// `D(m) (wo·m)/μo · [F G2(wo, wr) + (1 − F) G2(wo, wt)]` (the single-scatter BSDF's
    /// reflected plus transmitted power, moved to the half-vector domain) to 10⁻³, entering
    /// and leaving.
    #[test]
    fn tables_match_an_independent_integral_of_the_single_scatter_dielectric() {
        let mut worst = 0.0f64;
        let mut bad = Vec::new();
        for &eta_out in &[1.33f32, 1.5, 2.1] {
            for eta in [eta_out, 1.0 / eta_out] {
                for &roughness in &[0.21f32, 0.5, 0.77, 1.0] {
                    let alpha = roughness * roughness;
                    let tr = TrowbridgeReitz::isotropic(alpha);
                    for &mu in &[0.06f32, 0.3, 0.62, 0.97] {
                        let wo = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
                        let quadrature =
                            integrate_over_normals(f64::from(alpha), (1200, 256), |m| {
                                let om = wo.dot(m);
                                if om <= 0.0 {
                                    return 0.0;
                                }
                                let f = fresnel_dielectric(om, eta);
                                let wr = reflect(wo, m);
                                let mut g = 0.0;
                                if wr.z > 0.0 {
                                    g += f * tr.g2(wo, wr);
                                }
                                if let Some(wt) = refract(wo, m, eta).filter(|w| w.z < 0.0) {
                                    g += (1.0 - f) * tr.g2(wo, wt);
                                }
                                f64::from(tr.d(m) * om / mu * g)
                            });
                        let table = f64::from(dielectric_albedo(mu, alpha, eta));
                        let e = (table - quadrature).abs();
                        worst = worst.max(e);
                        if e >= 1e-3 {
                            bad.push(format!(
                                "η = {eta}, r = {roughness}, μ = {mu}: table {table} vs quadrature {quadrature}"
                            ));
                        }
                    }
                }
            }
        }
        eprintln!("worst |table − quadrature| = {worst:.2e}");
        assert!(bad.is_empty(), "off by 10⁻³ or more:\n{}", bad.join("\n"));
    }

    #[test]
    fn limits() {
        // Smooth: power is conserved exactly.
        assert_eq!(dielectric_albedo(0.4, 0.0, 1.5), 1.0);
        assert_eq!(dielectric_albedo(0.4, 0.5, f32::NAN), 1.0);
        // Rough glass loses energy to masking, more at high roughness; it never gains.
        let low = dielectric_albedo(0.7, 0.05, 1.5);
        let high = dielectric_albedo(0.7, 1.0, 1.5);
        assert!(high < low && low < 1.0 && high > 0.5, "{low} {high}");
        // Nodes reproduce their cells exactly.
        let (k, j, i) = (8, 40, 32);
        let eta = eta_of_node(k);
        let r = j as f32 / (ROUGHNESS_NODES - 1) as f32;
        let x = i as f32 / (MU_NODES - 1) as f32;
        let cell = integrate_dielectric_albedo(x * x, r * r, 1.0 / eta);
        assert!((dielectric_albedo(x * x, r * r, 1.0 / eta) - cell).abs() < 1e-5);
    }
}
