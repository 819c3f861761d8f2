//! The quadrature that fills [`energy`](super::energy)'s albedo table: compiled into the
//! build script, which tabulates it once per build (so no render pays for it at start-up),
//! and into the crate, whose tests compare the built table with it and with an independent
//! integral. It may only use `super::microfacet`, glam and std (the build script declares
//! both files as modules of its own).
//!
//! Each cell is integrated by quasi-Monte Carlo over visible normals: a reflected direction
//! drawn from `Dv(wo, m)` has weight `f_ss cos θi / pdf = G2(wo, wi) / G1(wo)`, so
//! `E0 ≈ (1/N) Σ G2/G1` and `E1 ≈ (1/N) Σ w(wo·m) G2/G1` over a 2-D Hammersley set (the
//! integrand is smooth and bounded by 1, so the error is far below the 10⁻³ the tests ask).
//! Rows are `μ = (i/(N_μ − 1))²`, columns perceptual roughness `r = √α` at `j/(N_r − 1)`.
//! The averages are Simpson's rule in `x = √μ`: `2 ∫ g μ dμ = 4 ∫ g(x²) x³ dx`.

use super::microfacet::{SMOOTH_ALPHA, TrowbridgeReitz, reflect};
use glam::{Vec2, Vec3};

/// Rows of the table: `μ = n·wo = (i/(MU_NODES − 1))²` (an odd count, for Simpson's rule).
pub const MU_NODES: usize = 65;
/// Columns of the table: perceptual roughness `r = √α` at `j/(ROUGHNESS_NODES − 1)`.
pub const ROUGHNESS_NODES: usize = 64;
/// Quasi-Monte Carlo points per cell (a power of two, so the Hammersley set is balanced).
const SAMPLES_PER_CELL: u32 = 2048;

/// Van der Corput's radical inverse in base 2 of `i` (the Hammersley sets' second axis).
#[inline]
pub fn radical_inverse_2(i: u32) -> f32 {
    i.reverse_bits() as f32 * (1.0 / 4_294_967_296.0)
}

/// `√μ` of row `i`.
#[inline]
pub fn sqrt_mu_of_node(i: usize) -> f32 {
    i as f32 / (MU_NODES - 1) as f32
}

/// `α` of column `j`.
#[inline]
pub fn alpha_of_node(j: usize) -> f32 {
    let r = j as f32 / (ROUGHNESS_NODES - 1) as f32;
    r * r
}

/// Schlick's weight `(1 − cos)⁵`.
#[inline]
pub fn schlick_weight(cos: f32) -> f32 {
    let w = (1.0 - cos).clamp(0.0, 1.0);
    let w2 = w * w;
    w2 * w2 * w
}

/// `[E0, E1]` at `(μ, α)` by quasi-Monte Carlo over visible normals.
pub fn integrate_albedo(mu: f32, alpha: f32) -> [f32; 2] {
    if alpha < SMOOTH_ALPHA {
        return [1.0, schlick_weight(mu)];
    }
    let tr = TrowbridgeReitz::isotropic(alpha);
    let mu = mu.clamp(1e-4, 1.0);
    let wo = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    let g1 = tr.g1(wo);
    let (mut e0, mut e1) = (0.0f64, 0.0f64);
    for k in 0..SAMPLES_PER_CELL {
        let u = Vec2::new(
            (k as f32 + 0.5) / SAMPLES_PER_CELL as f32,
            radical_inverse_2(k),
        );
        let m = tr.sample_visible(wo, u);
        let wi = reflect(wo, m);
        if wi.z <= 0.0 || g1 <= 0.0 {
            continue;
        }
        let weight = f64::from(tr.g2(wo, wi) / g1);
        e0 += weight;
        e1 += weight * f64::from(schlick_weight(wo.dot(m)));
    }
    let n = f64::from(SAMPLES_PER_CELL);
    [(e0 / n) as f32, (e1 / n) as f32]
}

/// Column `j` of the table: `[E0, E1]` at every row, and the cosine averages `[A0, A1]`.
pub fn column(j: usize) -> (Vec<[f32; 2]>, [f32; 2]) {
    let alpha = alpha_of_node(j);
    let mut albedo = Vec::with_capacity(MU_NODES);
    let (mut a0, mut a1) = (0.0f64, 0.0f64);
    for i in 0..MU_NODES {
        let x = sqrt_mu_of_node(i);
        let e = integrate_albedo(x * x, alpha);
        albedo.push(e);
        // Simpson's rule for 4 ∫ g(x²) x³ dx on the rows' own nodes.
        let simpson = match i {
            0 => 1.0,
            i if i == MU_NODES - 1 => 1.0,
            i if i % 2 == 1 => 4.0,
            _ => 2.0,
        };
        let h = 1.0 / (MU_NODES - 1) as f64;
        let w = 4.0 * f64::from(x).powi(3) * simpson * h / 3.0;
        a0 += w * f64::from(e[0]);
        a1 += w * f64::from(e[1]);
    }
    (albedo, [a0 as f32, a1 as f32])
}
