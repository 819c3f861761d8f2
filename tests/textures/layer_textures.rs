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
