//! The one light sampler is unbiased and its probabilities are the frequencies of its samples.
//!
//! Scene: 64 point lights (some with a range), 16 spot lights, an emissive mesh (a two-sided
//! quad split in two triangles, and a one-sided triangle) and a constant environment, all
//! seen from fixed shading points without occluders. The irradiance `E = ∫ L cos θ dω` the
//! sampler estimates (one light per sample, divided by its probability or density) must equal
//! the sum of each light's own contribution: closed forms for the delta lights
//! (`PunctualLight::incident`) and the environment (`π L`), and the emissive mesh estimated
//! apart by its own sampler (tested in tests/transport/area_lights.rs) with many more samples. 4σ.

use glam::{Vec2, Vec3};
use glint::light::area::{AreaLights, EmitterMesh};
use glint::light::environment::EnvironmentLight;
use glint::light::{LightSample, LightSampler, LightSet, LightUnits, PunctualLight};
use glint::scene::Light;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::borrow::Cow;

const LE: Vec3 = Vec3::new(3.0, 2.0, 1.0);
const SKY: Vec3 = Vec3::new(0.2, 0.3, 0.5);

fn lights() -> Vec<Light> {
    let mut rng = Pcg64::seed_from_u64(7);
    let mut lights = Vec::new();
    for i in 0..64 {
        lights.push(Light::Point {
            position: Vec3::new(
                rng.random_range(-6.0..6.0),
                rng.random_range(0.5..5.0),
                rng.random_range(-6.0..6.0),
            ),
            intensity: Vec3::new(
                rng.random_range(0.1..4.0),
                rng.random_range(0.1..4.0),
                rng.random_range(0.1..4.0),
            ),
            range: (i % 4 == 0).then_some(rng.random_range(3.0..9.0)),
        });
    }
    for _ in 0..16 {
        let position = Vec3::new(
            rng.random_range(-5.0..5.0),
            rng.random_range(2.0..6.0),
            rng.random_range(-5.0..5.0),
        );
        let target = Vec3::new(
            rng.random_range(-2.0..2.0),
            0.0,
            rng.random_range(-2.0..2.0),
        );
        lights.push(Light::Spot {
            position,
            direction: target - position,
            intensity: Vec3::splat(rng.random_range(2.0..20.0)),
            range: None,
            cos_inner: 0.95,
            cos_outer: rng.random_range(0.6..0.9),
        });
    }
    lights
}

/// Positions and triangles of one emissive mesh.
type Triangles = (Vec<Vec3>, Vec<[u32; 3]>);

/// The emissive meshes: a two-sided quad above the origin and a one-sided triangle facing it.
fn emitters() -> (Triangles, Triangles) {
    let quad = vec![
        Vec3::new(-1.0, 3.0, -1.0),
        Vec3::new(1.0, 3.0, -1.0),
        Vec3::new(1.0, 3.0, 1.0),
        Vec3::new(-1.0, 3.0, 1.0),
    ];
    let tri = vec![
        Vec3::new(3.0, 1.0, -1.0),
        Vec3::new(3.0, 2.0, 1.0),
        Vec3::new(3.0, 0.5, 1.0),
    ];
    ((quad, vec![[0, 1, 2], [0, 2, 3]]), (tri, vec![[0, 1, 2]]))
}

fn area_lights() -> AreaLights {
    let ((qp, qi), (tp, ti)) = emitters();
    let meshes = [
        EmitterMesh {
            positions: &qp,
            indices: &qi,
            two_sided: true,
            instances: &[],
        },
        EmitterMesh {
            positions: &tp,
            indices: &ti,
            two_sided: false,
            instances: &[],
        },
    ];
    AreaLights::new(&meshes, |_, _| LE).unwrap()
}

/// Shading points and normals, none on a light.
fn points() -> [(Vec3, Vec3); 4] {
    [
        (Vec3::ZERO, Vec3::Y),
        (
            Vec3::new(1.5, 0.2, -0.5),
            Vec3::new(0.3, 1.0, 0.1).normalize(),
        ),
        (
            Vec3::new(-3.0, 1.0, 2.0),
            Vec3::new(1.0, 0.4, -0.2).normalize(),
        ),
        (Vec3::new(2.0, 1.2, 0.0), Vec3::X),
    ]
}

/// `E` of the sample, `f = cos⁺/π · π`: the cosine-weighted incident radiance over its
/// density (a Lambertian irradiance estimate), 0 below the horizon.
fn estimate(sample: &LightSample, n: Vec3) -> Vec3 {
    match *sample {
        LightSample::Delta {
            wi,
            irradiance,
            probability,
            ..
        } => irradiance * n.dot(wi).max(0.0) / probability,
        LightSample::Area(ls) => ls.le * n.dot(ls.wi).max(0.0) / ls.pdf,
        LightSample::Environment(es) => es.radiance * n.dot(es.wi).max(0.0) / es.pdf,
    }
}

fn mean_and_error(values: &[Vec3]) -> (Vec3, Vec3) {
    let n = values.len() as f64;
    let mean = values.iter().map(|v| v.as_dvec3()).sum::<glam::DVec3>() / n;
    let var = values
        .iter()
        .map(|v| (v.as_dvec3() - mean) * (v.as_dvec3() - mean))
        .sum::<glam::DVec3>()
        / (n - 1.0);
    (mean.as_vec3(), (var / n).as_vec3().map(f32::sqrt))
}

fn sample_many(sampler: &LightSampler, p: Vec3, n: Vec3, count: usize, seed: u64) -> Vec<Vec3> {
    let mut rng = Pcg64::seed_from_u64(seed);
    (0..count)
        .map(|_| {
            let u_choice = rng.random::<f32>();
            let u = Vec2::new(rng.random(), rng.random());
            // Every kind's sample (and every split delta light) adds to one estimate.
            let split: Vec3 = sampler
                .delta(p)
                .filter_map(Result::ok)
                .map(|s| estimate(&s, n))
                .sum();
            let kinds: Vec3 = sampler
                .kinds()
                .into_iter()
                .flatten()
                .filter_map(|kind| sampler.sample(kind, p, n, u_choice, u).ok())
                .map(|s| estimate(&s, n))
                .sum();
            split + kinds
        })
        .collect()
}

#[test]
fn the_sampler_estimates_the_sum_of_every_light() {
    let set = LightSet::new(&lights(), LightUnits::Radiometric).unwrap();
    let area = area_lights();
    let env = EnvironmentLight::constant(SKY);
    let all = LightSampler::new(&set, Some(Cow::Borrowed(&area)), Some(&env));
    let area_only = LightSampler::new(&LightSet::default(), Some(Cow::Borrowed(&area)), None);
    let mut lit = 0;
    for (k, (p, n)) in points().into_iter().enumerate() {
        // Delta lights in closed form.
        let delta: Vec3 = set
            .lights
            .iter()
            .filter_map(|l| l.incident(p).ok())
            .map(|i| i.irradiance * n.dot(i.wi).max(0.0))
            .sum();
        let sky = std::f32::consts::PI * SKY;
        let (emitted, emitted_se) =
            mean_and_error(&sample_many(&area_only, p, n, 400_000, 100 + k as u64));
        let expected = delta + sky + emitted;
        let (mean, se) = mean_and_error(&sample_many(&all, p, n, 400_000, k as u64));
        let tolerance = 4.0 * (se * se + emitted_se * emitted_se).map(f32::sqrt) + 1e-5 * expected;
        assert!(
            (mean - expected).abs().cmple(tolerance).all(),
            "point {k}: sampler {mean} ± {se} vs lights one by one {expected} (delta {delta}, \
             sky {sky}, emitters {emitted} ± {emitted_se})"
        );
        lit += usize::from(delta.min_element() > 0.0 && emitted.min_element() > 0.0);
    }
    assert!(
        lit >= 3,
        "only {lit} points see both delta lights and emitters"
    );
}

#[test]
fn densities_the_sampler_reports_are_those_it_samples_with() {
    let set = LightSet::new(&lights(), LightUnits::Radiometric).unwrap();
    let area = area_lights();
    let env = EnvironmentLight::constant(SKY);
    let sampler = LightSampler::new(&set, Some(Cow::Borrowed(&area)), Some(&env));
    let mut rng = Pcg64::seed_from_u64(3);
    let (p, n) = points()[1];
    // Counts per delta light (by position of its probability in the list) against the
    // probability it reports: chi-square with the light's expected count.
    let count = 200_000usize;
    let mut chosen: Vec<(f32, [i64; 3])> = Vec::new();
    let mut delta_total = 0usize;
    let mut env_samples = 0usize;
    for _ in 0..count {
        let u_choice = rng.random::<f32>();
        let u = Vec2::new(rng.random(), rng.random());
        let samples = [
            sampler.sample_finite(p, n, u_choice, u),
            sampler.sample_infinite(p, u_choice, u),
        ];
        for sample in samples.into_iter().filter_map(Result::ok) {
            match sample {
                LightSample::Delta {
                    wi, probability, ..
                } => {
                    delta_total += 1;
                    // Lights are told apart by their direction from p (no two coincide here).
                    let key = [wi.x, wi.y, wi.z].map(|c| (c * 1e4).round() as i64);
                    chosen.push((probability, key));
                }
                LightSample::Area(ls) => {
                    let pdf = sampler.area_pdf(p, n, (ls.mesh, ls.instance, ls.triangle), ls.point);
                    assert!(
                        (pdf - ls.pdf).abs() <= 1e-4 * ls.pdf,
                        "area pdf {pdf} vs sampled {}",
                        ls.pdf
                    );
                }
                LightSample::Environment(es) => {
                    env_samples += 1;
                    let pdf = sampler.environment_pdf(es.wi);
                    assert!(
                        (pdf - es.pdf).abs() <= 1e-5 * es.pdf,
                        "environment pdf {pdf} vs sampled {}",
                        es.pdf
                    );
                }
            }
        }
    }
    assert_eq!(
        env_samples, count,
        "the environment is the one infinite light"
    );
    // Group the delta samples by light and compare frequencies with probabilities.
    chosen.sort_by_key(|&(_, key)| key);
    let mut chi2 = 0.0f64;
    let mut cells = 0usize;
    let mut i = 0;
    let mut probability_sum = 0.0f64;
    while i < chosen.len() {
        let key = chosen[i].1;
        let probability = f64::from(chosen[i].0);
        let mut j = i;
        while j < chosen.len() && chosen[j].1 == key {
            assert!(
                (f64::from(chosen[j].0) - probability).abs() <= 1e-6 * probability,
                "a light's probability must not depend on the sample"
            );
            j += 1;
        }
        let observed = (j - i) as f64;
        let expected = probability * count as f64;
        probability_sum += probability;
        if expected >= 5.0 {
            chi2 += (observed - expected).powi(2) / expected;
            cells += 1;
        }
        i = j;
    }
    assert!(cells > 20, "only {cells} lights were chosen often enough");
    assert!(delta_total > count / 4);
    use statrs::distribution::{ChiSquared, ContinuousCDF};
    let p_value = 1.0 - ChiSquared::new((cells - 1) as f64).unwrap().cdf(chi2);
    assert!(
        p_value > 1e-4,
        "selection frequencies differ from the reported probabilities: χ² = {chi2} over {cells} \
         lights, p = {p_value}"
    );
    assert!(
        probability_sum <= 1.0 + 1e-5,
        "probabilities sum to {probability_sum}"
    );
}

#[test]
fn one_light_consumes_no_random_numbers_and_is_exact() {
    let lights = [Light::Point {
        position: Vec3::new(0.0, 2.0, 0.0),
        intensity: Vec3::splat(3.0),
        range: None,
    }];
    let set = LightSet::new(&lights, LightUnits::Radiometric).unwrap();
    let sampler = LightSampler::new(&set, None, None);
    assert_eq!(sampler.kinds(), [None, None]);
    let samples: Vec<_> = sampler.delta(Vec3::ZERO).collect();
    assert_eq!(samples.len(), 1);
    let Ok(LightSample::Delta {
        irradiance,
        probability,
        ..
    }) = samples[0]
    else {
        panic!("a point light gives a delta sample");
    };
    assert_eq!(probability, 1.0);
    assert!((irradiance - Vec3::splat(0.75)).abs().max_element() < 1e-6);
}

#[test]
fn few_delta_lights_are_each_sampled_and_the_rest_chosen() {
    let lights = [
        Light::Point {
            position: Vec3::new(0.0, 2.0, 0.0),
            intensity: Vec3::splat(3.0),
            range: None,
        },
        Light::Directional {
            direction: -Vec3::Y,
            irradiance: Vec3::splat(0.5),
        },
    ];
    let set = LightSet::new(&lights, LightUnits::Radiometric).unwrap();
    let env = EnvironmentLight::constant(SKY);
    let sampler = LightSampler::new(&set, None, Some(&env));
    // Both delta lights every time, with probability 1; the environment is the only choice.
    let delta: Vec<_> = sampler.delta(Vec3::ZERO).collect();
    assert_eq!(delta.len(), 2);
    assert!(delta.iter().all(|s| matches!(
        s,
        Ok(LightSample::Delta {
            probability: 1.0,
            ..
        })
    )));
    let [finite, infinite] = sampler.kinds();
    let infinite = infinite.unwrap();
    assert!(finite.is_none() && !infinite.needs_choice && infinite.needs_position);
    let s = sampler
        .sample(infinite, Vec3::ZERO, Vec3::Y, 0.3, Vec2::new(0.2, 0.7))
        .unwrap();
    assert!(matches!(s, LightSample::Environment(_)));
    // Past DELTA_SPLIT_MAX they are chosen instead.
    let many: Vec<Light> = (0..=glint::light::sampler::DELTA_SPLIT_MAX)
        .map(|i| Light::Point {
            position: Vec3::new(i as f32, 2.0, 0.0),
            intensity: Vec3::ONE,
            range: None,
        })
        .collect();
    let set = LightSet::new(&many, LightUnits::Radiometric).unwrap();
    let sampler = LightSampler::new(&set, None, None);
    assert_eq!(sampler.delta(Vec3::ZERO).count(), 0);
    assert!(sampler.kinds()[0].is_some_and(|k| k.finite && k.needs_choice));
}

#[test]
fn a_thousand_point_lights_estimate_the_sum_of_their_contributions() {
    // 1,000 point lights (a quarter with a range) over a floor: the light tree's estimate at
    // each shading point, one light a sample, equals the sum of the lights' closed-form
    // contributions within 4σ. The tree is deep (about 10 levels), so a wrong probability
    // anywhere along a path shows.
    let mut rng = Pcg64::seed_from_u64(1000);
    let lights: Vec<Light> = (0..1000)
        .map(|i| Light::Point {
            position: Vec3::new(
                rng.random_range(-20.0..20.0),
                rng.random_range(0.3..6.0),
                rng.random_range(-20.0..20.0),
            ),
            intensity: Vec3::new(
                rng.random_range(0.05..3.0),
                rng.random_range(0.05..3.0),
                rng.random_range(0.05..3.0),
            ),
            range: (i % 4 == 0).then_some(rng.random_range(2.0..12.0)),
        })
        .collect();
    let set = LightSet::new(&lights, LightUnits::Radiometric).unwrap();
    let sampler = LightSampler::new(&set, None, None);
    assert_eq!(
        sampler.delta(Vec3::ZERO).count(),
        0,
        "1,000 lights are chosen, not split"
    );
    for (k, (p, n)) in points().into_iter().enumerate() {
        let expected: Vec3 = set
            .lights
            .iter()
            .filter_map(|l| l.incident(p).ok())
            .map(|i| i.irradiance * n.dot(i.wi).max(0.0))
            .sum();
        let (mean, se) = mean_and_error(&sample_many(&sampler, p, n, 200_000, 7 + k as u64));
        let tolerance = 4.0 * se + 1e-5 * expected;
        assert!(expected.min_element() > 0.0, "point {k} is lit");
        assert!(
            (mean - expected).abs().cmple(tolerance).all(),
            "point {k}: sampler {mean} ± {se} vs the lights one by one {expected}"
        );
    }
}
