//! The path tracer against closed forms of the rendering equation.
//!
//! Every test renders with fixed seeds, so it is deterministic; the tolerances are Monte Carlo
//! confidence bounds computed from the renders themselves. A pixel's estimate is the mean of K
//! renders with independent seeds; its standard error comes from their spread, and a pixel
//! passes when it lies within `Z` standard errors of the closed form (Student's t with K − 1
//! degrees of freedom: for K = 16, |t| > 5 has probability 1.6·10⁻⁴ per pixel). Each test also
//! asserts that the bound is tight (a few 10⁻³ relative at most), so a bias larger than that
//! cannot hide in the noise; image means, which average many pixels, are held to 10⁻³.

use crate::support;

use crate::support::{image_bits, look_at, ortho, quad, scene};
use glam::{Vec3, Vec4};
use glint::accel::{BackendKind, BuildOptions};
use glint::light::environment::EnvironmentLight;
use glint::render::{self, Integrator, LightStrategy, PixelSampling, RenderInputs, RenderSettings};
use glint::scene::{Camera, Material, Mesh, Scene};

/// Standard errors a pixel may lie from the closed form.
const Z: f64 = 5.0;

/// A Lambertian material of albedo ρ emitting `le`, shaded on both sides: glTF's dielectric
/// with KHR_materials_specular's factor 0, which leaves the diffuse lobe alone.
fn diffuse(rho: f32, le: f32) -> Material {
    Material {
        specular: 0.0,
        name: "diffuse".into(),
        base_color: Vec4::new(rho, rho, rho, 1.0),
        metallic: 0.0,
        roughness: 1.0,
        emissive: Vec3::splat(le),
        double_sided: true,
        ..Material::default()
    }
}

fn settings(size: u32, spp: u32, seed: u64) -> RenderSettings {
    RenderSettings {
        width: size,
        height: size,
        spp,
        seed,
        threads: 2,
        max_depth: 64,
        sampling: PixelSampling::Sobol,
        integrator: Integrator::Path,
        ..RenderSettings::default()
    }
}

/// Renders `scene` once per seed and returns per-pixel means and standard errors of the
/// luminance-free first channel.
fn estimate(
    scene: &Scene,
    camera: &Camera,
    env: Option<&EnvironmentLight>,
    backend: BackendKind,
    base: &RenderSettings,
    seeds: u64,
) -> (Vec<f64>, Vec<f64>) {
    let accel = render::prepare(scene, backend, BuildOptions::default()).expect("build");
    let mut inputs = RenderInputs::of_scene(scene, accel.as_ref(), camera);
    inputs.environment = env;
    let runs: Vec<Vec<f64>> = (0..seeds)
        .map(|seed| {
            let s = RenderSettings {
                seed: 1000 + seed,
                ..*base
            };
            let (film, _) = render::render_film(&inputs, &s, 0..s.spp, None).expect("render");
            let (image, _) = film.resolve();
            image.pixels.iter().map(|p| p.x as f64).collect()
        })
        .collect();
    let n = runs[0].len();
    let k = seeds as f64;
    let mut mean = vec![0.0; n];
    let mut se = vec![0.0; n];
    for i in 0..n {
        let m = runs.iter().map(|r| r[i]).sum::<f64>() / k;
        let var = runs.iter().map(|r| (r[i] - m).powi(2)).sum::<f64>() / (k - 1.0);
        mean[i] = m;
        se[i] = (var / k).sqrt();
    }
    (mean, se)
}

/// Asserts every pixel within `Z` standard errors of `want` with that bound below `max_rel`
/// relative, and the image mean within `Z` of its standard errors with that bound below
/// `image_rel` relative.
fn assert_matches(
    what: &str,
    (mean, se): &(Vec<f64>, Vec<f64>),
    want: f64,
    max_rel: f64,
    image_rel: f64,
) {
    for (i, (&m, &e)) in mean.iter().zip(se).enumerate() {
        assert!(
            (m - want).abs() <= Z * e + 1e-6 * want,
            "{what}: pixel {i} = {m} ± {e}, want {want}"
        );
        assert!(
            Z * e <= max_rel * want,
            "{what}: pixel {i}'s bound {} is too loose to test anything",
            Z * e
        );
    }
    let n = mean.len() as f64;
    let image_mean = mean.iter().sum::<f64>() / n;
    let image_se = (se.iter().map(|e| e * e).sum::<f64>()).sqrt() / n;
    assert!(
        (image_mean - want).abs() <= Z * image_se + 1e-6 * want,
        "{what}: image mean {image_mean} ± {image_se}, want {want}"
    );
    assert!(
        Z * image_se <= image_rel * want,
        "{what}: the image mean's bound {} is too loose",
        Z * image_se
    );
}

/// An open box of albedo 1 (floor and four walls, no lid), seen from above.
fn open_box(material: usize) -> Vec<Mesh> {
    vec![
        quad(Vec3::ZERO, Vec3::X, Vec3::Z, material),
        quad(Vec3::new(-1.0, 1.0, 0.0), Vec3::Z, Vec3::Y, material),
        quad(Vec3::new(1.0, 1.0, 0.0), Vec3::Y, Vec3::Z, material),
        quad(Vec3::new(0.0, 1.0, -1.0), Vec3::Y, Vec3::X, material),
        quad(Vec3::new(0.0, 1.0, 1.0), Vec3::X, Vec3::Y, material),
    ]
}

/// A closed cube of half-size 1 around the origin.
fn closed_cube(material: usize) -> Vec<Mesh> {
    let mut meshes = open_box(material);
    meshes.iter_mut().for_each(|m| {
        m.positions.iter_mut().for_each(|p| p.y -= 1.0);
    });
    meshes.push(quad(Vec3::Y, Vec3::Z, Vec3::X, material));
    meshes
}

/// White furnace: a non-convex open box of albedo 1 under a uniform environment L reflects
/// exactly L everywhere (energy is conserved and nothing absorbs).
#[test]
fn white_furnace_open_box_is_uniform() {
    let l = 1.5;
    let scene = scene(open_box(0), vec![diffuse(1.0, 0.0)], vec![]);
    let camera = look_at(
        Vec3::new(0.3, 3.5, 0.6),
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::Z,
        0.9,
    );
    let env = EnvironmentLight::constant(Vec3::splat(l));
    for &backend in BackendKind::available() {
        let est = estimate(
            &scene,
            &camera,
            Some(&env),
            backend,
            &settings(8, 256, 0),
            16,
        );
        assert_matches(&format!("furnace ({backend})"), &est, l as f64, 5e-2, 5e-3);
    }
}

/// A Lambertian plane of albedo ρ under a uniform environment L has radiance ρ·L, with MIS,
/// light sampling alone, BSDF sampling alone, and the direct integrator.
#[test]
fn lambert_plane_under_uniform_environment_reflects_rho_l() {
    let (rho, l) = (0.6, 2.0);
    let scene = scene(
        vec![quad(Vec3::ZERO, Vec3::X * 50.0, -Vec3::Z * 50.0, 0)],
        vec![diffuse(rho, 0.0)],
        vec![],
    );
    let camera = look_at(Vec3::new(0.0, 2.0, 2.0), Vec3::ZERO, Vec3::Y, 0.5);
    let env = EnvironmentLight::constant(Vec3::splat(l));
    let want = (rho * l) as f64;
    for (strategy, integrator) in [
        (LightStrategy::Mis, Integrator::Path),
        (LightStrategy::LightOnly, Integrator::Path),
        (LightStrategy::BsdfOnly, Integrator::Path),
        (LightStrategy::Mis, Integrator::Direct),
    ] {
        let s = RenderSettings {
            light_strategy: strategy,
            integrator,
            ..settings(6, 64, 0)
        };
        let est = estimate(&scene, &camera, Some(&env), BackendKind::default(), &s, 16);
        assert_matches(
            &format!("{strategy:?} {integrator}"),
            &est,
            want,
            3e-2,
            5e-3,
        );
    }
}

/// Form factor from a differential area to a parallel rectangle of sides a × b at distance
/// h, the area's normal through one corner of the rectangle.
fn corner_form_factor(a: f64, b: f64, h: f64) -> f64 {
    let (x, y) = (a / h, b / h);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * std::f64::consts::PI)
}

/// A square emitter of radiance Le, half-side s, at height h above a Lambertian floor: the
/// floor point under its centre has irradiance E = π Le F (F the form factor of four corner
/// rectangles) and radiance ρ E / π = ρ Le F. Light sampling, BSDF sampling and MIS agree
/// with it and with each other.
#[test]
fn irradiance_under_a_square_emitter_matches_the_form_factor() {
    let (rho, le, s, h) = (0.5f32, 3.0f32, 0.7f32, 1.0f32);
    let scene = scene(
        vec![
            quad(Vec3::ZERO, Vec3::X * 20.0, -Vec3::Z * 20.0, 0),
            // Facing down (u × v = −Y): only its front face emits.
            quad(Vec3::Y * h, Vec3::X * s, Vec3::Z * s, 1),
        ],
        vec![
            diffuse(rho, 0.0),
            Material {
                double_sided: false,
                ..diffuse(0.0, le)
            },
        ],
        vec![],
    );
    // A tiny orthographic view of the floor around the origin, from below the emitter.
    let camera = ortho(Vec3::new(3.0, 0.5, 0.0), Vec3::ZERO, Vec3::Y, 1e-4, 1e-4);
    let f = 4.0 * corner_form_factor(s as f64, s as f64, h as f64);
    let want = rho as f64 * le as f64 * f;
    for (strategy, max_rel, image_rel) in [
        (LightStrategy::Mis, 1e-2, 1e-3),
        (LightStrategy::LightOnly, 2e-2, 2e-3),
        (LightStrategy::BsdfOnly, 5e-2, 5e-3),
    ] {
        let st = RenderSettings {
            light_strategy: strategy,
            max_depth: 1,
            ..settings(8, 1024, 0)
        };
        let est = estimate(&scene, &camera, None, BackendKind::default(), &st, 16);
        assert_matches(&format!("{strategy:?}"), &est, want, max_rel, image_rel);
    }
}

/// Inside a closed cube whose walls all emit Le and reflect ρ (Lambertian), radiance is the
/// geometric series Le (1 + ρ + ρ² + …) = Le / (1 − ρ) everywhere, with Russian roulette on
/// or off, on both backends.
#[test]
fn closed_emissive_box_follows_the_geometric_series() {
    let (rho, le) = (0.5f32, 1.0f32);
    let scene = scene(closed_cube(0), vec![diffuse(rho, le)], vec![]);
    let camera = look_at(
        Vec3::new(0.2, -0.1, 0.3),
        Vec3::new(-0.5, -0.3, -1.0),
        Vec3::Y,
        1.2,
    );
    let want = (le / (1.0 - rho)) as f64;
    for &backend in BackendKind::available() {
        for rr in [true, false] {
            let s = RenderSettings {
                russian_roulette: rr,
                ..settings(6, 256, 0)
            };
            let est = estimate(&scene, &camera, None, backend, &s, 16);
            assert_matches(&format!("{backend}, RR {rr}"), &est, want, 3e-2, 5e-3);
        }
    }
}

/// Same seed, any thread count: the same bytes.
#[test]
fn path_traced_images_do_not_depend_on_the_thread_count() {
    let scene = scene(closed_cube(0), vec![diffuse(0.7, 0.5)], vec![]);
    let camera = look_at(Vec3::ZERO, Vec3::new(0.3, 0.2, -1.0), Vec3::Y, 1.0);
    let accel = render::prepare(&scene, BackendKind::default(), BuildOptions::default()).unwrap();
    let render = |threads| {
        let s = RenderSettings {
            threads,
            ..settings(24, 4, 7)
        };
        image_bits(&render::render(&scene, accel.as_ref(), &camera, &s, None).unwrap())
    };
    assert_eq!(render(1), render(3));
}

/// The coverage (alpha) of a quad whose right edge splits a pixel column in half: 1 on the
/// covered columns, 0 on the others, 1/2 on the split column. With a box filter of one pixel
/// and 64 stratified samples the split column's estimate is within 1/8 of 1/2 for Sobol
/// points (the edge is axis-aligned, so each of the 8 columns of strata lies wholly on one
/// side: the estimate is exact up to the strata straddling the edge).
#[test]
fn coverage_alpha_is_the_fraction_of_samples_that_hit() {
    // Pixels are 0.25 wide over x ∈ [−1, 1]; the quad spans x ∈ [−3, 0.125].
    let quad_mesh = quad(
        Vec3::new(-1.4375, 0.0, 0.0),
        Vec3::new(1.5625, 0.0, 0.0),
        Vec3::new(0.0, 3.0, 0.0),
        0,
    );
    let s = scene(
        vec![quad_mesh],
        vec![support::lambert(Vec3::splat(0.5), true)],
        vec![],
    );
    let camera = ortho(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, Vec3::Y, 1.0, 1.0);
    let accel = render::prepare(&s, BackendKind::Bvh, BuildOptions::default()).unwrap();
    let env = EnvironmentLight::constant(Vec3::ONE);
    let inputs = RenderInputs {
        environment: Some(&env),
        ..RenderInputs::of_scene(&s, accel.as_ref(), &camera)
    };
    let settings = RenderSettings {
        width: 8,
        height: 8,
        spp: 64,
        threads: 2,
        integrator: Integrator::Path,
        ..RenderSettings::default()
    };
    let (film, _) = render::render_film(&inputs, &settings, 0..64, None).unwrap();
    let (_, aovs) = film.resolve();
    let alpha = aovs.alpha.expect("alpha is always resolved");
    for y in 0..8 {
        for x in 0..8 {
            let a = alpha.get(x, y).unwrap();
            let want = match x {
                0..=3 => 1.0,
                4 => 0.5,
                _ => 0.0,
            };
            let tol = if x == 4 { 0.125 } else { 0.0 };
            assert!(
                (a - want).abs() <= tol,
                "pixel ({x}, {y}): alpha {a}, want {want}"
            );
        }
    }
}
