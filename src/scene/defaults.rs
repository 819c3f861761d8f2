//! Defaults for scenes that lack a camera or lights (most public assets do).
//!
//! # Default camera ([`default_camera`])
//! Perspective, vertical field of view [`DEFAULT_YFOV_DEGREES`] = 40°, no fixed aspect ratio
//! (the image's is used). It looks at the centre of the axis-aligned bounding box of the
//! scene's vertices as drawn ([`Scene::exact_bounds`]: every vertex through its node
//! transforms, skin and morph weights, not the placed boxes of shared meshes, which grow
//! under rotation)
//! from the direction [`DEFAULT_VIEW_FROM`] = normalise(0.5, 0.4, 1.0) — in front (+Z),
//! slightly above and to the right — with world +Y up, at the distance d = r / sin(yfov / 2)
//! where the bounding sphere (radius r = half the box diagonal) exactly fills the vertical
//! field of view. An empty scene, or one whose box is a single point, is framed as the unit
//! box centred on that point (or the origin). A flat box (zero thickness) needs no special
//! case: its diagonal is still positive.
//!
//! # Completion ([`camera_for`], [`lights_for`], [`complete`])
//! The one place where a scene is completed: a render's camera is the one asked for, else the
//! scene's first, else the default camera; its lights are the scene's plus any given, else
//! the default lights. Each says what it added, for the user to see.
//!
//! # Default light ([`default_lights`])
//! One directional light "over the camera's shoulder": it arrives from the direction
//! normalise(up + 0.5 · left + back) of the camera's own frame (up = camera +Y, left =
//! camera −X, back = camera +Z, i.e. behind the camera), so surfaces facing the camera are
//! lit at cos θ = 2/3 and shapes read clearly. Its irradiance is
//! [`DEFAULT_IRRADIANCE_W_PER_M2`] = 3 W/m², white: a white Lambertian surface facing it has
//! radiance 3/π ≈ 0.95 W/(m²·sr), bright but not clipped at exposure 0.

use super::{Camera, Light, Projection, Scene};
use glam::Vec3;

/// Vertical field of view of the default camera, degrees.
pub const DEFAULT_YFOV_DEGREES: f32 = 40.0;

/// Where the default camera sits relative to the box centre (normalised before use): in
/// front, a little above and to the right, so that three faces of a box show.
pub const DEFAULT_VIEW_FROM: Vec3 = Vec3::new(0.5, 0.4, 1.0);

/// Irradiance of the default directional light on a surface facing it, W/m².
pub const DEFAULT_IRRADIANCE_W_PER_M2: f32 = 3.0;

/// The box framed when the scene has no extent: the unit cube, half-size 0.5.
const EMPTY_SCENE_HALF_SIZE: f32 = 0.5;

/// A camera framing the scene's bounds (placement in the module documentation).
pub fn default_camera(scene: &Scene) -> Camera {
    let (lo, hi) = scene.exact_bounds().unwrap_or((Vec3::ZERO, Vec3::ZERO));
    let centre = 0.5 * (lo + hi);
    let half_diagonal = 0.5 * (hi - lo).length();
    let radius = if half_diagonal > 0.0 && half_diagonal.is_finite() {
        half_diagonal
    } else {
        Vec3::splat(EMPTY_SCENE_HALF_SIZE).length()
    };
    let yfov = DEFAULT_YFOV_DEGREES.to_radians();
    let distance = radius / (0.5 * yfov).sin();
    let back = DEFAULT_VIEW_FROM.normalize();
    let eye = centre + back * distance;
    // The view direction is never vertical, so world +Y gives a well-defined right axis.
    Camera::looking_along(
        "default camera",
        eye,
        -back,
        Vec3::Y,
        Projection::Perspective {
            yfov,
            aspect_ratio: None,
        },
    )
}

/// The lights given to a scene that has none, placed relative to `camera` (placement in the
/// module documentation). `scene` is not needed by a directional light; it is taken so that
/// defaults that depend on the scene's size can be added without changing callers.
pub fn default_lights(scene: &Scene, camera: &Camera) -> Vec<Light> {
    let _ = scene;
    let frame = camera.world_from_camera;
    let up = frame.transform_vector3(Vec3::Y);
    let left = frame.transform_vector3(Vec3::NEG_X);
    let back = frame.transform_vector3(Vec3::Z);
    let towards_light = (up + 0.5 * left + back).normalize_or_zero();
    // A degenerate camera matrix has no frame to be "over the shoulder" of: light from above.
    let towards_light = if towards_light == Vec3::ZERO {
        Vec3::Y
    } else {
        towards_light
    };
    vec![Light::Directional {
        direction: -towards_light,
        irradiance: Vec3::splat(DEFAULT_IRRADIANCE_W_PER_M2),
    }]
}

/// The stderr announcement for a default camera, e.g.
/// `no camera in scene: added a perspective camera, yfov 40°, at (1.2, 0.9, 2.4) looking at (0, 0, 0)`.
pub fn describe_camera(camera: &Camera) -> String {
    let eye = camera.world_from_camera.w_axis.truncate();
    let forward = camera.world_from_camera.transform_vector3(Vec3::NEG_Z);
    let fov = match camera.projection {
        Projection::Perspective { yfov, .. } => {
            format!("perspective camera, yfov {:.0}°", yfov.to_degrees())
        }
        Projection::Orthographic { xmag, ymag } => format!("orthographic camera, {xmag} × {ymag}"),
    };
    format!(
        "no camera in scene: added a {fov}, at {} looking along {}",
        fmt_vec(eye),
        fmt_vec(forward)
    )
}

/// The stderr announcement for default lights, e.g.
/// `no lights in scene: added a directional light, E = 3 W/m², from (0.3, 0.8, 0.5)`.
pub fn describe_lights(lights: &[Light]) -> String {
    let parts: Vec<String> = lights
        .iter()
        .map(|light| match light {
            Light::Directional {
                direction,
                irradiance,
            } => format!(
                "a directional light, E = {} W/m², from {}",
                fmt_scalar_or_rgb(*irradiance),
                fmt_vec(-*direction)
            ),
            Light::Point {
                position,
                intensity,
                ..
            } => format!(
                "a point light, I = {} W/sr, at {}",
                fmt_scalar_or_rgb(*intensity),
                fmt_vec(*position)
            ),
            Light::Spot {
                position,
                intensity,
                ..
            } => format!(
                "a spot light, I = {} W/sr, at {}",
                fmt_scalar_or_rgb(*intensity),
                fmt_vec(*position)
            ),
        })
        .collect();
    format!("no lights in scene: added {}", parts.join(", "))
}

fn fmt_vec(v: Vec3) -> String {
    format!("({:.2}, {:.2}, {:.2})", v.x, v.y, v.z)
}

fn fmt_scalar_or_rgb(v: Vec3) -> String {
    if v.x == v.y && v.y == v.z {
        format!("{}", v.x)
    } else {
        fmt_vec(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Mesh;

    fn scene_with_points(points: &[Vec3]) -> Scene {
        Scene {
            meshes: vec![Mesh {
                positions: points.to_vec(),
                indices: vec![[0, 0, 0]],
                ..Mesh::default()
            }],
            ..Scene::default()
        }
    }

    /// The camera's −Z passes through the box centre, and every box corner lies inside the
    /// vertical field of view (the bounding sphere fits), with the sphere touching it.
    fn assert_frames(scene: &Scene, lo: Vec3, hi: Vec3) {
        let camera = default_camera(scene);
        let Projection::Perspective { yfov, aspect_ratio } = camera.projection else {
            panic!("default camera must be perspective")
        };
        assert!((yfov - 40f32.to_radians()).abs() < 1e-6);
        assert_eq!(aspect_ratio, None);
        let eye = camera.world_from_camera.w_axis.truncate();
        let forward = camera.world_from_camera.transform_vector3(Vec3::NEG_Z);
        let centre = 0.5 * (lo + hi);
        let to_centre = (centre - eye).normalize();
        assert!(
            forward.dot(to_centre) > 1.0 - 1e-5,
            "camera must look at the centre"
        );
        // The view direction is the documented one.
        assert!((-forward).dot(DEFAULT_VIEW_FROM.normalize()) > 1.0 - 1e-5);
        let radius = 0.5 * (hi - lo).length();
        let radius = if radius > 0.0 {
            radius
        } else {
            Vec3::splat(0.5).length()
        };
        // Sphere tangent to the cone: sin(half angle) = r / d.
        let d = (centre - eye).length();
        assert!((radius / d - (0.5 * yfov).sin()).abs() < 1e-5);
        for i in 0..8 {
            let corner = Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            );
            let angle = forward.angle_between(corner - eye);
            assert!(
                angle <= 0.5 * yfov + 1e-5,
                "corner {corner} outside the field of view"
            );
        }
        // Rigid: unit orthogonal axes.
        let m = camera.world_from_camera;
        assert!((m.x_axis.truncate().length() - 1.0).abs() < 1e-5);
        assert!(m.x_axis.truncate().dot(m.y_axis.truncate()).abs() < 1e-5);
    }

    #[test]
    fn default_camera_frames_a_box() {
        let (lo, hi) = (Vec3::new(-1.0, 2.0, -3.0), Vec3::new(4.0, 3.0, 1.0));
        assert_frames(&scene_with_points(&[lo, hi]), lo, hi);
    }

    #[test]
    fn default_camera_frames_a_flat_box() {
        let (lo, hi) = (Vec3::new(-2.0, 0.0, -2.0), Vec3::new(2.0, 0.0, 2.0));
        assert_frames(&scene_with_points(&[lo, hi]), lo, hi);
    }

    #[test]
    fn default_camera_frames_an_empty_scene_as_the_unit_box() {
        let camera = default_camera(&Scene::default());
        assert!(camera.world_from_camera.is_finite());
        assert_frames(&Scene::default(), Vec3::splat(-0.5), Vec3::splat(0.5));
    }

    #[test]
    fn default_camera_handles_a_single_point() {
        let p = Vec3::new(3.0, -1.0, 2.0);
        let camera = default_camera(&scene_with_points(&[p]));
        assert!(camera.world_from_camera.is_finite());
        let forward = camera.world_from_camera.transform_vector3(Vec3::NEG_Z);
        let eye = camera.world_from_camera.w_axis.truncate();
        assert!(forward.dot((p - eye).normalize()) > 1.0 - 1e-5);
    }

    /// A white Lambertian surface facing the default light has radiance E/π = 3/π; the light
    /// comes from above, from the camera's left and from behind the camera.
    #[test]
    fn default_light_is_over_the_shoulder_with_three_watts_per_square_metre() {
        let scene = scene_with_points(&[Vec3::ZERO, Vec3::ONE]);
        let camera = default_camera(&scene);
        let lights = default_lights(&scene, &camera);
        assert_eq!(lights.len(), 1);
        let Light::Directional {
            direction,
            irradiance,
        } = lights[0]
        else {
            panic!("default light must be directional")
        };
        assert!((direction.length() - 1.0).abs() < 1e-6);
        let albedo = 1.0;
        let radiance_facing = albedo / std::f32::consts::PI * irradiance;
        assert!(
            (radiance_facing - Vec3::splat(3.0 / std::f32::consts::PI))
                .abs()
                .max_element()
                < 1e-6
        );
        let frame = camera.world_from_camera;
        let towards_light = -direction;
        assert!(
            towards_light.dot(frame.transform_vector3(Vec3::Y)) > 0.0,
            "from above"
        );
        assert!(
            towards_light.dot(frame.transform_vector3(Vec3::NEG_X)) > 0.0,
            "from the left"
        );
        assert!(
            towards_light.dot(frame.transform_vector3(Vec3::Z)) > 0.0,
            "from behind the camera"
        );
        // A surface facing the camera is lit at cos θ = 2/3.
        assert!((towards_light.dot(frame.transform_vector3(Vec3::Z)) - 2.0 / 3.0).abs() < 1e-5);
        assert!(describe_lights(&lights).contains("E = 3 W/m²"));
        assert!(describe_camera(&camera).contains("yfov 40°"));
    }
}

/// A value completion chose, and the announcement of what it added (`None` when the scene
/// supplied it).
#[derive(Clone, Debug, PartialEq)]
pub struct Completed<T> {
    /// The camera or light list to render with.
    pub value: T,
    /// What was added, e.g. [`describe_camera`]'s line; `None` if nothing was.
    pub added: Option<String>,
}

/// A camera index the scene does not have.
#[derive(Debug, thiserror::Error)]
#[error(
    "--camera {index}: the scene has {count} camera(s){}",
    if *count == 0 {
        "; leave out --camera to use a default one".to_string()
    } else {
        format!("; use 0 to {}", count - 1)
    }
)]
pub struct NoSuchCamera {
    /// The index asked for.
    pub index: usize,
    /// How many cameras the scene has.
    pub count: usize,
}

/// The camera to render `scene` through: camera `index`, or without one the scene's first
/// camera, or the [`default_camera`] when it has none.
pub fn camera_for(scene: &Scene, index: Option<usize>) -> Result<Completed<Camera>, NoSuchCamera> {
    match index {
        Some(index) => scene
            .cameras
            .get(index)
            .cloned()
            .map(|value| Completed { value, added: None })
            .ok_or(NoSuchCamera {
                index,
                count: scene.cameras.len(),
            }),
        None => Ok(match scene.cameras.first() {
            Some(camera) => Completed {
                value: camera.clone(),
                added: None,
            },
            None => {
                let value = default_camera(scene);
                Completed {
                    added: Some(describe_camera(&value)),
                    value,
                }
            }
        }),
    }
}

/// The lights to render `scene` with: its own followed by `extra`, or the [`default_lights`]
/// (placed relative to `camera`) when both are empty.
pub fn lights_for(scene: &Scene, extra: Vec<Light>, camera: &Camera) -> Completed<Vec<Light>> {
    if scene.lights.is_empty() && extra.is_empty() {
        let value = default_lights(scene, camera);
        return Completed {
            added: Some(describe_lights(&value)),
            value,
        };
    }
    let mut value = scene.lights.clone();
    value.extend(extra);
    Completed { value, added: None }
}

/// Radiance of the default environment, W/(m²·sr): uniform white. A white Lambertian surface
/// under it (unoccluded) has radiance 1, the same as the environment behind it.
pub const DEFAULT_ENVIRONMENT_RADIANCE: f32 = 1.0;

/// Completes `scene` in place for renders that take its first camera and its lights: adds the
/// default camera if it has none and the default lights if it has none. Returns the
/// announcements of what was added.
pub fn complete(scene: &mut Scene) -> Vec<String> {
    let camera = camera_for(scene, None).unwrap_or_else(|_| Completed {
        value: default_camera(scene),
        added: None,
    });
    let lights = lights_for(scene, Vec::new(), &camera.value);
    let mut added = Vec::new();
    if let Some(note) = camera.added {
        scene.cameras.push(camera.value);
        added.push(note);
    }
    if let Some(note) = lights.added {
        scene.lights = lights.value;
        added.push(note);
    }
    added
}
