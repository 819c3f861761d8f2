//! KHR_materials_diffuse_transmission's lobe pair (`bsdf::metallic_roughness`): the diffuse
//! base `mix(diffuse_brdf(baseColor), diffuse_btdf(C_t), t)` under the dielectric's Fresnel
//! weight. Chi-square of `sample` against `pdf` over the whole sphere, the pdf's integral,
//! sampling against evaluation, the closed form of the transmitted lobe, its reciprocity,
//! and energy: the pair sends on exactly what the reflection-only base reflected (white and
//! compensated: 1).

use super::harness::{dir, rng};
use super::layers::{albedo_sphere, assert_sampling_ok};
use glam::{DVec3, Vec3};
use glint::bsdf::{BrdfModel, Bsdf, BsdfFlags, LayeredBsdf, MetallicRoughnessBsdf, SheenBsdf};
use rand::Rng;
use std::f64::consts::PI;

const BASE: Vec3 = Vec3::new(0.2, 0.6, 0.3);
const COLOR: Vec3 = Vec3::new(0.9, 0.5, 0.2);

fn leaf(metallic: f32, roughness: f32, t: f32, model: BrdfModel) -> MetallicRoughnessBsdf {
    MetallicRoughnessBsdf::new(BASE, metallic, roughness)
        .with_model(model)
        .with_diffuse_transmission(t, COLOR)
}

/// `sample` draws what `pdf` says over the whole sphere (chi-square, p > 10⁻⁴), the pdf
/// integrates to the share of non-delta draws, and the mean sample weight equals uniform
/// sphere integration of `eval` (5σ): for both models, rough and smooth (a delta specular
/// lobe beside the diffuse pair), strengths 0.3 and 1, part metal, and under a sheen.
#[test]
fn diffuse_transmission_sampling_matches_pdf() {
    for model in BrdfModel::ALL {
        for (k, &(m, r, t)) in [
            (0.0f32, 0.5f32, 0.3f32),
            (0.0, 0.5, 1.0),
            (0.4, 0.3, 0.6),
            (0.0, 0.0, 0.5),
        ]
        .iter()
        .enumerate()
        {
            let b = leaf(m, r, t, model);
            assert!(b.flags().transmits() && b.flags().contains(BsdfFlags::DIFFUSE));
            assert_sampling_ok(
                &format!("{model} diffuse transmission {t}, metallic {m}, r = {r}"),
                &b,
                5000 + 10 * k as u64,
            );
        }
        let sheened = LayeredBsdf::new(
            leaf(0.0, 0.4, 0.7, model),
            None,
            Some(SheenBsdf::new(Vec3::new(0.8, 0.8, 0.5), 0.5)),
            None,
        );
        assert_sampling_ok(
            &format!("{model} diffuse transmission under sheen"),
            &sheened,
            5100,
        );
    }
}

/// The transmitted lobe written out again in f64 from the extension:
/// `(1 − m) (1 − max F(wo·h)) t C_t / π` with `F = f0 + (1 − f0)(1 − |wo·h|)⁵`, `f0 = 0.04`,
/// and `h` the half vector of `wo` and `wi` mirrored to `wo`'s side (Appendix B's
/// `fresnel_mix` at the mirrored light); `eval` matches it to 10⁻⁵ relative, and gives 0
/// for the transmitted directions of a surface without the extension.
#[test]
fn the_transmitted_lobe_is_the_extensions_btdf() {
    let mut checked = 0;
    for &(m, t) in &[(0.0f64, 1.0f64), (0.3, 0.4)] {
        let b = MetallicRoughnessBsdf::new(BASE, m as f32, 0.5)
            .with_diffuse_transmission(t as f32, COLOR);
        for &(co, po) in &[(0.95, 0.2), (0.5, 1.0), (0.1, 3.0)] {
            for &(ci, pi) in &[(-0.9, 2.0), (-0.4, 0.5), (-0.05, 4.0)] {
                let (wo, wi) = (dir(co, po), dir(ci, pi));
                let (v, l) = (wo.as_dvec3(), wi.as_dvec3());
                let h = (v + DVec3::new(l.x, l.y, -l.z)).normalize();
                let w = (1.0 - v.dot(h).abs()).powi(5);
                let f = 0.04 + 0.96 * w;
                let got = b.eval(wo, wi);
                for k in 0..3 {
                    let want = (1.0 - m) * (1.0 - f) * t * COLOR[k] as f64 / PI;
                    let rel = (got[k] as f64 - want).abs() / want;
                    assert!(
                        rel < 1e-5,
                        "m {m}, t {t}, wo {wo}, wi {wi}: {got} vs {want}"
                    );
                }
                assert_eq!(
                    MetallicRoughnessBsdf::new(BASE, m as f32, 0.5).eval(wo, wi),
                    Vec3::ZERO
                );
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 18);
    // Compensated with KHR_materials_specular 0: the Fresnel weight is exactly 1.
    let lambert = MetallicRoughnessBsdf::new(BASE, 0.0, 0.5)
        .with_dielectric_fresnel(1.5, 0.0, Vec3::ONE)
        .with_model(BrdfModel::Compensated)
        .with_diffuse_transmission(0.25, COLOR);
    let f = lambert.eval(dir(0.7, 1.0), dir(-0.3, 2.0)) * std::f32::consts::PI;
    assert!((f - 0.25 * COLOR).abs().max_element() < 1e-6, "{f}");
    let r = lambert.eval(dir(0.7, 1.0), dir(0.3, 2.0)) * std::f32::consts::PI;
    assert!((r - 0.75 * BASE).abs().max_element() < 1e-6, "{r}");
}

/// The spec model's transmitted lobe is reciprocal: `f(wo, wi) = f(−wi, −wo)` (the path
/// reversed, seen from the other side) to 10⁻⁴ over random pairs (f32 rounding near grazing
/// reaches 1.4·10⁻⁵; the reflection's reciprocity test allows the same).
#[test]
fn the_transmitted_lobe_is_reciprocal() {
    let b = leaf(0.2, 0.6, 0.8, BrdfModel::Spec);
    let mut r = rng(41);
    for _ in 0..20_000 {
        let wo = dir(
            r.random_range(0.01..1.0),
            r.random_range(0.0..std::f64::consts::TAU),
        );
        let wi = dir(
            -r.random_range(0.01..1.0),
            r.random_range(0.0..std::f64::consts::TAU),
        );
        let (a, c) = (b.eval(wo, wi), b.eval(-wi, -wo));
        assert!(
            (a - c).abs().max_element() <= 1e-4 * a.max_element(),
            "wo {wo}, wi {wi}: {a} vs {c}"
        );
    }
}

/// Energy: the pair moves light from the diffuse reflection to the transmission and creates
/// none. With a white base and a white `C_t`, the albedo over the whole sphere equals the
/// reflection-only material's at every strength (both models; uniform sphere integration of
/// `eval`, 5σ + 2·10⁻³); for the compensated model that is 1 (the white furnace of the lobe
/// pair). At strength 1 nothing diffuse is reflected: the upper hemisphere keeps only the
/// specular lobe's albedo.
#[test]
fn the_lobe_pair_sends_on_what_the_diffuse_reflection_gave_up() {
    for model in BrdfModel::ALL {
        for (j, &c) in [1.0f64, 0.6, 0.2].iter().enumerate() {
            let wo = dir(c, 0.9);
            for (i, &r) in [0.2f32, 0.6, 1.0].iter().enumerate() {
                let seed = 5200 + 10 * i as u64 + j as u64;
                let plain = MetallicRoughnessBsdf::new(Vec3::ONE, 0.0, r).with_model(model);
                let (a0, se0) = albedo_sphere(&plain, wo, 1.0, 200_000, seed);
                for t in [0.5f32, 1.0] {
                    let b = plain.with_diffuse_transmission(t, Vec3::ONE);
                    let (a, se) = albedo_sphere(&b, wo, 1.0, 200_000, seed + 100);
                    let tol = 5.0 * (se * se + se0 * se0).map(f32::sqrt) + Vec3::splat(2e-3);
                    assert!(
                        (a - a0).abs().cmple(tol).all(),
                        "{model}, r = {r}, cos θo = {c}, t = {t}: {a} ± {se} vs {a0} ± {se0}"
                    );
                    if model == BrdfModel::Compensated {
                        assert!(
                            (a - Vec3::ONE)
                                .abs()
                                .cmple(5.0 * se + Vec3::splat(2e-3))
                                .all(),
                            "compensated white, r = {r}, cos θo = {c}, t = {t}: {a} ± {se}"
                        );
                    }
                }
            }
        }
    }
}

/// Strength 0 is the material without the extension, bit for bit.
#[test]
fn strength_zero_changes_nothing() {
    for model in BrdfModel::ALL {
        let b = MetallicRoughnessBsdf::new(BASE, 0.3, 0.4).with_model(model);
        assert_eq!(b.with_diffuse_transmission(0.0, COLOR), b);
        assert_eq!(b.with_diffuse_transmission(f32::NAN, COLOR), b);
        assert!(!b.flags().transmits());
    }
}
