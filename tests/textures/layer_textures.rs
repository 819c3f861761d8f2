//! The KHR_materials layer textures in a render. A texture multiplies its factor, so:
//! a constant texture of value `t` on factor 1 renders exactly like factor `t` without a
//! texture (same samples, same arithmetic up to rounding), for each texture kind; and a texture
//! black on its left half and white on its right makes the left half render like a coat of
//! strength 0 and the right like strength 1.

use crate::support::{centre_settings, emitter, look_at, quad, render_with};
use glam::{Vec2, Vec3, Vec4};
use glint::accel::BackendKind;
use glint::render::{Integrator, RenderSettings};
use glint::scene::layers::{Clearcoat, Sheen, Transmission};
use glint::scene::{
    Light, MagFilter, Material, Mesh, NormalTextureRef, Scene, Texture, TextureRef, WrapMode,
};
use glint::texture::TextureFilter;

const W: u32 = 16;

/// A texture of `texels` (one row), nearest-texel lookups.
fn texture(texels: &[Vec4]) -> Texture {
    Texture {
        name: "layer".into(),
        width: texels.len() as u32,
        height: 1,
        texels: texels.to_vec().into(),
        wrap_s: WrapMode::ClampToEdge,
        wrap_t: WrapMode::ClampToEdge,
        mag_filter: MagFilter::Nearest,
    }
}

fn tref() -> Option<TextureRef> {
    Some(TextureRef {
        texture: 0,
        texcoord: 0,
        transform: glam::Affine2::IDENTITY,
    })
}

fn textured_quad() -> Mesh {
    let mut q = quad(Vec3::ZERO, Vec3::X, Vec3::Y, 0);
    q.texcoords[0] = Some(vec![
        Vec2::new(0.0, 1.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(0.0, 0.0),
    ]);
    q
}

/// The quad with `material`, lit by a point light and an emitter behind it (which the
/// transmission test sees through the quad), seen by a perspective camera; `textures` are the
/// scene's textures.
fn render(material: Material, textures: Vec<Texture>) -> Vec<Vec3> {
    render_mesh(textured_quad(), material, textures)
}

fn render_mesh(front: Mesh, material: Material, textures: Vec<Texture>) -> Vec<Vec3> {
    let meshes = vec![front, quad(-Vec3::Z * 2.0, Vec3::X * 4.0, Vec3::Y * 4.0, 1)];
    let scene = Scene {
        meshes,
        materials: vec![material, emitter(Vec3::new(0.3, 0.5, 0.7))],
        lights: vec![Light::Point {
            position: Vec3::new(0.3, 0.4, 2.0),
            intensity: Vec3::splat(5.0),
            range: None,
        }],
        textures,
        ..Scene::default()
    };
    let camera = look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y, 0.5);
    let settings = RenderSettings {
        integrator: Integrator::Path,
        max_depth: 4,
        spp: 4,
        texture_filter: TextureFilter::Nearest,
        ..centre_settings(W, W)
    };
    render_with(&scene, &camera, BackendKind::Bvh, &settings)
        .image
        .pixels
}

fn base() -> Material {
    Material {
        name: "layered".into(),
        base_color: Vec4::new(0.6, 0.4, 0.2, 1.0),
        metallic: 0.0,
        roughness: 0.5,
        ..Material::default()
    }
}

fn coat(factor: f32, roughness: f32, textured: bool) -> Material {
    Material {
        clearcoat: Some(Clearcoat {
            factor,
            roughness,
            texture: if textured { tref() } else { None },
            roughness_texture: if textured { tref() } else { None },
            normal_texture: None,
        }),
        ..base()
    }
}

fn sheen(color: Vec3, roughness: f32, textured: bool) -> Material {
    Material {
        sheen: Some(Sheen {
            color,
            roughness,
            color_texture: if textured { tref() } else { None },
            roughness_texture: if textured { tref() } else { None },
        }),
        ..base()
    }
}

fn transmission(factor: f32, textured: bool) -> Material {
    Material {
        transmission: Some(Transmission {
            factor,
            texture: if textured { tref() } else { None },
        }),
        ..base()
    }
}

fn assert_same(got: &[Vec3], want: &[Vec3], what: &str) {
    let scale = want.iter().map(|p| p.max_element()).fold(0.0f32, f32::max);
    assert!(scale > 0.0, "{what}: black image");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (*g - *w).abs().max_element() <= 1e-5 * scale,
            "{what}: pixel {i}: {g} vs {w}"
        );
    }
}

#[test]
fn a_constant_layer_texture_equals_its_value_as_factor() {
    // Channels: R = 0.5 (coat strength, transmission), G = 0.25 (coat roughness),
    // RGB (sheen colour), A = 0.75 (sheen roughness).
    let t = Vec4::new(0.5, 0.25, 0.8, 0.75);
    let constant = || vec![texture(&[t])];
    assert_same(
        &render(coat(1.0, 0.8, true), constant()),
        &render(coat(0.5, 0.8 * 0.25, false), vec![]),
        "clearcoat",
    );
    assert_same(
        &render(sheen(Vec3::ONE, 0.6, true), constant()),
        &render(sheen(t.truncate(), 0.6 * 0.75, false), vec![]),
        "sheen",
    );
    assert_same(
        &render(transmission(1.0, true), constant()),
        &render(transmission(0.5, false), vec![]),
        "transmission",
    );
    // The texture does change the image (the comparison above is not vacuous).
    let plain = render(coat(1.0, 0.8, false), vec![]);
    let textured = render(coat(1.0, 0.8, true), constant());
    assert!(
        plain
            .iter()
            .zip(&textured)
            .any(|(a, b)| (*a - *b).abs().max_element() > 1e-3),
        "the coat texture had no effect"
    );
}

#[test]
fn a_half_black_coat_texture_removes_the_coat_on_that_half() {
    // Left texel R = 0 (no coat), right texel R = 1 (full coat); G = 1 keeps the roughness.
    let halves = vec![texture(&[Vec4::new(0.0, 1.0, 1.0, 1.0), Vec4::ONE])];
    let got = render(coat(1.0, 0.3, true), halves);
    let none = render(coat(0.0, 0.3, false), vec![]);
    let full = render(coat(1.0, 0.3, false), vec![]);
    let (mut left, mut right) = (0, 0);
    for y in 0..W {
        // Pixel columns whose footprint lies well inside one half of the quad (the quad
        // spans the middle of the image; column W/2 straddles the seam).
        for x in 0..W {
            let i = (y * W + x) as usize;
            let want = if x < W / 2 - 1 {
                left += 1;
                none[i]
            } else if x > W / 2 {
                right += 1;
                full[i]
            } else {
                continue;
            };
            assert!(
                (got[i] - want).abs().max_element() <= 1e-5 * want.max_element().max(1e-3),
                "pixel ({x}, {y}): {} vs {want}",
                got[i]
            );
        }
    }
    assert!(left > 0 && right > 0);
    assert!(
        none.iter()
            .zip(&full)
            .any(|(a, b)| (*a - *b).abs().max_element() > 1e-3),
        "the coat had no effect"
    );
}

/// The quad's coat with a normal map of the one texel `texel` (texture 0); the quad gets
/// tangents along +X.
fn render_coat_normal(texel: Option<Vec4>) -> Vec<Vec3> {
    let mut material = coat(1.0, 0.2, false);
    if let (Some(c), Some(_)) = (&mut material.clearcoat, texel) {
        c.normal_texture = Some(NormalTextureRef {
            texture: tref().expect("some"),
            scale: 1.0,
        });
    }
    render_tangent(
        material,
        texel.map(|t| vec![texture(&[t])]).unwrap_or_default(),
    )
}

fn render_tangent(material: Material, textures: Vec<Texture>) -> Vec<Vec3> {
    let mut q = textured_quad();
    q.tangents = Some(vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4]);
    render_mesh(q, material, textures)
}

#[test]
fn a_flat_coat_normal_map_changes_nothing_and_a_tilted_one_moves_the_coat() {
    let none = render_coat_normal(None);
    // (0.5, 0.5, 1) decodes to the unperturbed normal.
    let flat = render_coat_normal(Some(Vec4::new(0.5, 0.5, 1.0, 1.0)));
    assert_same(&flat, &none, "flat coat normal map");
    let tilted = render_coat_normal(Some(Vec4::new(0.8, 0.5, 0.9, 1.0)));
    assert!(
        tilted
            .iter()
            .zip(&none)
            .any(|(a, b)| (*a - *b).abs().max_element() > 1e-3),
        "the coat normal map had no effect"
    );
    // The base is untouched: with a coat of strength 0 the map changes nothing.
    let mut zero = coat(0.0, 0.2, false);
    let plain = render_tangent(zero.clone(), vec![]);
    if let Some(c) = &mut zero.clearcoat {
        c.normal_texture = Some(NormalTextureRef {
            texture: tref().expect("some"),
            scale: 1.0,
        });
    }
    let mapped = render_tangent(zero, vec![texture(&[Vec4::new(0.8, 0.5, 0.9, 1.0)])]);
    assert_same(&mapped, &plain, "coat of strength 0");
}

// ---- The clear coat's normal: its own map, or none (KHR_materials_clearcoat) ----

/// Side of the flat-plane images below.
const PLANE_W: u32 = 64;
/// Height of the point light over the plane's centre, and the orthographic camera's half-size.
const LIGHT_HEIGHT: f32 = 1.0;
const PLANE_HALF: f32 = 1.0;

/// The texel that encodes a tangent-space normal tilted by `theta` toward azimuth `phi`.
fn tilt_texel(theta: f32, phi: f32) -> Vec4 {
    let m = Vec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    );
    ((m + Vec3::ONE) * 0.5).extend(1.0)
}

/// A strong "flake" normal map: 16 × 16 texels, each tilted by 25° in a pseudo-random
/// direction (nearest lookups, so each flake is a flat facet of 4 × 4 pixels).
fn flake_map() -> Texture {
    let n = 16u32;
    let mut state = 0x2545_f491u32;
    let texels = (0..n * n)
        .map(|_| {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let phi = (state >> 8) as f32 / (1u32 << 24) as f32 * std::f32::consts::TAU;
            tilt_texel(25f32.to_radians(), phi)
        })
        .collect::<Vec<_>>();
    Texture {
        width: n,
        height: n,
        ..texture(&texels)
    }
}

fn normal_ref(texture: usize) -> Option<NormalTextureRef> {
    Some(NormalTextureRef {
        texture: TextureRef {
            texture,
            ..tref().expect("some")
        },
        scale: 1.0,
    })
}

/// A plane z = 0 of half-size [`PLANE_HALF`] with tangents along +X, lit only by a point
/// light [`LIGHT_HEIGHT`] over its centre, seen straight down by an orthographic camera
/// that the plane fills: the luminance of each pixel (direct light, pixel centres).
fn plane_image(material: Material, textures: Vec<Texture>) -> Vec<f32> {
    let mut plane = textured_quad();
    plane.positions = plane.positions.iter().map(|p| *p * PLANE_HALF).collect();
    plane.tangents = Some(vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4]);
    let scene = Scene {
        meshes: vec![plane],
        materials: vec![material],
        lights: vec![Light::Point {
            position: Vec3::new(0.0, 0.0, LIGHT_HEIGHT),
            intensity: Vec3::splat(1.0),
            range: None,
        }],
        textures,
        ..Scene::default()
    };
    let camera = crate::support::ortho(
        Vec3::new(0.0, 0.0, 3.0),
        Vec3::ZERO,
        Vec3::Y,
        PLANE_HALF,
        PLANE_HALF,
    );
    let settings = RenderSettings {
        integrator: Integrator::Direct,
        texture_filter: TextureFilter::Nearest,
        ..centre_settings(PLANE_W, PLANE_W)
    };
    render_with(&scene, &camera, BackendKind::Bvh, &settings)
        .image
        .pixels
        .iter()
        .map(|p| p.dot(Vec3::new(0.2126, 0.7152, 0.0722)))
        .collect()
}

/// A material whose base reflects nothing (black metal) under a coat of roughness 0.5, so
/// its image is the coat's highlight alone.
fn coat_only(coat_map: Option<NormalTextureRef>, base_map: Option<NormalTextureRef>) -> Material {
    Material {
        base_color: Vec4::new(0.0, 0.0, 0.0, 1.0),
        metallic: 1.0,
        normal_texture: base_map,
        clearcoat: Some(Clearcoat {
            factor: 1.0,
            roughness: 0.5,
            texture: None,
            roughness_texture: None,
            normal_texture: coat_map,
        }),
        ..base()
    }
}

/// A white rough metal without a coat: its image is the base lobe's highlight alone.
fn base_only(base_map: Option<NormalTextureRef>) -> Material {
    Material {
        base_color: Vec4::ONE,
        metallic: 1.0,
        roughness: 0.5,
        normal_texture: base_map,
        ..base()
    }
}

/// Pixels brighter than half of `peak`: the highlight's extent.
fn extent(image: &[f32], peak: f32) -> usize {
    image.iter().filter(|&&v| v > 0.5 * peak).count()
}

fn peak(image: &[f32]) -> f32 {
    image.iter().copied().fold(0.0, f32::max)
}

/// Mean |a − b| over mean b.
fn relative_l1(a: &[f32], b: &[f32]) -> f32 {
    let diff: f32 = a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum();
    diff / b.iter().sum::<f32>().max(1e-12)
}

/// KHR_materials_clearcoat: "If clearcoatNormalTexture is not given, no normal mapping is
/// applied to the clear coat layer, even if normal mapping is applied to the base
/// material." A flat plane whose base carries a strong flake map and whose coat has no map
/// shows the coat highlight of an unperturbed plane (its extent within 10 %), while the base
/// lobe alone follows the map.
#[test]
fn a_coat_without_its_own_normal_map_ignores_the_base_map() {
    let flat = plane_image(coat_only(None, None), vec![]);
    let over_flakes = plane_image(coat_only(None, normal_ref(0)), vec![flake_map()]);
    let p = peak(&flat);
    assert!(p > 0.0, "no coat highlight");
    let (want, got) = (extent(&flat, p), extent(&over_flakes, p));
    assert!(
        want > 50 && want < (PLANE_W * PLANE_W / 2) as usize,
        "the flat coat's highlight must be a spot inside the image ({want} pixels)"
    );
    assert!(
        got.abs_diff(want) as f32 <= 0.1 * want as f32,
        "coat highlight over a mapped base covers {got} pixels, a flat mirror's {want}"
    );
    // The base alone: the map breaks its highlight up.
    let base_flat = plane_image(base_only(None), vec![]);
    let base_flakes = plane_image(base_only(normal_ref(0)), vec![flake_map()]);
    let moved = relative_l1(&base_flakes, &base_flat);
    assert!(
        moved > 0.3,
        "the base lobe must follow its normal map (relative L1 change {moved})"
    );
}

/// With a `clearcoatNormalTexture` the coat follows it, not the base's map: a uniform coat
/// map tilting the normal by 10° toward +X moves the coat's highlight to where a coat of that
/// normal (the BSDF evaluated in closed form at each pixel centre) has its peak, whether or
/// not the base carries the flake map.
#[test]
fn a_coat_with_its_own_normal_map_follows_it() {
    let tilt = 10f32.to_radians();
    let coat_map = texture(&[tilt_texel(tilt, 0.0)]);
    // The expected peak: the coat lobe at pixel centres along the image's middle row.
    let n = Vec3::new(tilt.sin(), 0.0, tilt.cos());
    let lobe = glint::bsdf::ClearcoatBsdf::new(1.0, 0.5).with_normal(n);
    let radiance_at = |x: f32| {
        use glint::bsdf::Bsdf;
        let to_light = Vec3::new(-x, 0.0, LIGHT_HEIGHT);
        let wi = to_light.normalize();
        lobe.eval(Vec3::Z, wi).x * wi.z / to_light.length_squared()
    };
    let pixel_x = |i: u32| ((i as f32 + 0.5) / PLANE_W as f32 * 2.0 - 1.0) * PLANE_HALF;
    let want = (0..PLANE_W)
        .max_by(|&a, &b| radiance_at(pixel_x(a)).total_cmp(&radiance_at(pixel_x(b))))
        .expect("pixels");
    assert!(
        want + 4 < PLANE_W / 2,
        "the tilt must move the peak off the centre ({want})"
    );
    let mut images = Vec::new();
    for base_map in [None, normal_ref(1)] {
        let image = plane_image(
            coat_only(normal_ref(0), base_map),
            vec![coat_map.clone(), flake_map()],
        );
        let row = (PLANE_W / 2) as usize * PLANE_W as usize;
        let got = (0..PLANE_W)
            .max_by(|&a, &b| image[row + a as usize].total_cmp(&image[row + b as usize]))
            .expect("pixels");
        assert!(
            got.abs_diff(want) <= 1,
            "coat peak at column {got}, its map's lobe peaks at {want} (base map {})",
            base_map.is_some()
        );
        images.push(image);
    }
    // Off the middle row too: the whole highlight is the tilted coat's, the base's flakes
    // change nothing (the base reflects nothing).
    let change = relative_l1(&images[1], &images[0]);
    assert!(
        change < 1e-3,
        "the base's map moved the coat (relative L1 {change})"
    );
}
