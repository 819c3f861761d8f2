//! The environment light: Blender's equirectangular mapping, importance sampling against its
//! pdf, a single bright texel as a directional light, and file loading (EXR incl. DWAB, HDR)
//! with its errors.

use crate::support::{chi_square, chi_square_threshold, mean_and_error};
use glam::{Vec2, Vec3};
use glint::light::environment::{
    EnvImage, EnvOptions, EnvironmentError, EnvironmentLight, Interpolation, SUPERSAMPLING,
    read_env_image,
};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use std::f32::consts::{PI, TAU};
use std::path::{Path, PathBuf};

fn shared(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/env")
        .join(name)
}

/// The mapping, written out independently of the library.
fn expected_uv(d: Vec3, rot_deg: f32) -> (f32, f32) {
    let u = (0.5 + (d.z.atan2(d.x) + rot_deg.to_radians()) / TAU).rem_euclid(1.0);
    (u, d.y.clamp(-1.0, 1.0).acos() / PI)
}

/// A unit direction from the polar angle θ (from +Y) and the image azimuth φ = 2π(u − ½).
fn direction(theta: f32, phi: f32) -> Vec3 {
    Vec3::new(
        theta.sin() * phi.cos(),
        theta.cos(),
        theta.sin() * phi.sin(),
    )
}

/// Writes an EXR (ZIP-compressed f32 RGB) whose texel colour is `f(column, row)`.
fn write_exr(path: &Path, w: usize, h: usize, f: impl Fn(usize, usize) -> Vec3 + Sync) {
    exr::prelude::write_rgb_file(path, w, h, |x, y| {
        let c = f(x, y);
        (c.x, c.y, c.z)
    })
    .unwrap();
}

/// An EXR of `w × h` whose colour encodes the texel centre: R = u, G = v.
fn uv_ramp(dir: &Path, w: usize, h: usize) -> PathBuf {
    let path = dir.join("ramp.exr");
    write_exr(&path, w, h, |x, y| {
        Vec3::new(
            (x as f32 + 0.5) / w as f32,
            (y as f32 + 0.5) / h as f32,
            0.25,
        )
    });
    path
}

#[test]
fn mapping_is_blenders_at_the_axes_and_random_directions() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (64, 32);
    let path = uv_ramp(dir.path(), w, h);
    let half_u = 0.5 / w as f32;
    let half_v = 0.5 / h as f32;
    for rot in [0.0f32, 90.0, -37.5] {
        let env = EnvironmentLight::from_file(&path, 1.0, rot).unwrap();
        // The axes, with rot = 0: +X the centre, −Z a quarter, +Z three quarters, ±Y the
        // poles (clamped to the outer row centres), −X the seam.
        if rot == 0.0 {
            let cases = [
                (Vec3::X, Some(0.5), 0.5),
                (-Vec3::Z, Some(0.25), 0.5),
                (Vec3::Z, Some(0.75), 0.5),
                (Vec3::Y, None, half_v),
                (-Vec3::Y, None, 1.0 - half_v),
                // Bilinear across the seam blends the first and last columns: (u₀ + u_last)/2.
                (-Vec3::X, Some(0.5), 0.5),
            ];
            for (d, u, v) in cases {
                let l = env.radiance(d);
                if let Some(u) = u {
                    assert!((l.x - u).abs() < 1e-5, "{d}: R {} want {u}", l.x);
                }
                assert!((l.y - v).abs() < 1e-5, "{d}: G {} want {v}", l.y);
            }
            let seam = env.direction_to_uv(-Vec3::X).x;
            assert!(seam.min(1.0 - seam) < 1e-6, "−X is the seam, u = {seam}");
        }
        if rot == 90.0 {
            // A right-handed quarter turn about +Y brings what was at +Z (u = 0.75) to +X,
            // and what was at +X (u = 0.5) to −Z.
            assert!((env.radiance(Vec3::X).x - 0.75).abs() < 1e-5);
            assert!((env.radiance(-Vec3::Z).x - 0.5).abs() < 1e-5);
        }
        let mut rng = Pcg64::seed_from_u64(11);
        let mut checked = 0;
        for _ in 0..2000 {
            let d = Vec3::new(
                rng.random::<f32>() - 0.5,
                rng.random::<f32>() - 0.5,
                rng.random::<f32>() - 0.5,
            )
            .normalize();
            let (u, v) = expected_uv(d, rot);
            let uv = env.direction_to_uv(d);
            let du = (uv.x - u).abs();
            assert!(du.min(1.0 - du) < 1e-5 && (uv.y - v).abs() < 1e-5);
            // Between texel centres the bilinear lookup of a linear ramp is exact.
            if (half_u..1.0 - half_u).contains(&u) && (half_v..1.0 - half_v).contains(&v) {
                let l = env.radiance(d);
                assert!(
                    (l.x - u).abs() < 1e-4 && (l.y - v).abs() < 1e-4,
                    "{d}: {l} vs {u},{v}"
                );
                assert!((l.z - 0.25).abs() < 1e-6);
                checked += 1;
            }
        }
        assert!(checked > 1800);
    }
    // Nearest lookup returns the containing texel's centre.
    let env = EnvironmentLight::from_file_with(
        &path,
        &EnvOptions {
            interpolation: Interpolation::Nearest,
            ..EnvOptions::default()
        },
    )
    .unwrap();
    let d = Vec3::new(0.3, 0.4, -0.5).normalize();
    let (u, v) = expected_uv(d, 0.0);
    let centre_u = ((u * w as f32).floor() + 0.5) / w as f32;
    let centre_v = ((v * h as f32).floor() + 0.5) / h as f32;
    let l = env.radiance(d);
    assert!((l.x - centre_u).abs() < 1e-6 && (l.y - centre_v).abs() < 1e-6);
    // Strength multiplies the radiance.
    let twice = EnvironmentLight::from_file(&path, 2.0, 0.0).unwrap();
    assert!(
        (twice.radiance(d)
            - 2.0
                * EnvironmentLight::from_file(&path, 1.0, 0.0)
                    .unwrap()
                    .radiance(d))
        .abs()
        .max_element()
            < 1e-6
    );
}

/// `∫ pdf dω` by the midpoint rule on a (θ, φ) grid of `sub × sub` points per texel: with
/// `sub` a multiple of the sampling distribution's cells per texel (4 for bilinear lookup of
/// a map up to 1024 × 512 texels, 2 up to 2048 × 1024), the integrand `pdf · sin θ` is
/// constant on each cell, so the rule is exact up to rounding.
fn integrate_pdf(env: &EnvironmentLight, w: usize, h: usize, sub: usize, rot_deg: f32) -> f64 {
    let (nu, nv) = (w * sub, h * sub);
    let (dphi, dtheta) = (TAU / nu as f32, PI / nv as f32);
    let mut total = 0.0f64;
    for j in 0..nv {
        let theta = (j as f32 + 0.5) * dtheta;
        for i in 0..nu {
            let phi = TAU * ((i as f32 + 0.5) / nu as f32 - 0.5) - rot_deg.to_radians();
            let pdf = env.pdf(direction(theta, phi));
            total += f64::from(pdf * theta.sin() * dtheta * dphi);
        }
    }
    total
}

#[test]
fn pdf_integrates_to_one_over_the_sphere() {
    for rot in [0.0, 37.0] {
        let env = EnvironmentLight::from_file(&shared("studio.hdr"), 1.0, rot).unwrap();
        let (w, h) = env.size().unwrap();
        let total = integrate_pdf(&env, w, h, 4, rot);
        assert!((total - 1.0).abs() < 1e-3, "rot {rot}: ∫pdf dω = {total}");
    }
    // The constant environment: uniform over the sphere.
    let c = EnvironmentLight::constant(Vec3::ONE);
    assert!((c.pdf(Vec3::Y) * 4.0 * PI - 1.0).abs() < 1e-6);
}

#[test]
fn samples_follow_the_pdf_chi_square() {
    // A random 16 × 8 map with black texels, both lookups. Bins are the texels; the expected
    // count of a bin is N ∫_texel pdf dω (integrated as above, 4 × 4 points per texel).
    let (w, h) = (16usize, 8usize);
    let mut rng = Pcg64::seed_from_u64(5);
    let texels: Vec<Vec3> = (0..w * h)
        .map(|k| {
            if k % 7 == 3 {
                Vec3::ZERO
            } else {
                Vec3::new(rng.random(), rng.random(), rng.random()) * 3.0
            }
        })
        .collect();
    for interpolation in [Interpolation::Nearest, Interpolation::Bilinear] {
        let rot = 20.0;
        let env = EnvironmentLight::from_image(
            EnvImage {
                width: w,
                height: h,
                texels: texels.clone(),
            },
            &EnvOptions {
                rotation_deg: rot,
                interpolation,
                ..EnvOptions::default()
            },
        )
        .unwrap();
        let n = 400_000u64;
        let mut counts = vec![0u64; w * h];
        let mut on_edges = 0;
        for _ in 0..n {
            let s = env.sample(Vec2::new(rng.random(), rng.random())).unwrap();
            assert!((s.wi.length() - 1.0).abs() < 1e-5);
            let (u, v) = expected_uv(s.wi, rot);
            let pdf = env.pdf(s.wi);
            assert!((s.radiance - env.radiance(s.wi)).abs().max_element() < 1e-3);
            if (s.pdf - pdf).abs() > 2e-3 * pdf {
                // Only where rounding in uv → direction → uv crosses a texel edge.
                let edge = |x: f32, n: usize| {
                    let f = (x * n as f32).fract();
                    f.min(1.0 - f) < 1e-3
                };
                assert!(
                    edge(u, w) || edge(v, h),
                    "sample pdf {} vs pdf() {pdf} at {u},{v}",
                    s.pdf
                );
                on_edges += 1;
            }
            let i = ((u * w as f32) as usize).min(w - 1);
            let j = ((v * h as f32) as usize).min(h - 1);
            counts[j * w + i] += 1;
        }
        let sub = 4;
        let (dphi, dtheta) = (TAU / (w * sub) as f32, PI / (h * sub) as f32);
        let expected: Vec<f64> = (0..w * h)
            .map(|k| {
                let (i, j) = (k % w, k / w);
                let mut p = 0.0f64;
                for b in 0..sub {
                    let theta = (j * sub + b) as f32 * dtheta + 0.5 * dtheta;
                    for a in 0..sub {
                        let u = ((i * sub + a) as f32 + 0.5) / (w * sub) as f32;
                        let phi = TAU * (u - 0.5) - rot.to_radians();
                        p +=
                            f64::from(env.pdf(direction(theta, phi)) * theta.sin() * dtheta * dphi);
                    }
                }
                p * n as f64
            })
            .collect();
        let (chi, dof) = chi_square(&counts, &expected);
        assert!(
            chi < chi_square_threshold(dof),
            "{interpolation:?}: χ² {chi}, {dof} dof"
        );
        assert!(
            on_edges < n / 10_000,
            "{on_edges} samples whose pdf() differs"
        );
        if interpolation == Interpolation::Nearest {
            // A black texel is never sampled under nearest lookup.
            for (k, t) in texels.iter().enumerate() {
                if *t == Vec3::ZERO {
                    assert_eq!(counts[k], 0);
                }
            }
        }
    }
}

/// A 16 × 8 map of a smooth gradient with three bright texels (one saturated blue), in
/// [`EnvImage`] form.
fn lamps_on_a_gradient() -> EnvImage {
    let (w, h) = (16usize, 8usize);
    let texels = (0..w * h)
        .map(|k| {
            let (i, j) = (k % w, k / w);
            match (i, j) {
                (3, 2) => Vec3::splat(400.0),
                (11, 5) => Vec3::new(0.0, 0.0, 600.0),
                (15, 4) => Vec3::new(200.0, 150.0, 100.0),
                _ => Vec3::splat(0.2 + (i as f32 + 2.0 * j as f32) / 40.0),
            }
        })
        .collect();
    EnvImage {
        width: w,
        height: h,
        texels,
    }
}

/// The χ² quantile at 1 − 1e-4 (Wilson–Hilferty).
fn chi_square_threshold_1e4(dof: usize) -> f64 {
    let k = dof.max(1) as f64;
    let z = 3.719_016; // standard normal quantile at 1 − 1e-4
    k * (1.0 - 2.0 / (9.0 * k) + z * (2.0 / (9.0 * k)).sqrt()).powi(3)
}

/// The supersampled distribution of bilinear lookup: the density of its samples, binned at
/// its own cells ([`SUPERSAMPLING`] per texel along each axis), equals `pdf()` (χ² at p < 1e-4), the density integrates
/// to 1, and it follows the lookup: the channel average of the radiance over the density,
/// `c(L)/p`, varies across a bright texel's tent (where the tent is above 10 %) far less than
/// with one cell per texel (measured with 2 × 2 cells: 10.5× against 43.6×; asserted: by a
/// factor 1.5).
#[test]
fn supersampled_distribution_matches_its_samples_and_the_lookup() {
    let image = lamps_on_a_gradient();
    let (w, h) = (image.width, image.height);
    let rot = 0.0;
    let env = EnvironmentLight::from_image(image.clone(), &EnvOptions::default()).unwrap();
    let cells = SUPERSAMPLING;
    assert!((integrate_pdf(&env, w, h, cells, rot) - 1.0).abs() < 1e-3);
    let (sw, sh) = (w * cells, h * cells);
    let n = 2_000_000u64;
    let mut rng = Pcg64::seed_from_u64(11);
    let mut counts = vec![0u64; sw * sh];
    for _ in 0..n {
        let s = env.sample(Vec2::new(rng.random(), rng.random())).unwrap();
        let (u, v) = expected_uv(s.wi, rot);
        let a = ((u * sw as f32) as usize).min(sw - 1);
        let b = ((v * sh as f32) as usize).min(sh - 1);
        counts[b * sw + a] += 1;
    }
    // Expected counts: N ∫_cell pdf dω, the midpoint rule on 2 × 2 points per cell (exact:
    // pdf · sin θ is constant on a cell).
    let sub = 2;
    let (dphi, dtheta) = (TAU / (sw * sub) as f32, PI / (sh * sub) as f32);
    let expected: Vec<f64> = (0..sw * sh)
        .map(|k| {
            let (a, b) = (k % sw, k / sw);
            let mut p = 0.0f64;
            for y in 0..sub {
                let theta = ((b * sub + y) as f32 + 0.5) * dtheta;
                for x in 0..sub {
                    let u = ((a * sub + x) as f32 + 0.5) / (sw * sub) as f32;
                    let phi = TAU * (u - 0.5) - rot;
                    p += f64::from(env.pdf(direction(theta, phi)) * theta.sin() * dtheta * dphi);
                }
            }
            p * n as f64
        })
        .collect();
    let (chi, dof) = chi_square(&counts, &expected);
    assert!(chi < chi_square_threshold_1e4(dof), "χ² {chi}, {dof} dof");

    // L/p over the 3 × 3 texels around the isolated white lamp (3, 2), at 24 × 24 points per
    // texel, with each distribution.
    let spread = |env: &EnvironmentLight| {
        let (mut lo, mut hi) = (f32::INFINITY, 0.0f32);
        for y in 0..72 {
            for x in 0..72 {
                let u = (2.0 + (x as f32 + 0.5) / 24.0) / w as f32;
                let v = (1.0 + (y as f32 + 0.5) / 24.0) / h as f32;
                let d = direction(PI * v, TAU * (u - 0.5));
                let (l, p) = env.radiance_and_pdf(d);
                let c = (l.x + l.y + l.z) / 3.0;
                // Only where the lamp dominates the gradient (its tent above 10 %).
                if c > 40.0 {
                    let ratio = c / (p * (PI * v).sin());
                    lo = lo.min(ratio);
                    hi = hi.max(ratio);
                }
            }
        }
        hi / lo
    };
    let per_texel = EnvironmentLight::from_image(
        image,
        &EnvOptions {
            cells_per_texel: Some(1),
            ..EnvOptions::default()
        },
    )
    .unwrap();
    let (fine, coarse) = (spread(&env), spread(&per_texel));
    println!("c(L)/p across the lamp's tent: per texel {coarse}×, supersampled {fine}×");
    assert!(
        coarse > 1.5 * fine,
        "per texel {coarse}× vs supersampled {fine}×"
    );
}

/// Channel-average weights: a saturated blue lamp gets the share of samples its blue channel
/// asks for, not the share its luminance (7 % of blue's) would give it.
#[test]
fn a_saturated_lamp_is_sampled_by_its_channel_average() {
    let image = lamps_on_a_gradient();
    let env = EnvironmentLight::from_image(image, &EnvOptions::default()).unwrap();
    let mut rng = Pcg64::seed_from_u64(12);
    let (n, mut blue, mut white) = (200_000, 0u32, 0u32);
    for _ in 0..n {
        let s = env.sample(Vec2::new(rng.random(), rng.random())).unwrap();
        let (u, v) = expected_uv(s.wi, 0.0);
        let (i, j) = ((u * 16.0) as usize, (v * 8.0) as usize);
        blue += u32::from((i, j) == (11, 5));
        white += u32::from((i, j) == (3, 2));
    }
    // The blue lamp's channel average (200) is half the white one's (400); luminance would
    // make it 0.072 × 600 = 43, about a ninth. Rows 2 and 5 have the same sin θ (0.83).
    let ratio = blue as f64 / white as f64;
    assert!((0.35..0.65).contains(&ratio), "blue/white samples {ratio}");
}

#[test]
fn a_single_bright_texel_lights_a_plane_like_a_directional_light() {
    let (w, h) = (64usize, 32usize);
    let (i0, j0) = (40usize, 10usize);
    let l = 100.0f32;
    let image = EnvImage {
        width: w,
        height: h,
        texels: (0..w * h)
            .map(|k| {
                if k == j0 * w + i0 {
                    Vec3::splat(l)
                } else {
                    Vec3::ZERO
                }
            })
            .collect(),
    };
    let dphi = TAU / w as f32;
    let (t0, t1) = (PI * j0 as f32 / h as f32, PI * (j0 + 1) as f32 / h as f32);
    let solid_angle = dphi * (t0.cos() - t1.cos());
    let centre = direction(
        PI * (j0 as f32 + 0.5) / h as f32,
        TAU * ((i0 as f32 + 0.5) / w as f32 - 0.5),
    );
    for interpolation in [Interpolation::Nearest, Interpolation::Bilinear] {
        let env = EnvironmentLight::from_image(
            image.clone(),
            &EnvOptions {
                interpolation,
                ..EnvOptions::default()
            },
        )
        .unwrap();
        let mut rng = Pcg64::seed_from_u64(9);
        for normal in [Vec3::Y, Vec3::new(1.0, 1.0, 0.3).normalize()] {
            let mut values = Vec::new();
            for _ in 0..20_000 {
                let s = env.sample(Vec2::new(rng.random(), rng.random())).unwrap();
                let (u, v) = expected_uv(s.wi, 0.0);
                let (i, j) = ((u * w as f32) as i64, (v * h as f32) as i64);
                match interpolation {
                    // Every sample lands in the texel...
                    Interpolation::Nearest => assert_eq!((i, j), (i0 as i64, j0 as i64)),
                    // ... or, bilinear, where the texel's tent reaches: its 3 × 3 neighbourhood.
                    Interpolation::Bilinear => {
                        assert!((i - i0 as i64).abs() <= 1 && (j - j0 as i64).abs() <= 1)
                    }
                }
                values.push(f64::from(s.radiance.x * normal.dot(s.wi).max(0.0) / s.pdf));
            }
            let (mean, err) = mean_and_error(&values);
            // The directional light of the same power: E = L Ω cos θ at the texel centre,
            // exact to O(texel²) (here ≈ 0.3 %); allow 1 %.
            let directional = f64::from(l * solid_angle * normal.dot(centre));
            assert!(
                (mean - directional).abs() < 0.01 * directional + 4.0 * err,
                "{interpolation:?} n {normal}: E {mean} ± {err}, directional {directional}"
            );
            if interpolation == Interpolation::Nearest && normal == Vec3::Y {
                // Exact: ∫_texel L cos θ dω = L Δφ (sin²θ₁ − sin²θ₀)/2; 4 standard errors.
                let exact = f64::from(l * dphi * (t1.sin().powi(2) - t0.sin().powi(2)) / 2.0);
                assert!(
                    (mean - exact).abs() < 4.0 * err + 1e-6 * exact,
                    "{mean} ± {err} vs {exact}"
                );
            }
        }
    }
}

#[test]
fn dwab_exr_decodes_to_the_same_texels_as_the_zip_exr() {
    let dwab = read_env_image(&shared("studio-dwab.exr"), u64::MAX).unwrap();
    let zip = read_env_image(&shared("studio.exr"), u64::MAX).unwrap();
    assert_eq!((dwab.width, dwab.height), (zip.width, zip.height));
    let worst = dwab
        .texels
        .iter()
        .zip(&zip.texels)
        .map(|(a, b)| ((*a - *b).abs() / b.max(Vec3::splat(1e-3))).max_element())
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-5, "largest relative difference {worst}");
}

#[test]
fn hdr_and_exr_of_the_same_map_agree() {
    // RGBE keeps 8-bit mantissas: within 0.4 % of a pixel's largest channel, so the averages
    // agree to well under 1 %.
    let a = EnvironmentLight::from_file(&shared("studio.hdr"), 1.0, 0.0).unwrap();
    let b = EnvironmentLight::from_file(&shared("studio.exr"), 1.0, 0.0).unwrap();
    let (ma, mb) = (a.average_radiance(), b.average_radiance());
    assert!(((ma - mb) / mb).abs().max_element() < 5e-3, "{ma} vs {mb}");
}

#[test]
fn bad_files_are_errors_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    // Over the pixel budget, refused before decoding.
    let err = EnvironmentLight::from_file_with(
        &shared("studio.exr"),
        &EnvOptions {
            pixel_budget: 1000,
            ..EnvOptions::default()
        },
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            EnvironmentError::TooLarge {
                width: 1024,
                height: 512,
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("studio.exr"));
    // Not an image.
    let text = dir.path().join("notes.hdr");
    std::fs::write(&text, "hello").unwrap();
    let err = EnvironmentLight::from_file(&text, 1.0, 0.0).unwrap_err();
    assert!(matches!(err, EnvironmentError::UnknownFormat { .. }));
    assert!(err.to_string().contains("notes.hdr"));
    // Missing.
    let err = EnvironmentLight::from_file(&dir.path().join("nope.exr"), 1.0, 0.0).unwrap_err();
    assert!(matches!(err, EnvironmentError::Io { .. }));
    // Truncated EXR.
    let bytes = std::fs::read(shared("studio.exr")).unwrap();
    let cut = dir.path().join("cut.exr");
    std::fs::write(&cut, &bytes[..bytes.len() / 3]).unwrap();
    let err = EnvironmentLight::from_file(&cut, 1.0, 0.0).unwrap_err();
    assert!(err.to_string().contains("cut.exr"), "{err}");
    // A NaN texel is refused, naming its position; negative channels are clamped to 0.
    let nan = dir.path().join("nan.exr");
    write_exr(&nan, 8, 4, |x, y| {
        if (x, y) == (5, 2) {
            Vec3::new(f32::NAN, 1.0, 1.0)
        } else {
            Vec3::ONE
        }
    });
    let err = EnvironmentLight::from_file(&nan, 1.0, 0.0).unwrap_err();
    assert!(
        matches!(
            err,
            EnvironmentError::NonFinite {
                count: 1,
                x: 5,
                y: 2,
                ..
            }
        ),
        "{err}"
    );
    let neg = dir.path().join("neg.exr");
    write_exr(&neg, 8, 4, |_, _| Vec3::new(-0.5, 2.0, -1e-4));
    let env = EnvironmentLight::from_file(&neg, 1.0, 0.0).unwrap();
    assert_eq!(env.radiance(Vec3::X), Vec3::new(0.0, 2.0, 0.0));
    // A bad strength.
    assert!(matches!(
        EnvironmentLight::from_file(&neg, f32::NAN, 0.0),
        Err(EnvironmentError::Parameter { .. })
    ));
}

/// The light-sample estimator alone (issue 23's numeric check): irradiance on a plane facing
/// a map of square lamps 1 to 5 texels wide, `c(L) cos θ / p` per sample, with the
/// supersampled distribution against one cell per texel. Both are unbiased (their means
/// agree within 4σ); the supersampled one has the lower variance, by the factor printed
/// (`cargo test --test transport -- environment:: --nocapture`).
#[test]
fn supersampling_lowers_the_light_sample_variance_on_small_lamps() {
    let (w, h) = (64usize, 32usize);
    for side in 1..=5usize {
        let texels: Vec<Vec3> = (0..w * h)
            .map(|k| {
                let (i, j) = (k % w, k / w);
                if (20..20 + side).contains(&i) && (8..8 + side).contains(&j) {
                    Vec3::splat(500.0)
                } else {
                    Vec3::splat(0.05)
                }
            })
            .collect();
        let image = EnvImage {
            width: w,
            height: h,
            texels,
        };
        let normal = direction(
            PI * (8.0 + side as f32 / 2.0) / h as f32,
            TAU * ((20.0 + side as f32 / 2.0) / w as f32 - 0.5),
        );
        let estimate = |cells: usize| {
            let env = EnvironmentLight::from_image(
                image.clone(),
                &EnvOptions {
                    cells_per_texel: Some(cells),
                    ..EnvOptions::default()
                },
            )
            .unwrap();
            let mut rng = Pcg64::seed_from_u64(side as u64);
            let values: Vec<f64> = (0..200_000)
                .map(|_| {
                    let s = env.sample(Vec2::new(rng.random(), rng.random())).unwrap();
                    let c = (s.radiance.x + s.radiance.y + s.radiance.z) / 3.0;
                    f64::from(c * normal.dot(s.wi).max(0.0) / s.pdf)
                })
                .collect();
            let (mean, err) = mean_and_error(&values);
            (mean, err * err * values.len() as f64)
        };
        let ((m1, v1), (m2, v2), (m4, v4)) = (estimate(1), estimate(2), estimate(4));
        for (m, cells) in [(m2, 2), (m4, 4)] {
            let sigma = ((v1 + v2.max(v4)) / 200_000.0).sqrt();
            assert!(
                (m1 - m).abs() < 4.0 * sigma,
                "{side}: {m1} vs {m} ({cells}×{cells}) ± {sigma}"
            );
        }
        println!(
            "lamp {side}×{side} texels: variance per sample, 1 cell/texel {v1:.4e}, 2×2 cells \
             {v2:.4e} ({:.2}× lower), 4×4 cells {v4:.4e} ({:.2}× lower)",
            v1 / v2,
            v1 / v4
        );
        assert!(v2 < v1, "{side}: 2×2 cells {v2} vs per texel {v1}");
        assert!(v4 < v2, "{side}: 4×4 cells {v4} vs 2×2 {v2}");
    }
}

/// Unit directions of the pixel centres of a `w × h` pinhole frame looking along `forward`
/// (vertical field of view `fov_deg`), row by row.
fn frame_directions(w: usize, h: usize, forward: Vec3, fov_deg: f32) -> Vec<Vec3> {
    let f = forward.normalize();
    let helper = if f.y.abs() > 0.9 { Vec3::X } else { Vec3::Y };
    let right = f.cross(helper).normalize();
    let up = right.cross(f);
    let tan = (fov_deg.to_radians() * 0.5).tan();
    let aspect = w as f32 / h as f32;
    let mut dirs = Vec::with_capacity(w * h);
    for j in 0..h {
        for i in 0..w {
            let sx = (2.0 * (i as f32 + 0.5) / w as f32 - 1.0) * tan * aspect;
            let sy = (1.0 - 2.0 * (j as f32 + 0.5) / h as f32) * tan;
            dirs.push((f + right * sx + up * sy).normalize());
        }
    }
    dirs
}

/// Unit directions of a `w × h` panoramic frame covering the whole sphere, its pixel centres
/// offset from the map's texel centres.
fn panorama_directions(w: usize, h: usize) -> Vec<Vec3> {
    let mut dirs = Vec::with_capacity(w * h);
    for j in 0..h {
        for i in 0..w {
            let theta = PI * (j as f32 + 0.37) / h as f32;
            let phi = TAU * ((i as f32 + 0.61) / w as f32 - 0.5);
            dirs.push(direction(theta, phi));
        }
    }
    dirs
}

/// Largest per-channel difference between horizontally or vertically adjacent texels of the
/// 4 × 4 texels around the bilinear patch that holds `uv` (u wrapping, v clamped): a bound on
/// how fast the bilinear lookup changes there, per texel of movement along either axis.
fn local_slope(image: &EnvImage, uv: Vec2) -> f32 {
    let (w, h) = (image.width as i64, image.height as i64);
    let x0 = (uv.x * w as f32 - 0.5).floor() as i64;
    let y0 = (uv.y * h as f32 - 0.5).floor() as i64;
    let at = |i: i64, j: i64| image.texels[(j.clamp(0, h - 1) * w + i.rem_euclid(w)) as usize];
    let mut slope = 0.0f32;
    for j in y0 - 1..=y0 + 2 {
        for i in x0 - 1..=x0 + 2 {
            slope = slope.max((at(i + 1, j) - at(i, j)).abs().max_element());
            slope = slope.max((at(i, j + 1) - at(i, j)).abs().max_element());
        }
    }
    slope
}

/// The mapping every lookup uses (polynomial atan2) against the exact one (f64 `atan2`), on
/// every pixel of 1280 × 720 frames: u within `MAX_ERROR/2π` plus rounding (modulo 1), v within `MAX_ERROR/π`
/// plus rounding, and the radiance within that movement times the lookup's local slope (plus
/// f32 rounding of the blend). Frames: the whole sphere, the horizon across the seam (−X),
/// straight up at the pole, and straight down at the other.
fn exact_uv(d: Vec3, rotation_deg: f32) -> Vec2 {
    let (x, y, z) = (f64::from(d.x), f64::from(d.y), f64::from(d.z));
    let rotation = f64::from(rotation_deg.to_radians());
    let u = (0.5 + (z.atan2(x) + rotation) / std::f64::consts::TAU).rem_euclid(1.0);
    let v = (x * x + z * z).sqrt().atan2(y) / std::f64::consts::PI;
    let below_one = 1.0 - f64::from(f32::EPSILON) / 2.0;
    Vec2::new(u.min(below_one) as f32, v.clamp(0.0, below_one) as f32)
}

fn assert_mapping_within_bound(name: &str, image: EnvImage, rotation_deg: f32) {
    use glint::light::environment::FAST_ANGLE_MAX_ERROR;
    // Rounding of the f32 scalings on top of the polynomial's bound.
    let du_bound = FAST_ANGLE_MAX_ERROR / TAU + 2.0e-7;
    let dv_bound = FAST_ANGLE_MAX_ERROR / PI + 2.0e-7;
    let env = EnvironmentLight::from_image(
        image.clone(),
        &EnvOptions {
            rotation_deg,
            ..EnvOptions::default()
        },
    )
    .unwrap();
    let (w, h) = (image.width as f32, image.height as f32);
    let frames = [
        ("panorama", panorama_directions(1280, 720)),
        ("seam", frame_directions(1280, 720, -Vec3::X, 60.0)),
        ("north pole", frame_directions(1280, 720, Vec3::Y, 60.0)),
        ("south pole", frame_directions(1280, 720, -Vec3::Y, 60.0)),
    ];
    let (mut worst_du, mut worst_dv, mut worst_ratio) = (0.0f32, 0.0f32, 0.0f32);
    for (frame, dirs) in &frames {
        for (k, &d) in dirs.iter().enumerate() {
            let (exact, fast) = (exact_uv(d, rotation_deg), env.direction_to_uv(d));
            let du = (fast.x - exact.x).abs();
            let du = du.min(1.0 - du);
            let dv = (fast.y - exact.y).abs();
            assert!(
                du <= du_bound && dv <= dv_bound,
                "{name}, {frame} pixel {k}: uv {fast} vs {exact}"
            );
            worst_du = worst_du.max(du);
            worst_dv = worst_dv.max(dv);
            let (l_exact, l_fast) = (env.radiance_at(exact), env.radiance(d));
            let moved = du_bound * w + dv_bound * h;
            let bound = moved * local_slope(&image, exact) + 1e-6 * l_exact.max_element();
            let diff = (l_fast - l_exact).abs().max_element();
            assert!(
                diff <= bound,
                "{name}, {frame} pixel {k} ({d}): {l_fast} vs {l_exact}, bound {bound}"
            );
            if bound > 0.0 {
                worst_ratio = worst_ratio.max(diff / bound);
            }
        }
    }
    eprintln!(
        "{name}: worst |Δu| {worst_du:e}, |Δv| {worst_dv:e}, radiance at {:.3} of its bound",
        worst_ratio
    );
}

#[test]
fn the_environment_mapping_is_within_its_bound_under_studio() {
    let image = read_env_image(&shared("studio.exr"), u64::MAX).unwrap();
    assert_mapping_within_bound("studio.exr", image.clone(), 0.0);
    assert_mapping_within_bound("studio.exr rotated 250°", image, 250.0);
}

/// A dim map with a one-texel-wide bright column on each side of the seam's wrap (the last
/// column) and a bright top row (the pole): where a small error in u or v moves the lookup
/// the most.
#[test]
fn the_environment_mapping_is_within_its_bound_on_bright_lines_at_the_seam_and_pole() {
    for (w, h) in [(64, 32), (4096, 2048)] {
        let texels = (0..w * h)
            .map(|k| {
                let (i, j) = (k % w, k / w);
                if i == w - 1 || j == 0 {
                    Vec3::new(1000.0, 800.0, 600.0)
                } else {
                    Vec3::splat(0.01)
                }
            })
            .collect();
        let image = EnvImage {
            width: w,
            height: h,
            texels,
        };
        assert_mapping_within_bound(&format!("lines {w}×{h}"), image, 0.0);
    }
}
