//! Area lights: irradiance by light sampling against closed forms (disk, rectangle), the
//! solid angle as E[1/pdf], `pdf()` against the density `sample` used, selection frequencies
//! by power, one- and two-sided emission, and bad input.

use crate::support::{chi_square, chi_square_threshold, mean_and_error};
use glam::{Vec2, Vec3};
use glint::light::area::{AreaLightError, AreaLights, EmitterMesh, SelectionMode};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::f64::consts::PI;

/// A mesh and its triangles, owned.
struct Owned {
    positions: Vec<Vec3>,
    indices: Vec<[u32; 3]>,
    two_sided: bool,
}

impl Owned {
    fn view(&self) -> EmitterMesh<'_> {
        EmitterMesh {
            positions: &self.positions,
            indices: &self.indices,
            two_sided: self.two_sided,
            instances: &[],
        }
    }
}

/// A disk of radius `r` at height `h` above the origin, facing down (−Y), as a fan of `n`
/// triangles.
fn disk(r: f32, h: f32, n: usize) -> Owned {
    let mut positions = vec![Vec3::new(0.0, h, 0.0)];
    for i in 0..n {
        let phi = std::f32::consts::TAU * i as f32 / n as f32;
        positions.push(Vec3::new(r * phi.cos(), h, r * phi.sin()));
    }
    let indices = (0..n as u32)
        .map(|i| [0, 1 + i, 1 + (i + 1) % n as u32])
        .collect();
    Owned {
        positions,
        indices,
        two_sided: false,
    }
}

/// An `a × b` rectangle centred above the origin at height `h`, facing down.
fn rectangle(a: f32, b: f32, h: f32) -> Owned {
    let (x, z) = (a / 2.0, b / 2.0);
    Owned {
        positions: vec![
            Vec3::new(-x, h, -z),
            Vec3::new(x, h, -z),
            Vec3::new(x, h, z),
            Vec3::new(-x, h, z),
        ],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        two_sided: false,
    }
}

/// Mean and standard error of `Le cos θ / pdf` at the origin (normal +Y), no occlusion, and
/// of `1/pdf` (the solid angle); also checks every sample's pdf against `pdf()`.
fn estimate(lights: &AreaLights, n: usize, seed: u64) -> ((f64, f64), (f64, f64)) {
    let (p, normal) = (Vec3::ZERO, Vec3::Y);
    let mut rng = Pcg64::seed_from_u64(seed);
    let mut e = Vec::with_capacity(n);
    let mut omega = Vec::with_capacity(n);
    for _ in 0..n {
        let Some(s) = lights.sample(
            p,
            normal,
            rng.random(),
            Vec2::new(rng.random(), rng.random()),
        ) else {
            e.push(0.0);
            omega.push(0.0);
            continue;
        };
        let q = lights.pdf(p, normal, (s.mesh, s.instance, s.triangle), s.point);
        assert!(
            (q - s.pdf).abs() <= 1e-4 * s.pdf,
            "pdf() {q} vs sample {}",
            s.pdf
        );
        assert!((s.wi.length() - 1.0).abs() < 1e-5);
        assert!(((s.point - p).length() - s.distance).abs() < 1e-5 * s.distance);
        e.push(f64::from(s.le.x * normal.dot(s.wi).max(0.0) / s.pdf));
        omega.push(f64::from(1.0 / s.pdf));
    }
    (mean_and_error(&e), mean_and_error(&omega))
}

#[test]
fn disk_irradiance_matches_pi_l_sin2() {
    // E = π L sin²θ, sin²θ = r²/(r² + h²). The 1024-gon differs from the disk by ≈ 6e-6
    // relative in area; 10M samples give a standard error ≈ 1.3e-4 relative (asserted < 2.5e-4), so the 1e-3
    // bound is over 4σ.
    let l = 3.0f32;
    // Area sampling alone (solid-angle sampling off) and the default, which samples the fan's
    // triangles by solid angle; only the latter has the variance for a large, near disk.
    let cases = [
        (false, 1.0f32, 1.0f32),
        (false, 0.3, 2.0),
        (false, 1.0, 0.7),
        (true, 1.0, 1.0),
        (true, 0.3, 2.0),
        (true, 2.0, 0.5),
    ];
    for (solid_angle, r, h) in cases {
        let mesh = disk(r, h, 1024);
        let lights = AreaLights::new(&[mesh.view()], |_, _| Vec3::splat(l))
            .unwrap()
            .with_solid_angle_sampling(solid_angle);
        // Solid-angle sampling has ≥ 16× less variance here (docs/lights.md): fewer samples.
        let samples = if solid_angle { 2_000_000 } else { 10_000_000 };
        let ((mean, err), _) = estimate(&lights, samples, 1);
        let sin2 = f64::from(r * r / (r * r + h * h));
        let exact = PI * f64::from(l) * sin2;
        assert!(
            err < 2.5e-4 * exact,
            "standard error {err} too large for the 1e-3 check"
        );
        assert!(
            (mean - exact).abs() < 1e-3 * exact,
            "r {r} h {h}: E = {mean} ± {err}, closed form {exact}"
        );
    }
}

#[test]
fn rectangle_irradiance_and_solid_angle_match_closed_forms() {
    // Centred on the axis, four corner rectangles of the standard form factor: with
    // A = a/2h, B = b/2h,
    //   E = 2L [A/√(1+A²) atan(B/√(1+A²)) + B/√(1+B²) atan(A/√(1+B²))],
    //   Ω = 4 asin(ab / √((a² + 4h²)(b² + 4h²))).
    let l = 2.0f64;
    let sizes = [(1.0f32, 1.0f32, 1.0f32), (2.0, 0.5, 0.7), (0.2, 0.3, 1.5)];
    for ((a, b, h), solid_angle) in sizes.into_iter().flat_map(|s| [(s, false), (s, true)]) {
        let lights = AreaLights::new(&[rectangle(a, b, h).view()], |_, _| Vec3::splat(l as f32))
            .unwrap()
            .with_solid_angle_sampling(solid_angle);
        let samples = if solid_angle { 2_000_000 } else { 10_000_000 };
        let ((mean, err), (omega, omega_err)) = estimate(&lights, samples, 2);
        let (aa, bb) = (f64::from(a / (2.0 * h)), f64::from(b / (2.0 * h)));
        let sa = (1.0 + aa * aa).sqrt();
        let sb = (1.0 + bb * bb).sqrt();
        let exact = 2.0 * l * (aa / sa * (bb / sa).atan() + bb / sb * (aa / sb).atan());
        assert!(
            err < 2.5e-4 * exact,
            "standard error {err} too large for the 1e-3 check"
        );
        assert!(
            (mean - exact).abs() < 1e-3 * exact,
            "{a}×{b} at {h}: E = {mean} ± {err}, closed form {exact}"
        );
        let (a, b, h) = (f64::from(a), f64::from(b), f64::from(h));
        let solid = 4.0 * (a * b / ((a * a + 4.0 * h * h) * (b * b + 4.0 * h * h)).sqrt()).asin();
        assert!(
            (omega - solid).abs() < 4.0 * omega_err + 2e-5 * solid,
            "Ω = {omega} ± {omega_err}, closed form {solid}"
        );
    }
}

#[test]
fn lights_are_chosen_in_proportion_to_power() {
    // Five triangles: areas 0.5, 2, 0.5, 0.5, 0.5; the second two-sided (its own mesh); the
    // fourth black; radiance per triangle from the closure (as a texture average would be).
    let tri = |x: f32, s: f32| {
        [
            Vec3::new(x, 0.0, 0.0),
            Vec3::new(x + s, 0.0, 0.0),
            Vec3::new(x, 0.0, s),
        ]
    };
    let one = Owned {
        positions: [tri(0.0, 1.0), tri(5.0, 1.0), tri(7.0, 1.0), tri(9.0, 1.0)].concat(),
        indices: vec![[0, 1, 2], [3, 4, 5], [6, 7, 8], [9, 10, 11]],
        two_sided: false,
    };
    let two = Owned {
        positions: tri(2.0, 2.0).to_vec(),
        indices: vec![[0, 1, 2]],
        two_sided: true,
    };
    let unlit = Owned {
        positions: tri(0.0, 1.0).to_vec(),
        indices: vec![],
        two_sided: false,
    };
    let radiance = |m: u32, t: u32| match (m, t) {
        (0, 0) => Vec3::new(1.0, 0.0, 0.0),
        (0, 1) => Vec3::splat(2.0),
        (0, 2) => Vec3::ZERO,
        (0, 3) => Vec3::new(0.0, 0.0, 5.0),
        (2, 0) => Vec3::splat(0.5),
        _ => Vec3::splat(100.0), // never asked: mesh 1 has no triangles
    };
    let lights = AreaLights::new(&[one.view(), unlit.view(), two.view()], radiance).unwrap();
    let lum = |c: Vec3| f64::from(c.dot(Vec3::new(0.2126, 0.7152, 0.0722)));
    // (mesh, triangle, power) with Φ = π A Y(Le) (×2 two-sided).
    let expected_power = [
        (0u32, 0u32, PI * 0.5 * lum(Vec3::X)),
        (0, 1, PI * 0.5 * 2.0),
        (0, 2, 0.0),
        (0, 3, PI * 0.5 * lum(Vec3::Z * 5.0)),
        (2, 0, PI * 2.0 * 0.5 * 2.0),
    ];
    let total: f64 = expected_power.iter().map(|e| e.2).sum();
    assert!((f64::from(lights.total_power()) - total).abs() < 1e-5 * total);
    let index: Vec<usize> = expected_power
        .iter()
        .map(|&(m, t, _)| lights.light_index(m, 0, t).unwrap())
        .collect();
    assert!(lights.light_index(1, 0, 0).is_none());
    let p = Vec3::new(1.0, 3.0, 1.0);
    for (k, &(_, _, power)) in expected_power.iter().enumerate() {
        let pmf = f64::from(lights.selection_pmf(p, Vec3::ZERO, index[k]));
        assert!(
            (pmf - power / total).abs() < 1e-6,
            "light {k}: {pmf} vs {}",
            power / total
        );
    }
    let n = 500_000u64;
    let mut counts = [0u64; 5];
    let mut rng = Pcg64::seed_from_u64(3);
    for _ in 0..n {
        let (i, _) = lights.select(p, Vec3::ZERO, rng.random()).unwrap();
        let k = index.iter().position(|&x| x == i).unwrap();
        counts[k] += 1;
    }
    let expected: Vec<f64> = expected_power
        .iter()
        .map(|e| e.2 / total * n as f64)
        .collect();
    let (chi, dof) = chi_square(&counts, &expected);
    assert!(
        chi < chi_square_threshold(dof),
        "χ² {chi}, {dof} dof: {counts:?}"
    );
}

#[test]
fn one_sided_lights_emit_from_the_front_only() {
    let mut rng = Pcg64::seed_from_u64(4);
    let front = rectangle(1.0, 1.0, 1.0); // faces −Y: lights the origin
    let lights = AreaLights::new(&[front.view()], |_, _| Vec3::ONE).unwrap();
    let above = Vec3::new(0.0, 2.0, 0.0);
    for _ in 0..100 {
        let u = Vec2::new(rng.random(), rng.random());
        assert!(lights.sample(above, Vec3::ZERO, rng.random(), u).is_none());
        assert!(
            lights
                .sample(Vec3::ZERO, Vec3::ZERO, rng.random(), u)
                .is_some()
        );
    }
    assert_eq!(
        lights.pdf(above, Vec3::ZERO, (0, 0, 0), Vec3::new(0.1, 1.0, 0.1)),
        0.0
    );
    let mut both = rectangle(1.0, 1.0, 1.0);
    both.two_sided = true;
    let lights = AreaLights::new(&[both.view()], |_, _| Vec3::ONE).unwrap();
    let s = lights
        .sample(above, Vec3::ZERO, 0.3, Vec2::new(0.2, 0.7))
        .unwrap();
    assert!(s.wi.y < 0.0 && s.normal.y < 0.0);
    assert!(lights.pdf(above, Vec3::ZERO, (s.mesh, s.instance, s.triangle), s.point) > 0.0);
}

#[test]
fn no_emission_builds_nothing_and_bad_input_is_refused() {
    let black = rectangle(1.0, 1.0, 1.0);
    let lights = AreaLights::new(&[black.view()], |_, _| Vec3::ZERO).unwrap();
    assert!(lights.is_empty());
    assert!(
        lights
            .sample(Vec3::ZERO, Vec3::Y, 0.5, Vec2::splat(0.5))
            .is_none()
    );
    assert!(AreaLights::new(&[], |_, _| Vec3::ONE).unwrap().is_empty());
    let mut broken = rectangle(1.0, 1.0, 1.0);
    broken.indices[1] = [0, 2, 9];
    let err = AreaLights::new(&[broken.view()], |_, _| Vec3::ONE).unwrap_err();
    assert!(
        matches!(
            err,
            AreaLightError::Index {
                mesh: 0,
                triangle: 1,
                index: 9,
                ..
            }
        ),
        "{err}"
    );
    let err = AreaLights::new(&[black.view()], |_, _| Vec3::new(1.0, -1.0, 0.0)).unwrap_err();
    assert!(matches!(err, AreaLightError::Radiance { .. }));
    // A degenerate triangle has no power and is never chosen.
    let flat = Owned {
        positions: vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::X * 2.0,
            Vec3::Y,
            Vec3::Y + Vec3::Z,
            Vec3::Z,
        ],
        indices: vec![[0, 1, 2], [3, 4, 5]],
        two_sided: false,
    };
    let lights =
        AreaLights::with_selection(&[flat.view()], |_, _| Vec3::ONE, SelectionMode::Power).unwrap();
    for k in 0..100 {
        let (i, _) = lights
            .select(Vec3::ZERO, Vec3::ZERO, k as f32 / 100.0)
            .unwrap();
        assert_eq!(i, 1);
    }
}

/// `n` random triangles in a 10 m box: random orientation and size, a quarter two-sided,
/// every tenth black; Le per triangle random.
fn random_emitters(n: usize, seed: u64) -> (Owned, Owned, Vec<Vec3>) {
    let mut rng = Pcg64::seed_from_u64(seed);
    let mut one = Owned {
        positions: vec![],
        indices: vec![],
        two_sided: false,
    };
    let mut two = Owned {
        positions: vec![],
        indices: vec![],
        two_sided: true,
    };
    let mut le = Vec::new();
    let mut v = || Vec3::new(rng.random(), rng.random(), rng.random()) - 0.5;
    for k in 0..n {
        let c = 10.0 * v();
        let size = 0.05 + 0.5 * (v().x + 0.5);
        let mesh = if k % 4 == 0 { &mut two } else { &mut one };
        let base = mesh.positions.len() as u32;
        mesh.positions
            .extend([c + size * v(), c + size * v(), c + size * v()]);
        mesh.indices.push([base, base + 1, base + 2]);
        le.push(if k % 10 == 3 {
            Vec3::ZERO
        } else {
            (v() + 0.5) * 4.0
        });
    }
    (one, two, le)
}

#[test]
fn light_bvh_pmf_sums_to_one_covers_every_reachable_light_and_matches_samples() {
    let (one, two, le) = random_emitters(400, 21);
    let (n_one, n_two) = (one.indices.len(), two.indices.len());
    // Le by (mesh, triangle): mesh 0 holds the triangles k % 4 != 0, mesh 1 the others.
    let order: Vec<usize> = (0..le.len())
        .filter(|k| k % 4 != 0)
        .chain((0..le.len()).filter(|k| k % 4 == 0))
        .collect();
    let le_of = |m: u32, t: u32| {
        le[order[if m == 0 {
            t as usize
        } else {
            n_one + t as usize
        }]]
    };
    let lights =
        AreaLights::with_selection(&[one.view(), two.view()], le_of, SelectionMode::Bvh).unwrap();
    assert_eq!(lights.lights().len(), n_one + n_two);
    let mut rng = Pcg64::seed_from_u64(22);
    let mut v = || Vec3::new(rng.random(), rng.random(), rng.random()) - 0.5;
    for trial in 0..20 {
        let p = 14.0 * v();
        let n = if trial % 3 == 0 {
            Vec3::ZERO
        } else {
            v().normalize()
        };
        let mut sum = 0.0f64;
        for (k, light) in lights.lights().iter().enumerate() {
            let pmf = lights.selection_pmf(p, n, k);
            assert!(pmf >= 0.0 && pmf.is_finite());
            sum += f64::from(pmf);
            // Conservative bounds: a light that can emit toward p has a positive probability.
            let facing = light.normal.dot(p - light.p0) > 1e-4;
            if light.power() > 0.0 && (facing || light.two_sided) {
                assert!(
                    pmf > 0.0,
                    "trial {trial}: reachable light {k} has probability 0"
                );
            }
            if light.power() == 0.0 {
                assert_eq!(pmf, 0.0);
            }
        }
        // One-sided lights facing away can empty a subtree the walk entered: then no light
        // is chosen (those lights contribute nothing, so the estimator stays unbiased) and
        // Σ pmf = 1 − P(no light). Check that against the sampler's failure frequency
        // (binomial, 5σ).
        assert!(sum <= 1.0 + 1e-5, "trial {trial}: Σ pmf = {sum}");
        let draws = 20_000;
        let failures = (0..draws)
            .filter(|k| {
                lights
                    .select(p, n, (*k as f32 + 0.5) / draws as f32)
                    .is_none()
            })
            .count();
        let fail = failures as f64 / draws as f64;
        let sigma = ((1.0 - sum).max(1e-4) * sum / draws as f64).sqrt();
        assert!(
            (fail - (1.0 - sum)).abs() < 5.0 * sigma + 1e-4,
            "trial {trial}: Σ pmf = {sum}, sampler fails {fail}"
        );
    }
    // With two-sided lights only, every node has positive importance everywhere: Σ pmf = 1.
    let mut both = one;
    both.two_sided = true;
    let all =
        AreaLights::with_selection(&[both.view(), two.view()], le_of, SelectionMode::Bvh).unwrap();
    let mut rng = Pcg64::seed_from_u64(24);
    let mut v = || Vec3::new(rng.random(), rng.random(), rng.random()) - 0.5;
    for trial in 0..20 {
        let p = 14.0 * v();
        let n = if trial % 3 == 0 {
            Vec3::ZERO
        } else {
            v().normalize()
        };
        let sum: f64 = (0..all.lights().len())
            .map(|k| f64::from(all.selection_pmf(p, n, k)))
            .sum();
        assert!(
            (sum - 1.0).abs() < 1e-5,
            "two-sided, trial {trial}: Σ pmf = {sum}"
        );
    }
    // Sampled frequencies against pmf() at one point, and each sample's own probability.
    let (p, n) = (
        Vec3::new(1.0, -2.0, 0.5),
        Vec3::new(0.3, 1.0, -0.2).normalize(),
    );
    let count = lights.lights().len();
    let samples = 400_000u64;
    // The last bin counts the draws that chose no light, expected 1 − Σ pmf.
    let mut counts = vec![0u64; count + 1];
    let mut rng = Pcg64::seed_from_u64(23);
    for _ in 0..samples {
        let Some((k, pmf)) = lights.select(p, n, rng.random()) else {
            counts[count] += 1;
            continue;
        };
        let q = lights.selection_pmf(p, n, k);
        assert!((pmf - q).abs() <= 1e-5 * q, "sampled {pmf} vs pmf() {q}");
        counts[k] += 1;
    }
    let mut expected: Vec<f64> = (0..count)
        .map(|k| f64::from(lights.selection_pmf(p, n, k)) * samples as f64)
        .collect();
    let chosen: f64 = expected.iter().sum();
    expected.push((samples as f64 - chosen).max(0.0));
    let (chi, dof) = chi_square(&counts, &expected);
    assert!(chi < chi_square_threshold(dof), "χ² {chi}, {dof} dof");
}

#[test]
fn light_bvh_irradiance_matches_the_closed_forms() {
    // The same closed forms as with the power CDF: the BVH changes only the variance. (Both
    // emitters are sampled by solid angle here, so 2M samples reach the 2.5e-4 error.)
    let l = 3.0f32;
    let (r, h) = (1.0f32, 1.0f32);
    let lights = AreaLights::with_selection(
        &[disk(r, h, 1024).view()],
        |_, _| Vec3::splat(l),
        SelectionMode::Bvh,
    )
    .unwrap();
    let ((mean, err), _) = estimate(&lights, 2_000_000, 5);
    let exact = PI * f64::from(l) * f64::from(r * r / (r * r + h * h));
    assert!(err < 2.5e-4 * exact);
    assert!(
        (mean - exact).abs() < 1e-3 * exact,
        "E = {mean} ± {err}, closed form {exact}"
    );
    let (a, b, h) = (2.0f32, 0.5f32, 0.7f32);
    let lights = AreaLights::with_selection(
        &[rectangle(a, b, h).view()],
        |_, _| Vec3::splat(l),
        SelectionMode::Bvh,
    )
    .unwrap();
    let ((mean, err), _) = estimate(&lights, 2_000_000, 6);
    let (aa, bb) = (f64::from(a / (2.0 * h)), f64::from(b / (2.0 * h)));
    let (sa, sb) = ((1.0 + aa * aa).sqrt(), (1.0 + bb * bb).sqrt());
    let exact = 2.0 * f64::from(l) * (aa / sa * (bb / sa).atan() + bb / sb * (aa / sb).atan());
    assert!(
        (mean - exact).abs() < 1e-3 * exact && err < 2.5e-4 * exact,
        "E = {mean} ± {err}, closed form {exact}"
    );
}
