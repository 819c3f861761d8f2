//! KHR_materials_diffuse_transmission in a render (issue 35): a leaf lit from behind glows.
//!
//! A thin sheet (a single-sided quad facing the camera, `z = 0`, front +Z) with diffuse
//! transmission `t` and colour `C_t`, seen head-on by an orthographic camera, lit only from
//! behind:
//! - by a directional light of irradiance `E` at angle θ: every pixel shows
//!   `L = (1 − F) t C_t E cos θ / π`, with `F = 0` under KHR_materials_specular 0 (both
//!   models) and, for the spec model at the default specular, `F = max F(wo·h)` at the half
//!   vector of the view and the mirrored light. Light samples only (a delta light), both
//!   integrators, every backend: within 10⁻³. Lit from the front instead, the same sheet
//!   reflects `(1 − t) ρ E cos θ / π`.
//! - by a parallel emitting rectangle of radiance `Le` behind it: `L(p) = t C_t Le F(p)`
//!   with `F(p)` the closed-form form factor of the rectangle seen from `p`. Light samples
//!   and BSDF samples through the sheet meet under MIS (the path tracer): the mean over the
//!   pixels of rendered/expected is 1 within 4σ (σ: the pixels' spread) and within 1 %.
//!
//! - through a slab (a wide box of thickness `d`, every face transmitting all of its diffuse
//!   base, `t` = 1, white, no specular) lit from behind by the directional light: light
//!   crosses two faces, and inside a KHR_materials_volume it is attenuated over the
//!   cosine-distributed path lengths `d/μ`: `L = E cos θ/π · 2 ∫₀¹ μ exp(−σ d/μ) dμ` (1 when
//!   thin-walled, without the volume): 4σ and 1 %.
//!
//! Strength 0 renders today's pixels bit for bit.

use crate::support::{
    centre_settings, emitter, image_bits, lambert, ortho, quad, render_with, scene,
};
use glam::{DVec3, Vec3};
use glint::accel::BackendKind;
use glint::render::{BrdfModel, Integrator, RenderSettings};
use glint::scene::layers::{DiffuseTransmission, Volume};
use glint::scene::{Camera, Light, Material, Scene};

const SIZE: u32 = 16;
/// Half the orthographic view (the sheet's half-size is 2: it fills the view).
const VIEW: f32 = 0.3;
const RHO: Vec3 = Vec3::new(0.3, 0.6, 0.2);
const COLOR: Vec3 = Vec3::new(1.0, 0.8, 0.5);

fn leaf(t: f32, specular: f32) -> Material {
    Material {
        name: "leaf".into(),
        roughness: 0.5,
        specular,
        diffuse_transmission: Some(DiffuseTransmission {
            factor: t,
            texture: None,
            color: COLOR,
            color_texture: None,
        }),
        ..lambert(RHO, false)
    }
}

fn camera() -> Camera {
    ortho(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, VIEW, VIEW)
}

fn sheet() -> glint::scene::Mesh {
    quad(Vec3::ZERO, Vec3::X * 2.0, Vec3::Y * 2.0, 0)
}

/// The mean pixel of `scene` and the largest relative deviation of any pixel from it.
fn render(scene: &Scene, backend: BackendKind, settings: &RenderSettings) -> (Vec3, f32) {
    let out = render_with(scene, &camera(), backend, settings);
    let n = out.image.pixels.len() as f32;
    let mean = out.image.pixels.iter().copied().sum::<Vec3>() / n;
    let spread = out
        .image
        .pixels
        .iter()
        .map(|p| ((*p - mean).abs() / mean.max(Vec3::splat(1e-12))).max_element())
        .fold(0.0f32, f32::max);
    (mean, spread)
}

/// A directional light travelling at `theta` from +Z (through the sheet from behind when
/// `behind`, onto its front otherwise), irradiance `e`.
fn directional(theta: f64, behind: bool, e: f32) -> Light {
    let z = if behind { theta.cos() } else { -theta.cos() };
    Light::Directional {
        direction: DVec3::new(theta.sin(), 0.0, z).as_vec3(),
        irradiance: Vec3::splat(e),
    }
}

#[test]
fn a_sheet_lit_from_behind_by_the_sun_glows_by_the_closed_form() {
    let (theta, e) = (0.7f64, 3.0f32);
    let cos = theta.cos();
    let wo = DVec3::Z;
    let mirrored_light = DVec3::new(-theta.sin(), 0.0, cos);
    let h = (wo + mirrored_light).normalize();
    let fresnel = 0.04 + 0.96 * (1.0 - wo.dot(h)).powi(5);
    let mut failures = Vec::new();
    for &backend in BackendKind::available() {
        for integrator in [Integrator::Path, Integrator::Direct] {
            for (model, specular, f) in [
                (BrdfModel::Compensated, 0.0, 0.0),
                (BrdfModel::Spec, 0.0, 0.0),
                (BrdfModel::Spec, 1.0, fresnel),
            ] {
                for t in [1.0f32, 0.4] {
                    let settings = RenderSettings {
                        spp: 4,
                        integrator,
                        brdf: model,
                        ..centre_settings(SIZE, SIZE)
                    };
                    let back = scene(
                        vec![sheet()],
                        vec![leaf(t, specular)],
                        vec![directional(theta, true, e)],
                    );
                    let (got, spread) = render(&back, backend, &settings);
                    let want = COLOR.as_dvec3()
                        * ((1.0 - f) * t as f64 * e as f64 * cos / std::f64::consts::PI);
                    let what = format!(
                        "{backend}, {integrator:?}, {model}, specular {specular}, t = {t}, lit from behind"
                    );
                    eprintln!("{what}: {got} vs {want} (spread {spread:.1e})");
                    if !crate::support::close(got, want, 1e-3) || spread > 1e-3 {
                        failures.push(format!("{what}: {got} vs {want}"));
                    }
                    // Lit from the front: the diffuse reflection keeps 1 − t (specular 0).
                    if specular == 0.0 {
                        let front = scene(
                            vec![sheet()],
                            vec![leaf(t, 0.0)],
                            vec![directional(theta, false, e)],
                        );
                        let (got, _) = render(&front, backend, &settings);
                        let want = RHO.as_dvec3()
                            * ((1.0 - t as f64) * e as f64 * cos / std::f64::consts::PI);
                        if !crate::support::close(got, want, 1e-3) {
                            failures.push(format!("{what} → front: {got} vs {want}"));
                        }
                    }
                }
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The form factor from a point to the rectangle `[x0, x1] × [y0, y1]` (relative to the
/// point) in a parallel plane at distance `d`: the corner formula, odd in each side, summed
/// with signs.
fn form_factor(x0: f64, x1: f64, y0: f64, y1: f64, d: f64) -> f64 {
    let g = |a: f64, b: f64| {
        let (x, y) = (a / d, b / d);
        let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
        (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / std::f64::consts::TAU
    };
    g(x1, y1) - g(x0, y1) - g(x1, y0) + g(x0, y0)
}

#[test]
fn a_sheet_before_an_area_light_glows_by_the_form_factor() {
    let (t, le, d, half) = (0.7f32, 2.0f32, 0.6f64, 1.0f64);
    let lamp = quad(
        Vec3::new(0.0, 0.0, -d as f32),
        Vec3::X * half as f32,
        Vec3::Y * half as f32,
        1,
    );
    let mut failures = Vec::new();
    for &backend in BackendKind::available() {
        for model in BrdfModel::ALL {
            let s = scene(
                vec![sheet(), lamp.clone()],
                vec![leaf(t, 0.0), emitter(Vec3::splat(le))],
                vec![],
            );
            let settings = RenderSettings {
                spp: 256,
                integrator: Integrator::Path,
                max_depth: 4,
                brdf: model,
                ..centre_settings(SIZE, SIZE)
            };
            let camera = camera();
            let out = render_with(&s, &camera, backend, &settings);
            // The pixel centres' points on the sheet.
            let ratios: Vec<f64> = (0..SIZE * SIZE)
                .map(|i| {
                    let (x, y) = (i % SIZE, i / SIZE);
                    let px = (2.0 * (x as f64 + 0.5) / SIZE as f64 - 1.0) * VIEW as f64;
                    let py = (1.0 - 2.0 * (y as f64 + 0.5) / SIZE as f64) * VIEW as f64;
                    let f = form_factor(-half - px, half - px, -half - py, half - py, d);
                    let want = COLOR.as_dvec3() * (t as f64 * le as f64 * f);
                    let got = out.image.pixels[i as usize].as_dvec3();
                    (got / want).element_sum() / 3.0
                })
                .collect();
            let n = ratios.len() as f64;
            let mean = ratios.iter().sum::<f64>() / n;
            let var = ratios.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (n - 1.0);
            let sigma = (var / n).sqrt();
            let what = format!("{backend}, {model}");
            eprintln!("{what}: rendered/closed form {mean:.5} ± {sigma:.5}");
            if (mean - 1.0).abs() > 4.0 * sigma || (mean - 1.0).abs() > 0.01 || sigma > 2.5e-3 {
                failures.push(format!("{what}: {mean} ± {sigma}"));
            }
        }
    }
    assert!(failures.is_empty(), "not 1 within 4σ and 1 %: {failures:?}");
}

/// Strength 0 is the material without the extension: the same pixels, bit for bit, on a
/// scene with an area light, a floor and bounces (both models).
#[test]
fn strength_zero_renders_todays_pixels() {
    for &backend in BackendKind::available() {
        for model in BrdfModel::ALL {
            let lamp = quad(Vec3::new(1.2, 0.0, 1.0), Vec3::X * 0.5, -Vec3::Y * 0.5, 1);
            let floor = |material: Material| {
                scene(
                    vec![sheet(), lamp.clone()],
                    vec![material, emitter(Vec3::splat(3.0))],
                    vec![directional(2.5, true, 1.0)],
                )
            };
            let plain = Material {
                diffuse_transmission: None,
                ..leaf(0.0, 1.0)
            };
            let settings = RenderSettings {
                spp: 8,
                integrator: Integrator::Path,
                brdf: model,
                ..RenderSettings::default()
            };
            let settings = RenderSettings {
                width: SIZE,
                height: SIZE,
                ..settings
            };
            let a = render_with(&floor(plain), &camera(), backend, &settings);
            let b = render_with(&floor(leaf(0.0, 1.0)), &camera(), backend, &settings);
            assert!(a.image.pixels.iter().any(|p| p.max_element() > 0.0));
            assert_eq!(image_bits(&a), image_bits(&b), "{backend}, {model}");
        }
    }
}

/// The slab's transmitted radiance over `E cos θ / π`: `2 ∫₀¹ μ exp(−τ/μ) dμ` for optical
/// depth `τ` (midpoint rule, 10⁶ steps).
fn slab_transmittance(tau: f64) -> f64 {
    let n = 1_000_000;
    let h = 1.0 / n as f64;
    (0..n)
        .map(|i| {
            let mu = (i as f64 + 0.5) * h;
            mu * (-tau / mu).exp()
        })
        .sum::<f64>()
        * 2.0
        * h
}

#[test]
fn a_slab_lit_from_behind_transmits_through_its_volume() {
    let (theta, e, d, w) = (0.5f64, 2.0f32, 0.1f32, 50.0f32);
    let attenuation = Vec3::new(0.5, 0.7, 0.9);
    let (hd, z) = (d / 2.0, Vec3::Z);
    let slab = vec![
        quad(Vec3::ZERO, Vec3::X * w, Vec3::Y * w, 0),
        quad(-z * d, Vec3::X * w, -Vec3::Y * w, 0),
        quad(Vec3::new(w, 0.0, -hd), Vec3::Y * w, z * hd, 0),
        quad(Vec3::new(-w, 0.0, -hd), z * hd, Vec3::Y * w, 0),
        quad(Vec3::new(0.0, w, -hd), z * hd, Vec3::X * w, 0),
        quad(Vec3::new(0.0, -w, -hd), Vec3::X * w, z * hd, 0),
    ];
    let mut failures = Vec::new();
    for &backend in BackendKind::available() {
        for volume in [true, false] {
            let material = Material {
                name: "wax".into(),
                diffuse_transmission: Some(DiffuseTransmission {
                    factor: 1.0,
                    texture: None,
                    color: Vec3::ONE,
                    color_texture: None,
                }),
                volume: volume.then_some(Volume {
                    thickness: d,
                    attenuation_color: attenuation,
                    attenuation_distance: d,
                }),
                ..lambert(Vec3::ONE, false)
            };
            let s = scene(
                slab.clone(),
                vec![material],
                vec![directional(theta, true, e)],
            );
            let settings = RenderSettings {
                width: 8,
                height: 8,
                spp: 512,
                integrator: Integrator::Path,
                max_depth: 8,
                ..centre_settings(8, 8)
            };
            let out = render_with(&s, &camera(), backend, &settings);
            let what = format!("{backend}, volume {volume}");
            for k in 0..3 {
                // σ d = −ln(attenuationColor) with the attenuation distance d.
                let tau = if volume {
                    -(attenuation[k] as f64).ln()
                } else {
                    0.0
                };
                let want = e as f64 * theta.cos() / std::f64::consts::PI * slab_transmittance(tau);
                let values: Vec<f64> = out.image.pixels.iter().map(|p| p[k] as f64).collect();
                let n = values.len() as f64;
                let mean = values.iter().sum::<f64>() / n;
                let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
                let sigma = (var / n).sqrt();
                eprintln!("{what}, channel {k}: {mean:.5} ± {sigma:.5} vs {want:.5}");
                let err = (mean - want).abs();
                if err > 4.0 * sigma.max(1e-6 * want) || err > 0.01 * want {
                    failures.push(format!("{what}, channel {k}: {mean} ± {sigma} vs {want}"));
                }
            }
        }
    }
    assert!(failures.is_empty(), "not within 4σ and 1 %: {failures:?}");
}
