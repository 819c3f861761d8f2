//! White furnace for the glTF metallic-roughness material (issue 22): a white sphere (base
//! colour 1) under a uniform environment of radiance 1 reflects exactly 1 wherever it is seen,
//! when the BRDF conserves energy. Rendered with the path tracer (≥ 32 bounces, Russian
//! roulette on) at roughness 0.25, 0.5 and 1 for metallic 1 and metallic 0, on every backend:
//! the mean over the sphere's pixels must be 1 within 1 %, and every ring from centre to rim
//! (equal widths in the disc's radius; the last ring sees the surface at grazing angles) within
//! 2 %. Non-convex: two touching rough-metal spheres on a metal slab, where light bounces
//! many times between the surfaces, render every 8×8 block within 3 % of 1. With
//! `BrdfModel::Spec`, glTF's Appendix B taken literally, the rough metal sphere
//! must be clearly darker: single-scatter GGX loses the light that bounces between microfacets,
//! which proves the option changes the model.

use crate::support::{Furnace, look_at, ortho, quad, scene, white_furnace};
use glam::{Vec2, Vec3, Vec4};
use glint::accel::BackendKind;
use glint::bsdf::SheenBsdf;
use glint::bsdf::sheen::{directional_albedo, sheen_albedo};
use glint::render::{BrdfModel, Image};
use glint::scene::layers::{
    Anisotropy, Clearcoat, DiffuseTransmission, Sheen, Transmission, Volume,
};
use glint::scene::{Material, Mesh};

/// Image side in pixels; the sphere's disc spans `SIZE · RADIUS_IN_VIEW` of it.
const SIZE: u32 = 48;
/// Half the orthographic view's width over the sphere's radius.
const VIEW: f32 = 1.05;
/// Rings from centre to rim, and the share of the radius they cover (pixels farther out may
/// straddle the silhouette, where the tessellation's flat facets show).
const RINGS: usize = 6;
const RIM: f64 = 0.97;

/// A UV sphere of radius 1 around the origin with smooth vertex normals.
fn sphere(material: usize) -> Mesh {
    let (stacks, slices) = (96u32, 192u32);
    let mut positions = Vec::new();
    for i in 0..=stacks {
        let theta = std::f32::consts::PI * i as f32 / stacks as f32;
        for j in 0..=slices {
            let phi = std::f32::consts::TAU * j as f32 / slices as f32;
            positions.push(Vec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ));
        }
    }
    let row = slices + 1;
    let mut indices = Vec::new();
    for i in 0..stacks {
        for j in 0..slices {
            let (a, b) = (i * row + j, i * row + j + 1);
            let (c, d) = (a + row, b + row);
            if i > 0 {
                indices.push([a, c, b]);
            }
            if i + 1 < stacks {
                indices.push([b, c, d]);
            }
        }
    }
    Mesh {
        name: "sphere".into(),
        normals: Some(positions.clone()),
        positions,
        indices,
        material,
        ..Mesh::default()
    }
}

fn white(metallic: f32, roughness: f32) -> Material {
    Material {
        name: "white".into(),
        base_color: Vec4::ONE,
        metallic,
        roughness,
        ..Material::default()
    }
}

/// A white sphere of rough glass: KHR_materials_transmission 1 with a volume (so rays bend
/// and the inside is glass of index `ior`), no attenuation.
fn glass(ior: f32, roughness: f32) -> Material {
    Material {
        name: "glass".into(),
        ior,
        transmission: Some(Transmission {
            factor: 1.0,
            texture: None,
        }),
        volume: Some(Volume {
            thickness: 1.0,
            attenuation_color: Vec3::ONE,
            attenuation_distance: f32::INFINITY,
        }),
        ..white(0.0, roughness)
    }
}

/// The mean over the sphere's pixels and per ring, by backend.
fn furnace(material: Material, brdf: BrdfModel, backend: BackendKind, spp: u32) -> (f64, Vec<f64>) {
    let (mean, rings, _) = furnace_with_noise(material, brdf, backend, spp, 32);
    (mean, rings)
}

/// [`furnace`] with a path depth and the rings' standard errors (the spread of their pixels
/// over the square root of their count: every pixel of a furnace sphere has the same
/// expectation, or one that changes little across a ring, so this bounds the noise).
fn furnace_with_noise(
    material: Material,
    brdf: BrdfModel,
    backend: BackendKind,
    spp: u32,
    max_depth: u32,
) -> (f64, Vec<f64>, Vec<f64>) {
    let image = furnace_image(material, brdf, backend, spp, max_depth);
    let value =
        |x: u32, y: u32| f64::from(image.pixels[(y * SIZE + x) as usize].dot(Vec3::ONE)) / 3.0;
    let (mean, rings) = disc_statistics(value);
    let (_, squares) = disc_statistics(|x, y| value(x, y) * value(x, y));
    let mut n = [0usize; RINGS];
    for y in 0..SIZE {
        for x in 0..SIZE {
            if let Some(r) = disc_radius(x, y) {
                n[(((r / RIM) * RINGS as f64) as usize).min(RINGS - 1)] += 1;
            }
        }
    }
    let se = rings
        .iter()
        .zip(&squares)
        .zip(n)
        .map(|((m, m2), n)| ((m2 - m * m).max(0.0) / n.max(1) as f64).sqrt())
        .collect();
    (mean, rings, se)
}

/// The sphere's pixels: `value(x, y)` averaged over the disc (pixel centres inside
/// [`RIM`]) and over each of [`RINGS`] rings.
fn disc_statistics(value: impl Fn(u32, u32) -> f64) -> (f64, Vec<f64>) {
    let (mut sum, mut count) = (0.0, 0usize);
    let mut rings = [(0.0, 0usize); RINGS];
    for y in 0..SIZE {
        for x in 0..SIZE {
            let Some(r) = disc_radius(x, y) else {
                continue;
            };
            let v = value(x, y);
            sum += v;
            count += 1;
            let ring = ((r / RIM) * RINGS as f64) as usize;
            rings[ring.min(RINGS - 1)].0 += v;
            rings[ring.min(RINGS - 1)].1 += 1;
        }
    }
    let rings = rings.iter().map(|&(s, n)| s / n.max(1) as f64).collect();
    (sum / count as f64, rings)
}

/// The pixel centre's distance from the disc's centre in sphere radii, when below [`RIM`].
fn disc_radius(x: u32, y: u32) -> Option<f64> {
    let c = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) / SIZE as f32 * 2.0 - Vec2::ONE;
    let r = f64::from(c.length() * VIEW);
    (r < RIM).then_some(r)
}

/// The rendered furnace image of the sphere, by backend.
fn furnace_image(
    material: Material,
    brdf: BrdfModel,
    backend: BackendKind,
    spp: u32,
    max_depth: u32,
) -> Image<Vec3> {
    let scene = scene(vec![sphere(0)], vec![material], vec![]);
    let camera = ortho(Vec3::new(0.0, -4.0, 0.3), Vec3::ZERO, Vec3::Z, VIEW, VIEW);
    let furnace = Furnace {
        size: SIZE,
        spp,
        seed: 7,
        max_depth,
        brdf,
    };
    white_furnace(&scene, &camera, backend, &furnace)
}

#[test]
fn white_spheres_reflect_the_furnace_exactly() {
    for &backend in BackendKind::available() {
        for metallic in [1.0, 0.0] {
            for roughness in [0.25, 0.5, 1.0] {
                let (mean, rings) = furnace(
                    white(metallic, roughness),
                    BrdfModel::Compensated,
                    backend,
                    64,
                );
                let what = format!("{backend}, metallic {metallic}, roughness {roughness}");
                eprintln!("{what}: mean {mean:.4}, rings {rings:.4?}");
                assert!((mean - 1.0).abs() <= 0.01, "{what}: sphere mean {mean}");
                for (i, r) in rings.iter().enumerate() {
                    assert!((r - 1.0).abs() <= 0.02, "{what}: ring {i} of {RINGS} = {r}");
                }
            }
        }
    }
}

/// Appendix B taken literally loses light on rough metal: the option really switches the
/// model (the same sphere renders at 1 with the default). The dielectric is printed too (the
/// spec's mix gains a little at grazing angles and loses to masking elsewhere).
#[test]
fn the_spec_brdf_loses_energy_on_rough_metal() {
    for &backend in BackendKind::available() {
        for metallic in [1.0, 0.0] {
            for roughness in [0.25, 0.5, 1.0] {
                let (mean, rings) =
                    furnace(white(metallic, roughness), BrdfModel::Spec, backend, 16);
                eprintln!(
                    "spec, {backend}, metallic {metallic}, roughness {roughness}: mean {mean:.4}, rings {rings:.4?}"
                );
                let bound = match (metallic, roughness) {
                    (1.0, 1.0) => 0.8,
                    (1.0, 0.5) => 0.97,
                    _ => continue,
                };
                assert!(
                    mean < bound,
                    "{backend}, roughness {roughness}: spec white metal {mean}, expected below {bound}"
                );
            }
        }
    }
}

/// Rough glass (KHR_materials_transmission with a volume, ior 1.5) in the furnace:
/// light refracts into the sphere, bounces inside (total internal reflection included) and
/// leaves; with the compensated interface reflection plus transmission is 1 at every
/// interaction, so the sphere shows exactly the environment (radiance 1 outside, η² inside,
/// which the radiance scaling of refraction turns back into 1): mean within 1 %, rings within
/// 2 %, and each ring's standard error at most a quarter of that (4σ). Paths may bounce 256
/// times: at roughness 0.25 (and more so at higher indices) rays near the rim refract to just inside
/// the critical angle and, once a tilted microfacet reflects them totally, circle inside
/// the sphere by total internal reflection for tens of bounces (at depth 32 the rim ring read
/// 0.976, at 512 1.000). Single scattering (`spec`) loses light at every interaction.
#[test]
fn rough_glass_spheres_reflect_and_transmit_the_furnace_exactly() {
    let mut failures = Vec::new();
    for &backend in BackendKind::available() {
        for (ior, roughness, spp) in [
            (1.5, 0.0, 64),
            (1.5, 0.25, 128),
            (1.5, 0.5, 128),
            (1.5, 1.0, 768),
        ] {
            let (mean, rings, se) = furnace_with_noise(
                glass(ior, roughness),
                BrdfModel::Compensated,
                backend,
                spp,
                256,
            );
            let what = format!("{backend}, glass ior {ior}, roughness {roughness}, {spp} spp");
            eprintln!("{what}: mean {mean:.4}, rings {rings:.4?} ± {se:.4?}");
            if (mean - 1.0).abs() > 0.01
                || rings.iter().any(|r| (r - 1.0).abs() > 0.02)
                || se.iter().any(|&e| 4.0 * e > 0.02)
            {
                failures.push(what);
            }
        }
        let (spec, rings) = furnace(glass(1.5, 1.0), BrdfModel::Spec, backend, 16);
        eprintln!("spec, {backend}, glass ior 1.5, roughness 1: mean {spec:.4}, rings {rings:.4?}");
        if spec > 0.5 {
            failures.push(format!(
                "{backend}: single-scatter rough glass at {spec}, expected below 0.5"
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "not 1 within 1 % (mean) and 2 % (rings, 4σ): {failures:?}"
    );
}

/// A clear coat (KHR_materials_clearcoat, factor 1, roughness 0.3 and 1) over a white
/// compensated base (metal and dielectric, roughness 0.5): the coat takes `Fc(n·wo)` and
/// reflects it (its lobe compensated by `1/E0`), the base reflects the rest, so the sphere is
/// 1 within the statistics (1 % mean, 2 % rings, as the bare spheres).
/// [`sphere`] with tangents along its parallels, `(−sin φ, cos φ, 0)` (zero at the poles,
/// where the frame falls back to isotropic shading), as KHR_materials_anisotropy needs.
fn sphere_with_tangents(material: usize) -> Mesh {
    let mut mesh = sphere(material);
    let tangents = mesh
        .positions
        .iter()
        .map(|p| Vec3::new(-p.y, p.x, 0.0).normalize_or_zero().extend(1.0))
        .collect();
    mesh.tangents = Some(tangents);
    mesh
}

/// KHR_materials_anisotropy in the white furnace (issue 35): white metal and white
/// dielectric at roughness 0.3 and 0.6, strength 0, 0.5 and 1, on every backend. The
/// compensated lobes read their own albedo table (no isotropic roughness holds the furnace at
/// strength 1, see `bsdf::anisotropic_albedo`): the sphere's mean is 1 within 1 % and every
/// ring within 2 % (4σ of the rings' noise below 2 %).
#[test]
fn anisotropic_white_spheres_reflect_the_furnace_exactly() {
    let mut failures = Vec::new();
    for &backend in BackendKind::available() {
        for metallic in [1.0, 0.0] {
            for roughness in [0.3, 0.6] {
                for strength in [0.0, 0.5, 1.0] {
                    let material = Material {
                        anisotropy: Some(Anisotropy {
                            strength,
                            rotation: 0.4,
                            texture: None,
                        }),
                        ..white(metallic, roughness)
                    };
                    let scene = scene(vec![sphere_with_tangents(0)], vec![material], vec![]);
                    let camera = ortho(Vec3::new(0.0, -4.0, 0.3), Vec3::ZERO, Vec3::Z, VIEW, VIEW);
                    let furnace = Furnace {
                        size: SIZE,
                        spp: 64,
                        seed: 7,
                        max_depth: 32,
                        brdf: BrdfModel::Compensated,
                    };
                    let image = white_furnace(&scene, &camera, backend, &furnace);
                    let value = |x: u32, y: u32| {
                        f64::from(image.pixels[(y * SIZE + x) as usize].dot(Vec3::ONE)) / 3.0
                    };
                    let (mean, rings) = disc_statistics(value);
                    let what = format!(
                        "{backend}, metallic {metallic}, roughness {roughness}, anisotropy {strength}"
                    );
                    eprintln!("{what}: mean {mean:.4}, rings {rings:.4?}");
                    if (mean - 1.0).abs() > 0.01 || rings.iter().any(|r| (r - 1.0).abs() > 0.02) {
                        failures.push(format!("{what}: mean {mean:.4}, rings {rings:.4?}"));
                    }
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "not 1 within 1 % (mean) and 2 % (rings): {failures:?}"
    );
}

/// Rough glass of `ior` exactly 1 (issue 35): every microfacet passes light straight on, so
/// the sphere is invisible in the furnace and reads 1 on both models. Before, the half vector
/// of `wi = −wo` was zero, every rough draw was rejected and the sphere read 0.
#[test]
fn rough_glass_of_ior_one_passes_the_furnace_straight_through() {
    let mut failures = Vec::new();
    for &backend in BackendKind::available() {
        for brdf in [BrdfModel::Compensated, BrdfModel::Spec] {
            for roughness in [0.5, 1.0] {
                let (mean, rings, se) =
                    furnace_with_noise(glass(1.0, roughness), brdf, backend, 16, 32);
                let what = format!("{backend}, {brdf}, glass ior 1, roughness {roughness}");
                eprintln!("{what}: mean {mean:.4}, rings {rings:.4?} ± {se:.4?}");
                if (mean - 1.0).abs() > 0.01 || rings.iter().any(|r| (r - 1.0).abs() > 0.02) {
                    failures.push(what);
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "not 1 within 1 % (mean) and 2 % (rings): {failures:?}"
    );
}

/// KHR_materials_diffuse_transmission in the white furnace (issue 35): a white dielectric
/// sphere (roughness 0.5) whose diffuse base transmits a share `t` = 0.5 and 1 with a white
/// colour, thin-walled, and at `t` = 1 also as the boundary of a clear KHR_materials_volume.
/// Light passes into the sphere, bounces diffusely inside and leaves; the compensated lobe
/// pair sends on exactly what the reflection-only base reflected, so the sphere reads 1:
/// mean within 1 %, every ring within 2 % (each ring's standard error at most a quarter of
/// that, 4σ), on both models' shared conserving case (compensated) and every backend.
#[test]
fn diffusely_transmitting_white_spheres_hold_the_furnace() {
    let mut failures = Vec::new();
    for &backend in BackendKind::available() {
        for (t, volume) in [(0.5, false), (1.0, false), (1.0, true)] {
            let material = Material {
                diffuse_transmission: Some(DiffuseTransmission {
                    factor: t,
                    texture: None,
                    color: Vec3::ONE,
                    color_texture: None,
                }),
                volume: volume.then_some(Volume {
                    thickness: 1.0,
                    attenuation_color: Vec3::ONE,
                    attenuation_distance: f32::INFINITY,
                }),
                ..white(0.0, 0.5)
            };
            let (mean, rings, se) =
                furnace_with_noise(material, BrdfModel::Compensated, backend, 64, 64);
            let what = format!("{backend}, diffuse transmission {t}, volume {volume}");
            eprintln!("{what}: mean {mean:.4}, rings {rings:.4?} ± {se:.4?}");
            if (mean - 1.0).abs() > 0.01
                || rings.iter().any(|r| (r - 1.0).abs() > 0.02)
                || se.iter().any(|&e| 4.0 * e > 0.02)
            {
                failures.push(format!("{what}: mean {mean:.4}, rings {rings:.4?}"));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "not 1 within 1 % (mean) and 2 % (rings, 4σ): {failures:?}"
    );
}

#[test]
fn a_clear_coat_over_a_white_base_reflects_the_furnace_exactly() {
    for &backend in BackendKind::available() {
        for (metallic, coat_roughness) in [(1.0, 0.3), (0.0, 1.0)] {
            let material = Material {
                clearcoat: Some(Clearcoat {
                    factor: 1.0,
                    roughness: coat_roughness,
                    texture: None,
                    roughness_texture: None,
                    normal_texture: None,
                }),
                ..white(metallic, 0.5)
            };
            let (mean, rings) = furnace(material, BrdfModel::Compensated, backend, 64);
            let what = format!("{backend}, coat r {coat_roughness} over metallic {metallic}");
            eprintln!("{what}: mean {mean:.4}, rings {rings:.4?}");
            assert!((mean - 1.0).abs() <= 0.01, "{what}: sphere mean {mean}");
            for (i, r) in rings.iter().enumerate() {
                assert!((r - 1.0).abs() <= 0.02, "{what}: ring {i} of {RINGS} = {r}");
            }
        }
    }
}

/// A white sheen (KHR_materials_sheen, colour 1, roughness 0.5) over a white Lambertian base
/// (KHR_materials_specular 0): the extension's albedo scaling
/// `min(1 − E(μo), 1 − E(μi))` is not energy conserving, and on a convex sphere (every
/// reflected ray escapes) each pixel shows the stack's albedo in closed form,
///
/// ```text
/// a(μo) = E_s(μo) + 2 ∫₀¹ (1 − max(E(μo), E(μi))) μi dμi
/// ```
///
/// with `E_s` the sheen lobe's albedo and `E` its table. The sphere's mean and rings match
/// `a` at each pixel's `μo` within 1 % and 2 %, and `a ≤ 1` (the scaling never adds light).
#[test]
fn a_white_sheen_over_a_white_base_reflects_its_closed_form() {
    let roughness = 0.5f32;
    let lobe = SheenBsdf::new(Vec3::ONE, roughness);
    let albedo = |mu_o: f32| {
        let n = 2000;
        let e_o = sheen_albedo(mu_o, roughness);
        let base: f64 = (0..n)
            .map(|i| {
                let mu = (i as f32 + 0.5) / n as f32;
                let e_i = sheen_albedo(mu, roughness);
                2.0 * f64::from((1.0 - e_o.max(e_i)) * mu) / n as f64
            })
            .sum();
        f64::from(directional_albedo(&lobe, mu_o.max(1e-3), 256)) + base
    };
    // The pixel centre's μo = cos θ of the surface seen there (orthographic view).
    let expect = |x: u32, y: u32| {
        disc_radius(x, y).map_or(0.0, |r| albedo((1.0 - r * r).max(0.0).sqrt() as f32))
    };
    let (want_mean, want_rings) = disc_statistics(expect);
    assert!(want_rings.iter().all(|&a| a <= 1.0), "{want_rings:?}");
    for &backend in BackendKind::available() {
        let material = Material {
            sheen: Some(Sheen {
                color: Vec3::ONE,
                roughness,
                color_texture: None,
                roughness_texture: None,
            }),
            specular: 0.0,
            ..white(0.0, 0.5)
        };
        let (mean, rings, se) =
            furnace_with_noise(material, BrdfModel::Compensated, backend, 64, 32);
        eprintln!(
            "{backend}, white sheen over white Lambert: mean {mean:.4} (closed form {want_mean:.4}), rings {rings:.4?} ± {se:.4?} (closed form {want_rings:.4?})"
        );
        assert!(
            se.iter().all(|&e| 4.0 * e <= 0.02),
            "{backend}: sheen rings too noisy: {se:?}"
        );
        assert!(
            (mean - want_mean).abs() <= 0.01,
            "{backend}: sheen mean {mean} vs {want_mean}"
        );
        for (i, (r, w)) in rings.iter().zip(&want_rings).enumerate() {
            assert!(
                (r - w).abs() <= 0.02,
                "{backend}: sheen ring {i} = {r} vs {w}"
            );
        }
    }
}

/// The spheres touch each other and the slab: every point of the scene sees the others, and
/// near the contacts light bounces many times before it escapes. With an albedo of 1 at every
/// angle, radiance 1 everywhere still solves the rendering equation. White metal and white
/// dielectric at roughness 0.25, 0.5 and 1, 256 spp. Roughness 1 used to fail this test
/// with the plain visible-normal sampler (unbiased but heavy-tailed: half its draws left
/// below the horizon with weight 0, the rest weighed up to 1/E0 ≈ 3.3, and the products
/// along the crevices' paths put single 8×8 blocks 4-50 % off at 256-2048 spp); the folded
/// sampler of the compensated model keeps every draw (see docs/bsdf.md).
#[test]
fn touching_spheres_on_a_slab_reflect_the_furnace_everywhere() {
    let size = 48u32;
    for &backend in BackendKind::available() {
        for metallic in [1.0, 0.0] {
            for roughness in [0.25, 0.5, 1.0] {
                let worst = non_convex_worst_block(backend, metallic, roughness, 256, size);
                eprintln!(
                    "{backend}, metallic {metallic}, roughness {roughness}: worst 8×8 block |mean − 1| = {worst:.4}"
                );
                assert!(
                    worst <= 0.03,
                    "{backend}, metallic {metallic}, roughness {roughness}: a block is {worst} off"
                );
            }
        }
    }
}

/// Renders two touching white spheres on a white slab (one material: `metallic`,
/// `roughness`) in the furnace and returns the largest `|block mean − 1|` over its 8×8
/// blocks.
fn non_convex_worst_block(
    backend: BackendKind,
    metallic: f32,
    roughness: f32,
    spp: u32,
    size: u32,
) -> f64 {
    let mut left = sphere(0);
    let mut right = sphere(0);
    left.positions
        .iter_mut()
        .for_each(|p| *p += Vec3::new(-1.0, 0.0, 1.0));
    right
        .positions
        .iter_mut()
        .for_each(|p| *p += Vec3::new(1.0, 0.0, 1.0));
    let slab = quad(Vec3::ZERO, Vec3::X * 4.0, Vec3::Y * 4.0, 0);
    let material = Material {
        double_sided: true,
        ..white(metallic, roughness)
    };
    let scene = scene(vec![left, right, slab], vec![material], vec![]);
    let camera = look_at(
        Vec3::new(0.0, -4.5, 3.0),
        Vec3::new(0.0, 0.0, 0.7),
        Vec3::Z,
        0.8,
    );
    let furnace = Furnace {
        size,
        spp,
        seed: 11,
        max_depth: 32,
        brdf: BrdfModel::Compensated,
    };
    let image = white_furnace(&scene, &camera, backend, &furnace);
    let mut worst = 0.0f64;
    for by in 0..size / 8 {
        for bx in 0..size / 8 {
            let mut sum = 0.0;
            for y in by * 8..by * 8 + 8 {
                for x in bx * 8..bx * 8 + 8 {
                    let p = image.pixels[(y * size + x) as usize];
                    sum += f64::from(p.dot(Vec3::ONE)) / 3.0;
                }
            }
            worst = worst.max((sum / 64.0 - 1.0).abs());
        }
    }
    worst
}

/// The furnace rings of a glass sphere (ior 1.5, `roughness`) under `max_depth` and
/// `max_transmission_depth`, same seed whatever the depths (so the renders differ only by
/// the paths the budgets cut).
fn glass_furnace_rings(
    backend: BackendKind,
    roughness: f32,
    max_depth: u32,
    max_transmission_depth: u32,
) -> Vec<f64> {
    let scene = scene(vec![sphere(0)], vec![glass(1.5, roughness)], vec![]);
    let camera = ortho(Vec3::new(0.0, -4.0, 0.3), Vec3::ZERO, Vec3::Z, VIEW, VIEW);
    let env = glint::light::environment::EnvironmentLight::constant(Vec3::ONE);
    let accel = glint::render::prepare(&scene, backend, glint::accel::BuildOptions::default())
        .expect("build");
    let mut inputs = glint::render::RenderInputs::of_scene(&scene, accel.as_ref(), &camera);
    inputs.environment = Some(&env);
    let settings = glint::render::RenderSettings {
        width: SIZE,
        height: SIZE,
        spp: 64,
        seed: 5,
        threads: 2,
        max_depth,
        max_transmission_depth,
        integrator: glint::render::Integrator::Path,
        ..glint::render::RenderSettings::default()
    };
    let (film, _) =
        glint::render::render_film(&inputs, &settings, 0..settings.spp, None).expect("render");
    let image = film.resolve().0;
    let value =
        |x: u32, y: u32| f64::from(image.pixels[(y * SIZE + x) as usize].dot(Vec3::ONE)) / 3.0;
    disc_statistics(value).1
}

/// Glass that needs no tuning (issue 35): transmission bounces (refractions, reflections
/// inside the glass) have their own budget beside `--max-depth`, so a glass sphere at the
/// default settings reads every furnace ring, the rim's included, within 1 % of a depth-512
/// render: smooth glass, and rough glass (0.25), where rays near the rim circle inside by total
/// internal reflection for tens of bounces (with those bounces counted in a depth of 32, its
/// rim read 0.976). Same seed, so only the paths the budgets cut differ. The budget is what
/// does it: four transmission bounces leave the rough sphere's rim more than 1 % short
/// (measured: rim 0.840 at 4, 0.892 at 8, 0.935 at 16, 0.977 at 32, 0.998 at the default 64,
/// 1.000 at 512).
#[test]
fn glass_at_the_default_depths_matches_depth_512() {
    let defaults = glint::render::RenderSettings::default();
    for &backend in BackendKind::available() {
        for roughness in [0.0, 0.25] {
            let default = glass_furnace_rings(
                backend,
                roughness,
                defaults.max_depth,
                defaults.max_transmission_depth,
            );
            let deep = glass_furnace_rings(backend, roughness, 512, 512);
            eprintln!(
                "{backend}, roughness {roughness}: rings at the defaults {default:.4?}, at 512 {deep:.4?}"
            );
            for (ring, (d, r)) in default.iter().zip(&deep).enumerate() {
                assert!(
                    (d - r).abs() <= 0.01 * r,
                    "{backend}, roughness {roughness}: ring {ring}: {d:.4} at the defaults, {r:.4} at depth 512"
                );
            }
        }
        let short = glass_furnace_rings(backend, 0.25, defaults.max_depth, 4);
        let deep = glass_furnace_rings(backend, 0.25, 512, 512);
        let (s, r) = (short[RINGS - 1], deep[RINGS - 1]);
        assert!(
            (s - r).abs() > 0.01 * r,
            "{backend}: 4 transmission bounces already give the rim ({s:.4} vs {r:.4})"
        );
    }
}
