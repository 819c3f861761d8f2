//! Mirrors and emission against closed forms, on every backend: a floor mirror (glTF smooth
//! metal) in front of a lit diffuse wall shows the wall's radiance times its reflectance,
//! Schlick's `F = ρ + (1 − ρ)(1 − cos θ)⁵` at the view angle; --max-depth 0 and 1; an
//! emitter seen directly shows Le and in the mirror F·Le. Also: the specialised kernel gives
//! the general kernel's image.

use crate::support::*;
use glam::{DVec3, Vec2, Vec3, Vec4};
use glint::accel::{BackendKind, Ray};
use glint::render::{KernelChoice, RenderOutput, RenderSettings};
use glint::scene::{Camera, Light, MagFilter, Material, Scene, Texture, TextureRef, WrapMode};
use std::f64::consts::PI;

const TOL: f64 = 1e-4;
const EDGE: f64 = 1e-3;
const R_MIRROR: Vec3 = Vec3::new(0.9, 0.6, 0.3);
const RHO_WALL: Vec3 = Vec3::new(0.5, 0.7, 0.8);
const E_WALL: Vec3 = Vec3::new(3.0, 2.0, 1.0);
const E_FLOOR: Vec3 = Vec3::new(1.0, 1.5, 2.0);

fn floor_quad() -> ExactQuad {
    ExactQuad::new(
        Vec3::ZERO,
        Vec3::new(3.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, -3.0),
    )
}

fn wall_quad() -> ExactQuad {
    ExactQuad::new(
        Vec3::new(0.0, 2.0, -3.0),
        Vec3::new(3.0, 0.0, 0.0),
        Vec3::new(0.0, 2.0, 0.0),
    )
}

fn mesh_of(q: ExactQuad, material: usize) -> glint::scene::Mesh {
    quad(q.center.as_vec3(), q.u.as_vec3(), q.v.as_vec3(), material)
}

/// A floor mirror (material 0) facing +Y and a wall (material 1) facing the camera (+Z).
fn room(floor: Material, wall: Material, lights: Vec<Light>) -> (Scene, Camera) {
    let scene = scene(
        vec![mesh_of(floor_quad(), 0), mesh_of(wall_quad(), 1)],
        vec![floor, wall],
        lights,
    );
    let camera = look_at(
        Vec3::new(0.0, 1.5, 4.0),
        Vec3::new(0.0, 0.6, -3.0),
        Vec3::Y,
        0.9,
    );
    (scene, camera)
}

/// A directional light onto the wall (the floor sees it edge-on) and one onto the floor (the
/// wall sees it edge-on): neither shadows the other surface.
fn lights() -> Vec<Light> {
    vec![
        Light::Directional {
            direction: -Vec3::Z,
            irradiance: E_WALL,
        },
        Light::Directional {
            direction: -Vec3::Y,
            irradiance: E_FLOOR,
        },
    ]
}

/// What a camera ray sees first.
enum Seen {
    Wall,
    /// The floor, and where its mirror reflection goes: Some(true) to the wall, Some(false)
    /// away from it, None too close to the wall's edge to tell; and the view's cos θ.
    Floor(Option<bool>, f64),
    Nothing,
    Ambiguous,
}

fn trace(ray: &Ray) -> Seen {
    let (floor, wall) = (floor_quad(), wall_quad());
    if floor.near_edge(ray, EDGE) || wall.near_edge(ray, EDGE) {
        return Seen::Ambiguous;
    }
    match (floor.hit(ray, EDGE), wall.hit(ray, EDGE)) {
        (Some((tf, _)), Some((tw, _))) if tw < tf => Seen::Wall,
        (None, Some(_)) => Seen::Wall,
        (Some((_, p)), _) => {
            let d = ray.dir.as_dvec3();
            let cos = -d.y / d.length();
            let reflected = Ray::new(p.as_vec3(), Vec3::new(d.x as f32, -d.y as f32, d.z as f32));
            if wall.near_edge(&reflected, 10.0 * EDGE) {
                Seen::Floor(None, cos)
            } else {
                Seen::Floor(Some(wall.hit(&reflected, 10.0 * EDGE).is_some()), cos)
            }
        }
        (None, None) => Seen::Nothing,
    }
}

/// Schlick's Fresnel of a metal of base colour `rho` at `cos θ`: its mirror reflectance.
fn schlick(rho: Vec3, cos: f64) -> DVec3 {
    let rho = rho.as_dvec3();
    rho + (DVec3::ONE - rho) * (1.0 - cos).powi(5)
}

/// Checks every unambiguous pixel: wall pixels against `wall`, floor pixels against
/// `floor(reflects_wall, cos θ of the view)`, others 0. Returns (wall pixels, floor pixels
/// seeing the wall).
fn check(
    out: &RenderOutput,
    camera: &Camera,
    label: &str,
    wall: DVec3,
    floor: impl Fn(bool, f64) -> DVec3,
) -> (usize, usize) {
    let (w, h) = (out.image.width, out.image.height);
    let (mut walls, mut reflections) = (0, 0);
    for y in 0..h {
        for x in 0..w {
            let want = match trace(&centre_ray(camera, w, h, x, y)) {
                Seen::Wall => {
                    walls += 1;
                    wall
                }
                Seen::Floor(Some(sees_wall), cos) => {
                    reflections += sees_wall as usize;
                    floor(sees_wall, cos)
                }
                Seen::Nothing => DVec3::ZERO,
                Seen::Floor(None, _) | Seen::Ambiguous => continue,
            };
            let got = out.image.get(x, y).unwrap();
            assert!(
                close(got, want, TOL),
                "{label}: pixel ({x}, {y}) = {got}, closed form {want}"
            );
        }
    }
    (walls, reflections)
}

fn settings(max_depth: u32) -> RenderSettings {
    RenderSettings {
        max_depth,
        ..centre_settings(64, 48)
    }
}

fn wall_radiance() -> DVec3 {
    RHO_WALL.as_dvec3() / PI * E_WALL.as_dvec3()
}

#[test]
fn mirror_shows_the_lit_plane_times_its_reflectance() {
    for &backend in BackendKind::available() {
        let (scene, camera) = room(mirror(R_MIRROR, 1.0), lambert(RHO_WALL, false), lights());
        let out = render_with(&scene, &camera, backend, &settings(8));
        let (walls, reflections) = check(
            &out,
            &camera,
            backend.name(),
            wall_radiance(),
            |sees, cos| {
                if sees {
                    schlick(R_MIRROR, cos) * wall_radiance()
                } else {
                    DVec3::ZERO
                }
            },
        );
        assert!(
            walls > 300 && reflections > 300,
            "{walls} wall, {reflections} mirror pixels"
        );
    }
}

/// A partly metallic smooth surface has a delta lobe (metal, Schlick's F) and a Lambertian
/// one. The direct integrator follows the delta lobe when the BSDF's lobe choice picks it,
/// with probability `P = s/(s + d)` (`s = m·mean(F)`, `d = (1 − m)·mean(ρ)`, see
/// `bsdf::metallic_roughness`), weighted by `1/P`: unbiased, so the mean of many samples at
/// the pixel centre is the closed form, within 5σ of that Bernoulli choice.
#[test]
fn partly_metallic_mirror_adds_its_diffuse_part() {
    let metallic = 0.6f64;
    let spp = 1024u32;
    for &backend in BackendKind::available() {
        let (scene, camera) = room(
            mirror(R_MIRROR, metallic as f32),
            lambert(RHO_WALL, false),
            lights(),
        );
        let settings = RenderSettings { spp, ..settings(8) };
        let out = render_with(&scene, &camera, backend, &settings);
        let rho = R_MIRROR.as_dvec3();
        let diffuse = rho * (1.0 - metallic) / PI * E_FLOOR.as_dvec3();
        let (w, h) = (out.image.width, out.image.height);
        let mut reflections = 0;
        for y in 0..h {
            for x in 0..w {
                let got = out.image.get(x, y).unwrap().as_dvec3();
                let (want, sigma) = match trace(&centre_ray(&camera, w, h, x, y)) {
                    Seen::Wall => (wall_radiance(), DVec3::ZERO),
                    Seen::Floor(Some(false), _) => (diffuse, DVec3::ZERO),
                    Seen::Floor(Some(true), cos) => {
                        reflections += 1;
                        let f = schlick(R_MIRROR, cos);
                        let s = metallic * (f.x + f.y + f.z) / 3.0;
                        let d = (1.0 - metallic) * (rho.x + rho.y + rho.z) / 3.0;
                        let p = s / (s + d);
                        let specular = f * metallic * wall_radiance();
                        let sigma = specular * ((1.0 - p) / p / spp as f64).sqrt();
                        (diffuse + specular, sigma)
                    }
                    Seen::Nothing => (DVec3::ZERO, DVec3::ZERO),
                    Seen::Floor(None, _) | Seen::Ambiguous => continue,
                };
                let tolerance = 5.0 * sigma + want * TOL;
                assert!(
                    (got - want).abs().cmple(tolerance).all(),
                    "{backend}: pixel ({x}, {y}) = {got}, closed form {want} ± {tolerance}"
                );
            }
        }
        assert!(reflections > 300, "{reflections} mirror pixels");
    }
}

#[test]
fn max_depth_zero_traces_no_reflection_and_one_traces_one() {
    for &backend in BackendKind::available() {
        let (scene, camera) = room(mirror(R_MIRROR, 1.0), lambert(RHO_WALL, false), lights());
        let depth0 = render_with(&scene, &camera, backend, &settings(0));
        let (_, reflections) = check(&depth0, &camera, "max-depth 0", wall_radiance(), |_, _| {
            DVec3::ZERO
        });
        assert!(reflections > 300);
        assert_eq!(depth0.stats.rays.reflection, 0);

        let depth1 = render_with(&scene, &camera, backend, &settings(1));
        check(
            &depth1,
            &camera,
            "max-depth 1",
            wall_radiance(),
            |sees, cos| {
                if sees {
                    schlick(R_MIRROR, cos) * wall_radiance()
                } else {
                    DVec3::ZERO
                }
            },
        );
        // One reflection ray per pixel that sees the mirror, and no second bounce.
        let mirror_pixels = (0..depth1.image.pixels.len())
            .filter(|&i| {
                let (x, y) = (i as u32 % 64, i as u32 / 64);
                floor_quad()
                    .hit(&centre_ray(&camera, 64, 48, x, y), 0.0)
                    .is_some()
                    && wall_quad()
                        .hit(&centre_ray(&camera, 64, 48, x, y), 0.0)
                        .is_none()
            })
            .count() as u64;
        let traced = depth1.stats.rays.reflection;
        assert!(
            traced.abs_diff(mirror_pixels) <= 8,
            "{traced} vs {mirror_pixels}"
        );
    }
}

#[test]
fn emission_seen_directly_and_in_a_mirror() {
    let le = Vec3::new(2.0, 5.0, 0.5);
    for &backend in BackendKind::available() {
        let (scene, camera) = room(mirror(R_MIRROR, 1.0), emitter(le), vec![]);
        let out = render_with(&scene, &camera, backend, &settings(8));
        let (walls, reflections) = check(&out, &camera, "emission", le.as_dvec3(), |sees, cos| {
            if sees {
                schlick(R_MIRROR, cos) * le.as_dvec3()
            } else {
                DVec3::ZERO
            }
        });
        assert!(walls > 300 && reflections > 300);
        assert_eq!(out.stats.rays.shadow, 0, "no lights, no shadow rays");
    }
}

/// A scene that uses every feature: textures, vertex colours and normals, mirrors, emission,
/// point / spot / directional lights with and without range.
fn everything_scene() -> (Scene, Camera) {
    let texture = Texture {
        name: "checker".into(),
        width: 2,
        height: 2,
        texels: vec![
            Vec4::new(1.0, 0.2, 0.2, 1.0),
            Vec4::new(0.2, 1.0, 0.2, 1.0),
            Vec4::new(0.2, 0.2, 1.0, 1.0),
            Vec4::ONE,
        ]
        .into(),
        wrap_s: WrapMode::Repeat,
        wrap_t: WrapMode::MirroredRepeat,
        mag_filter: MagFilter::Linear,
    };
    let textured = Material {
        base_color_texture: Some(TextureRef {
            texture: 0,
            texcoord: 0,
            transform: glam::Affine2::from_scale(Vec2::splat(3.0)),
        }),
        emissive: Vec3::splat(0.05),
        ..lambert(Vec3::new(0.9, 0.8, 0.7), true)
    };
    let (scene, camera) = room(mirror(R_MIRROR, 0.7), textured, vec![]);
    let mut scene = scene;
    let wall = &mut scene.meshes[1];
    wall.texcoords[0] = Some(vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y]);
    wall.colors = Some(vec![
        Vec4::ONE,
        Vec4::new(1.0, 0.5, 0.5, 1.0),
        Vec4::ONE,
        Vec4::splat(0.5),
    ]);
    wall.normals = Some(vec![
        Vec3::new(0.1, 0.0, 1.0).normalize(),
        Vec3::Z,
        Vec3::new(-0.1, 0.1, 1.0).normalize(),
        Vec3::Z,
    ]);
    scene.textures.push(texture);
    scene.lights = vec![
        Light::Point {
            position: Vec3::new(1.0, 2.0, 1.0),
            intensity: Vec3::splat(5.0),
            range: None,
        },
        Light::Spot {
            position: Vec3::new(-1.0, 3.0, 0.0),
            direction: Vec3::new(0.2, -1.0, -0.5).normalize(),
            intensity: Vec3::new(20.0, 10.0, 5.0),
            range: Some(6.0),
            cos_inner: 0.9,
            cos_outer: 0.7,
        },
        Light::Point {
            position: Vec3::new(0.0, 0.5, -1.0),
            intensity: Vec3::splat(2.0),
            range: Some(2.5),
        },
        Light::Spot {
            position: Vec3::new(2.0, 1.0, 2.0),
            direction: Vec3::new(-0.5, -0.2, -1.0).normalize(),
            intensity: Vec3::splat(8.0),
            range: None,
            cos_inner: 0.95,
            cos_outer: 0.8,
        },
        Light::Directional {
            direction: Vec3::new(0.3, -1.0, -0.4).normalize(),
            irradiance: Vec3::splat(0.7),
        },
    ];
    (scene, camera)
}

#[test]
fn specialised_kernel_matches_the_general_one() {
    let (scene, camera) = everything_scene();
    let (walls_only, _) = room(lambert(R_MIRROR, false), lambert(RHO_WALL, false), lights());
    for &backend in BackendKind::available() {
        for test_scene in [&scene, &walls_only] {
            let mut settings = RenderSettings {
                spp: 4,
                seed: 7,
                ..settings(8)
            };
            let specialised = render_with(test_scene, &camera, backend, &settings);
            settings.kernel = KernelChoice::General;
            let general = render_with(test_scene, &camera, backend, &settings);
            assert!(general.stats.kernel.textures && general.stats.kernel.vertex_colors);
            assert!(specialised.image.pixels.iter().any(|p| *p != Vec3::ZERO));
            for (i, (s, g)) in specialised
                .image
                .pixels
                .iter()
                .zip(&general.image.pixels)
                .enumerate()
            {
                // Lights are summed in another order: equal up to rounding.
                assert!(
                    close(*s, g.as_dvec3(), 1e-5),
                    "{backend}: pixel {i}: {s} vs {g}"
                );
            }
            assert_eq!(specialised.stats.rays, general.stats.rays);
        }
    }
    // The simple scene really was rendered by a reduced kernel.
    let features = glint::scene::SceneFeatures::of(&walls_only);
    let flags = glint::render::KernelFlags::for_scene(&features, KernelChoice::Specialised);
    assert!(!flags.textures && !flags.vertex_colors && !flags.shading_normals);
}
