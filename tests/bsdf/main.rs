//! BSDF tests that can fail: energy, reciprocity, chi-square goodness of fit of `sample`
//! against `pdf`, the pdf's integral, sample weights, and values against the glTF
//! specification's Appendix B formulas written out again here in f64.

mod harness;

use glam::{Vec2, Vec3};
use glint::bsdf::{BrdfModel, Bsdf, LambertBsdf, MetallicRoughnessBsdf};
use glint::sampling::warp::{UNIFORM_HEMISPHERE_PDF, uniform_hemisphere};
use harness::{P_THRESHOLD, check_sampling, dir, reciprocity_error, rng};
use rand::Rng;

/// Samples per chi-square configuration.
const N: usize = 400_000;

/// Directions of `wo`: near normal, 45°-ish, grazing-ish (cos θ, φ).
const WO: [(f64, f64); 3] = [(0.97, 0.3), (0.6, 2.0), (0.15, 4.0)];

/// ∫ f(wo, wi) |cos θi| dwi over the upper hemisphere by uniform hemisphere sampling
/// (independent of the BSDF's own sampler): (mean, standard error) per channel.
fn albedo_uniform(bsdf: &impl Bsdf, wo: Vec3, n: usize, seed: u64) -> (Vec3, Vec3) {
    let mut r = rng(seed);
    let (mut s, mut s2) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
    for _ in 0..n {
        let wi = uniform_hemisphere(Vec2::new(r.random(), r.random()));
        let v = (bsdf.eval(wo, wi) * wi.z / UNIFORM_HEMISPHERE_PDF).as_dvec3();
        s += v;
        s2 += v * v;
    }
    let nf = n as f64;
    let mean = s / nf;
    let se = ((s2 / nf - mean * mean).max(glam::DVec3::ZERO) / nf).map(f64::sqrt);
    (mean.as_vec3(), se.as_vec3())
}

fn assert_sampling_ok(name: &str, bsdf: &impl Bsdf, seed: u64) {
    for (k, &(c, phi)) in WO.iter().enumerate() {
        let wo = dir(c, phi);
        let rep = check_sampling(bsdf, wo, N, seed + k as u64);
        assert!(
            rep.p_value > P_THRESHOLD,
            "{name}, cos θo = {c}: chi-square p = {:.3e} ({rep:?})",
            rep.p_value
        );
        // The pdf integrates to the fraction of draws that give a non-delta direction
        // (binomial standard error; 2·10⁻³ for the quadrature of peaked lobes).
        let p = rep.non_delta_fraction;
        let tol = 5.0 * (p * (1.0 - p) / N as f64).sqrt() + 2e-3;
        assert!(
            (rep.pdf_integral - p).abs() < tol,
            "{name}, cos θo = {c}: ∫pdf = {} vs non-delta fraction {p}",
            rep.pdf_integral
        );
        // Non-delta sample weights average to the albedo found by uniform sampling of eval
        // (both estimators' errors, 5σ).
        let (a, se) = albedo_uniform(bsdf, wo, N, seed + 100 + k as u64);
        let delta = rep.albedo_non_delta - a;
        let tol =
            5.0 * (rep.albedo_se * rep.albedo_se + se * se).map(f32::sqrt) + Vec3::splat(1e-4);
        assert!(
            delta.abs().cmple(tol).all(),
            "{name}, cos θo = {c}: albedo by sampling {} ± {} vs uniform {a} ± {se}",
            rep.albedo_non_delta,
            rep.albedo_non_delta_se
        );
    }
}

/// Draws cosine-weighted directions but claims the uniform hemisphere's pdf (consistently in
/// `sample` and `pdf`): only the histogram can tell.
struct WrongPdf;

impl Bsdf for WrongPdf {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        LambertBsdf { albedo: Vec3::ONE }.eval(wo, wi)
    }
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z > 0.0 && wi.z > 0.0 {
            UNIFORM_HEMISPHERE_PDF
        } else {
            0.0
        }
    }
    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<glint::bsdf::BsdfSample> {
        let mut s = LambertBsdf { albedo: Vec3::ONE }.sample(wo, u_lobe, u)?;
        s.pdf = UNIFORM_HEMISPHERE_PDF;
        s.weight = self.eval(wo, s.wi) * s.wi.z / s.pdf;
        Some(s)
    }
    fn flags(&self) -> glint::bsdf::BsdfFlags {
        glint::bsdf::BsdfFlags::REFLECTION | glint::bsdf::BsdfFlags::DIFFUSE
    }
}

#[test]
fn chi_square_rejects_a_wrong_pdf() {
    let rep = check_sampling(&WrongPdf, dir(0.8, 1.0), 100_000, 5);
    assert!(rep.p_value < 1e-12, "p = {}", rep.p_value);
}

// --- Lambert ---------------------------------------------------------------------------

#[test]
fn lambert_conserves_energy_and_samples_its_pdf() {
    let b = LambertBsdf { albedo: Vec3::ONE };
    assert_sampling_ok("lambert", &b, 1);
    // Energy equality: ρ = 1 reflects everything, at every angle.
    for &(c, phi) in &WO {
        let (a, se) = albedo_uniform(&b, dir(c, phi), N, 7);
        assert!((a - Vec3::ONE).abs().cmple(5.0 * se).all(), "{a} ± {se}");
    }
    assert_eq!(reciprocity_error(&b, 10_000, 3), 0.0);
}

// --- glTF metallic-roughness -------------------------------------------------------------

/// glTF 2.0 Appendix B, written out in f64 from the specification: GGX D with α = r², the
/// height-correlated visibility ν, Schlick Fresnel, `mix(dielectric, metal, metallic)`, with
/// KHR_materials_specular's `dielectric_f0 = min(f0_ior · specularColor, 1) · specular`,
/// `f90 = specular` and `(1 − max(F)) · diffuse`.
#[allow(clippy::too_many_arguments)]
fn appendix_b(
    base: [f64; 3],
    metallic: f64,
    roughness: f64,
    ior: f64,
    specular: f64,
    specular_color: [f64; 3],
    v: glam::DVec3,
    l: glam::DVec3,
) -> [f64; 3] {
    let n = glam::DVec3::Z;
    let h = (v + l).normalize();
    let a = roughness * roughness;
    let a2 = a * a;
    let (ndh, ndl, ndv, vdh) = (n.dot(h), n.dot(l), n.dot(v), v.dot(h));
    let chi = |x: f64| if x > 0.0 { 1.0 } else { 0.0 };
    let d = a2 * chi(ndh) / (std::f64::consts::PI * (ndh * ndh * (a2 - 1.0) + 1.0).powi(2));
    let vis = chi(h.dot(l)) * chi(h.dot(v))
        / (2.0
            * (ndv.abs() * (a2 + (1.0 - a2) * ndl * ndl).sqrt()
                + ndl.abs() * (a2 + (1.0 - a2) * ndv * ndv).sqrt()));
    let spec = d * vis;
    let fw = (1.0 - vdh.abs()).powi(5);
    let f0_ior = ((ior - 1.0) / (ior + 1.0)).powi(2);
    let fd: Vec<f64> = (0..3)
        .map(|k| {
            let f0 = (f0_ior * specular_color[k]).min(1.0) * specular;
            f0 + (specular - f0) * fw
        })
        .collect();
    let fd_max = fd.iter().cloned().fold(0.0, f64::max);
    let mut out = [0.0; 3];
    for k in 0..3 {
        let diffuse = base[k] / std::f64::consts::PI;
        let dielectric = fd[k] * spec + (1.0 - fd_max) * diffuse;
        let metal = spec * (base[k] + (1.0 - base[k]) * fw);
        out[k] = (1.0 - metallic) * dielectric + metallic * metal;
    }
    out
}

fn check_against_appendix_b(ior: f32, specular: f32, specular_color: Vec3) {
    let base = Vec3::new(0.8, 0.5, 0.2);
    let mut checked = 0;
    for &metallic in &[0.0f32, 0.4, 1.0] {
        for &roughness in &[0.2f32, 0.5, 1.0] {
            let b = MetallicRoughnessBsdf::new(base, metallic, roughness).with_dielectric_fresnel(
                ior,
                specular,
                specular_color,
            );
            for &(co, po) in &[(0.9, 0.0), (0.5, 1.0), (0.2, 2.5)] {
                for &(ci, pi) in &[(0.95, 3.0), (0.6, 4.0), (0.3, 1.2), (0.1, 0.2)] {
                    let (v, l) = (dir(co, po), dir(ci, pi));
                    let got = b.eval(v, l);
                    let want = appendix_b(
                        base.as_dvec3().to_array(),
                        metallic as f64,
                        roughness as f64,
                        ior as f64,
                        specular as f64,
                        specular_color.as_dvec3().to_array(),
                        v.as_dvec3(),
                        l.as_dvec3(),
                    );
                    for k in 0..3 {
                        let rel = (got[k] as f64 - want[k]).abs() / want[k].abs().max(1e-6);
                        assert!(
                            rel < 2e-4,
                            "m = {metallic}, r = {roughness}, v = {v}, l = {l}: {got} vs {want:?}"
                        );
                    }
                    checked += 1;
                }
            }
        }
    }
    assert_eq!(checked, 108);
}

#[test]
fn metallic_roughness_matches_appendix_b() {
    check_against_appendix_b(1.5, 1.0, Vec3::ONE);
}

#[test]
fn metallic_roughness_matches_the_ior_and_specular_extensions() {
    check_against_appendix_b(1.33, 0.7, Vec3::new(1.0, 0.5, 2.0));
    check_against_appendix_b(2.4, 1.0, Vec3::new(30.0, 1.0, 0.0));
}

#[test]
fn metallic_roughness_is_reciprocal() {
    for &(m, r) in &[(0.0, 0.3), (0.5, 0.6), (1.0, 1.0), (0.0, 0.0)] {
        let b = MetallicRoughnessBsdf::new(Vec3::new(0.7, 0.4, 0.9), m, r).with_dielectric_fresnel(
            1.6,
            0.8,
            Vec3::new(1.0, 0.8, 1.2),
        );
        let e = reciprocity_error(&b, 20_000, 11);
        assert!(
            e < 1e-4,
            "metallic {m}, roughness {r}: relative asymmetry {e}"
        );
    }
}

#[test]
fn metal_sampling_matches_pdf() {
    for model in BrdfModel::ALL {
        for (k, &r) in [0.3f32, 0.6, 1.0].iter().enumerate() {
            let b =
                MetallicRoughnessBsdf::new(Vec3::new(0.95, 0.64, 0.54), 1.0, r).with_model(model);
            assert_sampling_ok(&format!("{model} metal r = {r}"), &b, 20 + 10 * k as u64);
        }
    }
}

#[test]
fn dielectric_sampling_matches_pdf() {
    for model in BrdfModel::ALL {
        for (k, &r) in [0.3f32, 0.6, 1.0].iter().enumerate() {
            let b = MetallicRoughnessBsdf::new(Vec3::new(0.2, 0.5, 0.8), 0.0, r).with_model(model);
            assert_sampling_ok(
                &format!("{model} dielectric r = {r}"),
                &b,
                60 + 10 * k as u64,
            );
        }
    }
}

#[test]
fn mixed_and_smooth_sampling_matches_pdf() {
    for model in BrdfModel::ALL {
        // Half metal: both lobes with comparable probabilities.
        let b = MetallicRoughnessBsdf::new(Vec3::new(0.9, 0.9, 0.2), 0.5, 0.45).with_model(model);
        assert_sampling_ok(&format!("{model} half metal r = 0.45"), &b, 100);
        // Smooth dielectric: a delta specular lobe plus a sampled diffuse lobe; the pdf must
        // integrate to the diffuse lobe's probability only.
        let b = MetallicRoughnessBsdf::new(Vec3::new(0.6, 0.6, 0.6), 0.0, 0.0).with_model(model);
        assert_sampling_ok(&format!("{model} smooth dielectric"), &b, 110);
    }
}

/// KHR_materials_anisotropy: the anisotropic visible-normal sampler (plain for `spec`,
/// folded and mixed with cosine draws for `compensated`) draws the density `pdf` returns
/// (chi-square), for metal and dielectric at two roughnesses and two strengths; `wo`'s
/// azimuths (0.3, 2, 4 rad) are off the distribution's axes.
#[test]
fn anisotropic_sampling_matches_pdf() {
    for model in BrdfModel::ALL {
        for (k, &(r, s)) in [(0.3f32, 0.5f32), (0.3, 1.0), (0.6, 1.0)]
            .iter()
            .enumerate()
        {
            for m in [1.0, 0.0] {
                let b = MetallicRoughnessBsdf::new(Vec3::new(0.95, 0.64, 0.54), m, r)
                    .with_anisotropy(r, s)
                    .with_model(model);
                assert!(b.distribution.alpha_x > b.distribution.alpha_y);
                assert_sampling_ok(
                    &format!("{model} metallic {m} r = {r} anisotropy {s}"),
                    &b,
                    700 + 10 * k as u64 + m as u64,
                );
            }
        }
    }
}

/// The compensated anisotropic lobes conserve energy through their own albedo table: white
/// metal and white dielectric reflect 1 at every angle and azimuth (5σ of 10⁵ samples plus
/// 10⁻² for the coarser anisotropic table, whose error between nodes
/// `bsdf::anisotropic_albedo`'s test bounds). Uncompensated, the white metal at strength 1
/// keeps about half.
#[test]
fn compensated_anisotropic_white_surfaces_reflect_one() {
    let mut worst = 0.0f32;
    for (i, &(r, s)) in [
        (0.3f32, 0.5f32),
        (0.3, 1.0),
        (0.6, 0.5),
        (0.6, 1.0),
        (0.0, 1.0),
    ]
    .iter()
    .enumerate()
    {
        for (j, &(c, phi)) in [
            (1.0f64, 0.0f64),
            (0.8, 0.4),
            (0.5, 1.2),
            (0.2, 1.57),
            (0.2, 0.1),
        ]
        .iter()
        .enumerate()
        {
            let wo = dir(c, phi);
            for m in [1.0, 0.0] {
                let b = MetallicRoughnessBsdf::new(Vec3::ONE, m, r)
                    .with_anisotropy(r, s)
                    .with_model(BrdfModel::Compensated);
                let (a, se) = albedo_sampled(&b, wo, 100_000, 9000 + 10 * i as u64 + j as u64);
                worst = worst.max((a - Vec3::ONE).abs().max_element());
                assert!(
                    (a - Vec3::ONE)
                        .abs()
                        .cmple(5.0 * se + Vec3::splat(1e-2))
                        .all(),
                    "white, metallic {m}, r = {r}, anisotropy {s}, cos θo = {c}, φ = {phi}: \
                     albedo {a} ± {se}, want 1"
                );
            }
        }
    }
    eprintln!("largest deviation of a white anisotropic albedo from 1: {worst}");
    let spec = MetallicRoughnessBsdf::new(Vec3::ONE, 1.0, 0.3).with_anisotropy(0.3, 1.0);
    let (a, _) = albedo_sampled(&spec, dir(1.0, 0.0), 50_000, 5);
    assert!(
        a.x < 0.6,
        "spec white anisotropic metal at normal incidence: {a}"
    );
}

/// The albedo `∫ f cos dwi` (delta lobes included) as the mean of `sample`'s weights:
/// (mean, standard error) per channel.
fn albedo_sampled(bsdf: &impl Bsdf, wo: Vec3, n: usize, seed: u64) -> (Vec3, Vec3) {
    let mut r = rng(seed);
    let (mut s, mut s2) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
    for _ in 0..n {
        let u = Vec2::new(r.random(), r.random());
        if let Some(x) = bsdf.sample(wo, r.random(), u) {
            let v = x.weight.as_dvec3();
            s += v;
            s2 += v * v;
        }
    }
    let nf = n as f64;
    let mean = s / nf;
    let se = ((s2 / nf - mean * mean).max(glam::DVec3::ZERO) / nf).map(f64::sqrt);
    (mean.as_vec3(), se.as_vec3())
}

/// The compensated model conserves energy: white metal and white dielectric reflect exactly 1
/// at every angle and roughness (within 5σ of 2·10⁵ samples plus 2·10⁻³ for the tables,
/// whose QMC and interpolation error `bsdf::energy`'s test bounds by 10⁻³), where the spec's
/// white metal at roughness 1 keeps 0.31-0.95 of the light; a coloured metal stays below 1;
/// with `specular = 0` the compensated dielectric is exactly Lambert's `ρ/π`.
#[test]
fn compensated_white_surfaces_reflect_one() {
    for (i, &r) in [0.05f32, 0.2, 0.5, 0.8, 1.0].iter().enumerate() {
        for (j, &c) in [1.0f64, 0.8, 0.5, 0.2, 0.05].iter().enumerate() {
            let wo = dir(c, 0.7);
            let seed = 3000 + 10 * i as u64 + j as u64;
            for m in [1.0, 0.0, 0.4] {
                let b =
                    MetallicRoughnessBsdf::new(Vec3::ONE, m, r).with_model(BrdfModel::Compensated);
                let (a, se) = albedo_sampled(&b, wo, 200_000, seed);
                assert!(
                    (a - Vec3::ONE)
                        .abs()
                        .cmple(5.0 * se + Vec3::splat(2e-3))
                        .all(),
                    "white, metallic {m}, r = {r}, cos θo = {c}: albedo {a} ± {se}, want 1"
                );
            }
            let gold = MetallicRoughnessBsdf::new(Vec3::new(1.0, 0.78, 0.34), 1.0, r)
                .with_model(BrdfModel::Compensated);
            let (a, se) = albedo_sampled(&gold, wo, 50_000, seed + 7);
            assert!(
                a.cmple(Vec3::ONE + 5.0 * se + Vec3::splat(2e-3)).all(),
                "gold r = {r}, cos θo = {c}: albedo {a} ± {se} above 1"
            );
            // Specular 0 leaves the whole of the light to the base: exactly ρ/π.
            let lambert = MetallicRoughnessBsdf::new(Vec3::new(0.8, 0.5, 0.2), 0.0, r)
                .with_dielectric_fresnel(1.5, 0.0, Vec3::ONE)
                .with_model(BrdfModel::Compensated);
            let wi = dir(0.3 + 0.1 * j as f64, 2.0);
            let f = lambert.eval(wo, wi) * std::f32::consts::PI;
            assert!(
                (f - Vec3::new(0.8, 0.5, 0.2)).abs().max_element() < 1e-6,
                "specular 0, r = {r}: π f = {f}"
            );
        }
    }
    // The spec's model really loses light (the option is not the same BRDF).
    let spec = MetallicRoughnessBsdf::new(Vec3::ONE, 1.0, 1.0);
    let (a, _) = albedo_sampled(&spec, dir(1.0, 0.0), 50_000, 5);
    assert!(
        a.x < 0.35,
        "spec white metal at normal incidence, r = 1: {a}"
    );
}

/// The compensated dielectric is albedo scaling: what its specular lobe does not reflect
/// towards `wo` goes to the diffuse base, so a base of colour ρ reflects
/// `E_d(μo) + ρ (1 − E_d(μo))`, with `E_d(μo)` the albedo of the same material over a black
/// base (both sampled: 5σ plus 2·10⁻³ for the tables). The base's weight depends on `μo` only,
/// as OpenPBR's and Cycles' do, so this model is not reciprocal.
#[test]
fn compensated_dielectric_base_gets_what_the_specular_lobe_leaves() {
    let rho = Vec3::new(0.7, 0.4, 0.9);
    for (i, &r) in [0.0f32, 0.3, 0.7, 1.0].iter().enumerate() {
        for (j, &c) in [1.0f64, 0.5, 0.15].iter().enumerate() {
            let wo = dir(c, 0.4);
            let with = |base: Vec3| {
                MetallicRoughnessBsdf::new(base, 0.0, r)
                    .with_dielectric_fresnel(1.6, 0.8, Vec3::new(1.0, 0.8, 1.2))
                    .with_model(BrdfModel::Compensated)
            };
            let seed = 3500 + 10 * i as u64 + j as u64;
            let (e, se_e) = albedo_sampled(&with(Vec3::ZERO), wo, 100_000, seed);
            let (a, se_a) = albedo_sampled(&with(rho), wo, 100_000, seed + 100);
            let want = e + rho * (Vec3::ONE - e);
            assert!(
                (a - want)
                    .abs()
                    .cmple(5.0 * (se_a + se_e) + Vec3::splat(2e-3))
                    .all(),
                "r = {r}, cos θo = {c}: albedo {a} ± {se_a}, want {want} (E_d = {e} ± {se_e})"
            );
        }
    }
}

/// A coloured rough metal reflects its single-scatter albedo `E_F(μo)` times
/// `1 + F_ms (1/E0(μo) − 1)`, with Kulla & Conty's `F_ms = F_avg A0/(1 − F_avg(1 − A0))` from
/// the cosine-averaged Fresnel `F_avg = f0 + (1 − f0)/21`: sampled albedo against that closed
/// form of the tables (5σ plus 2·10⁻³), and below Turquin's `F_ms = f0` by more than the noise
/// where the two differ (the test fails on the old factor).
#[test]
fn coloured_metal_gets_the_fresnel_weighted_multiple_scattering() {
    use glint::bsdf::energy::{
        ggx_albedo, ggx_albedo_average, multiple_scattering_factor, multiple_scattering_fresnel,
        schlick_albedo, schlick_fresnel_average,
    };
    let f0 = Vec3::new(0.95, 0.6, 0.25);
    for (i, &r) in [0.5f32, 0.8, 1.0].iter().enumerate() {
        let alpha = r * r;
        for (j, &c) in [1.0f64, 0.5, 0.2].iter().enumerate() {
            let wo = dir(c, 1.1);
            let metal = MetallicRoughnessBsdf::new(f0, 1.0, r).with_model(BrdfModel::Compensated);
            let (a, se) = albedo_sampled(&metal, wo, 200_000, 3700 + 10 * i as u64 + j as u64);
            let e = ggx_albedo(wo.z, alpha);
            let single = schlick_albedo(e, f0, Vec3::ONE);
            let f_ms = multiple_scattering_fresnel(
                schlick_fresnel_average(f0, Vec3::ONE),
                ggx_albedo_average(alpha).a0,
            );
            let want = single * multiple_scattering_factor(e, f_ms);
            let turquin = single * multiple_scattering_factor(e, f0);
            assert!(
                (a - want).abs().cmple(5.0 * se + Vec3::splat(2e-3)).all(),
                "r = {r}, cos θo = {c}: albedo {a} ± {se}, want {want} (Turquin's {turquin})"
            );
            if r == 1.0 {
                assert!(
                    (turquin - a).min_element() > 5.0 * se.max_element(),
                    "r = {r}, cos θo = {c}: {a} not below Turquin's {turquin}"
                );
            }
        }
    }
}

/// The energy bound: ∫ f cos dwi ≤ 1 for white metals at many angles and roughnesses (single
/// scattering only loses light); equality for a dielectric with `specular = 0` (pure
/// Lambert). The glTF dielectric mix is not conserving (the spec says so): its diffuse is
/// weighted by `1 − F(wo·h)`, near 1 for most `wi`, while the specular lobe reflects
/// `F(n·wo)`, so a white dielectric at grazing angles reflects up to ~1.3 (measured 1.299 at
/// roughness 0.05, cos θo = 0.2; 1.709 at cos θo = 0.05). The test bounds it by the sum of its lobes' maxima,
/// `(1 − f0) + F(n·wo)`, and prints the largest albedo it saw.
#[test]
fn metallic_roughness_energy() {
    let mut worst_dielectric = 0.0f32;
    for (i, &r) in [0.05f32, 0.2, 0.5, 0.8, 1.0].iter().enumerate() {
        for (j, &c) in [1.0f64, 0.8, 0.5, 0.2, 0.05].iter().enumerate() {
            let wo = dir(c, 0.7);
            let seed = 1000 + 10 * i as u64 + j as u64;
            let metal = MetallicRoughnessBsdf::new(Vec3::ONE, 1.0, r);
            let rep = check_sampling(&metal, wo, 50_000, seed);
            assert!(
                rep.albedo.max_element() <= 1.0 + 5.0 * rep.albedo_se.max_element() + 1e-4,
                "white metal r = {r}, cos θo = {c}: albedo {} ± {}",
                rep.albedo,
                rep.albedo_se
            );
            let diel = MetallicRoughnessBsdf::new(Vec3::ONE, 0.0, r);
            let rep = check_sampling(&diel, wo, 50_000, seed + 500);
            worst_dielectric = worst_dielectric.max(rep.albedo.max_element());
            let bound = 0.96 + 0.04 + 0.96 * (1.0 - c as f32).powi(5);
            assert!(
                rep.albedo.max_element() <= bound + 5.0 * rep.albedo_se.max_element(),
                "white dielectric r = {r}, cos θo = {c}: albedo {} ± {} > {bound}",
                rep.albedo,
                rep.albedo_se
            );
            let lambert = diel.with_dielectric_fresnel(1.5, 0.0, Vec3::ONE);
            let (a, se) = albedo_uniform(&lambert, wo, 50_000, seed + 900);
            assert!(
                (a - Vec3::ONE)
                    .abs()
                    .cmple(5.0 * se + Vec3::splat(1e-4))
                    .all(),
                "specular 0, r = {r}, cos θo = {c}: albedo {a} ± {se}, want 1"
            );
        }
    }
    eprintln!("largest white-dielectric albedo: {worst_dielectric}");
}

/// The smooth end is a Schlick-Fresnel mirror, and rough metal tends to it as roughness → 0.
#[test]
fn roughness_zero_is_the_limit_of_rough_metal() {
    let base = Vec3::new(0.9, 0.6, 0.3);
    for &c in &[0.9f64, 0.5, 0.2] {
        let wo = dir(c, 1.0);
        let smooth = MetallicRoughnessBsdf::new(base, 1.0, 0.0);
        let s = smooth
            .sample(wo, 0.5, Vec2::splat(0.5))
            .expect("delta sample");
        let w = (1.0 - c as f32).powi(5);
        let fresnel = base + (Vec3::ONE - base) * w;
        assert!(s.delta && (s.weight - fresnel).abs().max_element() < 1e-5);
        let rough = MetallicRoughnessBsdf::new(base, 1.0, 0.05);
        let rep = check_sampling(&rough, wo, 50_000, 77);
        // α = 0.0025: masking costs well under 1% of the light at these angles.
        assert!(
            (rep.albedo - fresnel).abs().max_element() < 0.01,
            "cos θo = {c}: rough albedo {} vs smooth {fresnel}",
            rep.albedo
        );
    }
}
mod diffuse_transmission;
mod layers;
