//! Scenes, renders and closed forms shared by the renderer's integration tests.
#![allow(dead_code)]

use glam::{DVec3, Mat4, Vec3, Vec4};
use glint::accel::{BackendKind, BuildOptions, Ray};
use glint::render::{self, CameraRays, PixelSampling, RenderOutput, RenderSettings};
use glint::scene::{Camera, Light, Material, Mesh, Projection, Scene};

/// A Lambertian material with reflectance `rho`: a glTF dielectric without specular
/// reflection (KHR_materials_specular's factor 0), whose BRDF is exactly `ρ/π`.
pub fn lambert(rho: Vec3, double_sided: bool) -> Material {
    Material {
        name: "lambert".into(),
        base_color: rho.extend(1.0),
        metallic: 0.0,
        roughness: 1.0,
        specular: 0.0,
        double_sided,
        ..Material::default()
    }
}

/// A smooth metal: `metallic` of the surface a mirror of reflectance Schlick(ρ, 1, cos θ)
/// (ρ at normal incidence), the rest Lambertian (no dielectric specular).
pub fn mirror(rho: Vec3, metallic: f32) -> Material {
    Material {
        name: "mirror".into(),
        base_color: rho.extend(1.0),
        metallic,
        roughness: 0.0,
        specular: 0.0,
        double_sided: false,
        ..Material::default()
    }
}

/// An emitter with radiance `le` and black reflectance.
pub fn emitter(le: Vec3) -> Material {
    Material {
        name: "emitter".into(),
        base_color: Vec4::new(0.0, 0.0, 0.0, 1.0),
        metallic: 0.0,
        specular: 0.0,
        emissive: le,
        double_sided: false,
        ..Material::default()
    }
}

/// A parallelogram `center ± u ± v` as two triangles whose front face looks along `u × v`.
pub fn quad(center: Vec3, u: Vec3, v: Vec3, material: usize) -> Mesh {
    Mesh {
        name: "quad".into(),
        positions: vec![
            center - u - v,
            center + u - v,
            center + u + v,
            center - u + v,
        ],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        material,
        ..Mesh::default()
    }
}

/// Camera-to-world transform of a camera at `eye` looking at `target` (camera −Z), +Y up.
pub fn world_from_look_at(eye: Vec3, target: Vec3, up: Vec3) -> Mat4 {
    ortho(eye, target, up, 1.0, 1.0).world_from_camera
}

/// A perspective camera at `eye` looking at `target`.
pub fn look_at(eye: Vec3, target: Vec3, up: Vec3, yfov: f32) -> Camera {
    let projection = Projection::Perspective {
        yfov,
        aspect_ratio: None,
    };
    Camera::look_at("test", eye, target, up, projection)
}

/// An orthographic camera at `eye` looking at `target`, half-extents `xmag`, `ymag`.
pub fn ortho(eye: Vec3, target: Vec3, up: Vec3, xmag: f32, ymag: f32) -> Camera {
    Camera::look_at(
        "ortho",
        eye,
        target,
        up,
        Projection::Orthographic { xmag, ymag },
    )
}

/// Settings for a 1-spp render at pixel centres.
pub fn centre_settings(width: u32, height: u32) -> RenderSettings {
    RenderSettings {
        integrator: glint::render::Integrator::Direct,
        width,
        height,
        spp: 1,
        sampling: PixelSampling::PixelCenter,
        threads: 2,
        ..RenderSettings::default()
    }
}

/// A ray-query configuration: a backend, and for Embree which kernels.
#[derive(Clone, Copy, Debug)]
pub struct Kernel {
    pub backend: BackendKind,
    pub options: BuildOptions,
}

impl From<BackendKind> for Kernel {
    fn from(backend: BackendKind) -> Self {
        Kernel {
            backend,
            options: BuildOptions::default(),
        }
    }
}

impl std::fmt::Display for Kernel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&glint::accel::configuration_label(
            self.backend,
            &self.options,
        ))
    }
}

/// Every backend and Embree kernel this machine runs ([`glint::accel::every_configuration`]).
pub fn every_kernel() -> Vec<Kernel> {
    glint::accel::every_configuration()
        .into_iter()
        .map(|(backend, options)| Kernel { backend, options })
        .collect()
}

/// Builds `scene` with `kernel` (a backend, or a backend and its build options) and renders it.
pub fn render_with(
    scene: &Scene,
    camera: &Camera,
    kernel: impl Into<Kernel>,
    settings: &RenderSettings,
) -> RenderOutput {
    let kernel = kernel.into();
    let accel = render::prepare(scene, kernel.backend, kernel.options).expect("build");
    render::render(scene, accel.as_ref(), camera, settings, None).expect("render")
}

/// The f32 camera ray the renderer traces through the centre of pixel (x, y).
pub fn centre_ray(camera: &Camera, width: u32, height: u32, x: u32, y: u32) -> Ray {
    CameraRays::new(camera, width, height)
        .expect("camera")
        .ray(x as f32 + 0.5, y as f32 + 0.5)
}

/// A parallelogram in f64 for exact ray intersection.
#[derive(Clone, Copy, Debug)]
pub struct ExactQuad {
    pub center: DVec3,
    pub u: DVec3,
    pub v: DVec3,
}

impl ExactQuad {
    pub fn new(center: Vec3, u: Vec3, v: Vec3) -> Self {
        Self {
            center: center.as_dvec3(),
            u: u.as_dvec3(),
            v: v.as_dvec3(),
        }
    }

    /// Unit front normal (u × v).
    pub fn normal(&self) -> DVec3 {
        self.u.cross(self.v).normalize()
    }

    /// The exact hit of `ray` (taken exactly as its f32 values) with the parallelogram, if
    /// it lies inside by more than `margin` (a fraction of each half-extent), with its t.
    pub fn hit(&self, ray: &Ray, margin: f64) -> Option<(f64, DVec3)> {
        let o = ray.origin.as_dvec3();
        let d = ray.dir.as_dvec3();
        let n = self.normal();
        let den = n.dot(d);
        if den == 0.0 {
            return None;
        }
        let t = n.dot(self.center - o) / den;
        if t <= 0.0 {
            return None;
        }
        let p = o + d * t;
        let rel = p - self.center;
        let a = rel.dot(self.u) / self.u.length_squared();
        let b = rel.dot(self.v) / self.v.length_squared();
        (a.abs() < 1.0 - margin && b.abs() < 1.0 - margin).then_some((t, p))
    }

    /// Whether the parallelogram's interior contains points within `margin` of its edges
    /// along `ray` (for skipping pixels that straddle an edge).
    pub fn near_edge(&self, ray: &Ray, margin: f64) -> bool {
        self.hit(ray, -margin).is_some() && self.hit(ray, margin).is_none()
    }
}

/// Lambertian reflection of a point light: ρ/π · I · cosθ / d² at `p` with normal `n`
/// (0 below the horizon).
pub fn point_light_radiance(rho: Vec3, intensity: Vec3, light: DVec3, p: DVec3, n: DVec3) -> DVec3 {
    let to_light = light - p;
    let d2 = to_light.length_squared();
    let cos = n.dot(to_light) / d2.sqrt();
    if cos <= 0.0 {
        return DVec3::ZERO;
    }
    rho.as_dvec3() / std::f64::consts::PI * intensity.as_dvec3() * cos / d2
}

/// Whether `got` equals `want` to relative error `tol` in every channel (both zero counts).
pub fn close(got: Vec3, want: DVec3, tol: f64) -> bool {
    let got = got.as_dvec3();
    (0..3).all(|i| {
        let (g, w) = (got[i], want[i]);
        if w == 0.0 {
            g == 0.0
        } else {
            ((g - w) / w).abs() < tol
        }
    })
}

/// A scene of one material and the given meshes and lights.
pub fn scene(meshes: Vec<Mesh>, materials: Vec<Material>, lights: Vec<Light>) -> Scene {
    Scene {
        meshes,
        materials,
        lights,
        ..Scene::default()
    }
}

/// The radiance's bits, pixel by pixel and channel by channel: for "the same image" checks.
pub fn image_bits(out: &RenderOutput) -> Vec<u32> {
    out.image
        .pixels
        .iter()
        .flat_map(|p| p.to_array().map(f32::to_bits))
        .collect()
}

/// Every value of an output is finite.
pub fn all_finite(out: &RenderOutput) -> bool {
    out.image.pixels.iter().all(|p| p.is_finite())
        && out
            .aovs
            .albedo
            .iter()
            .chain(&out.aovs.normal)
            .all(|img| img.pixels.iter().all(|p| p.is_finite()))
        && out
            .aovs
            .depth
            .iter()
            .all(|img| img.pixels.iter().all(|p| p.is_finite()))
}

/// A triangle in f64, from a mesh's f32 vertices taken exactly.
#[derive(Clone, Copy, Debug)]
pub struct ExactTriangle {
    pub p: [DVec3; 3],
}

impl ExactTriangle {
    /// The triangles of `mesh`.
    pub fn of_mesh(mesh: &Mesh) -> Vec<ExactTriangle> {
        mesh.indices
            .iter()
            .map(|t| ExactTriangle {
                p: t.map(|i| mesh.positions[i as usize].as_dvec3()),
            })
            .collect()
    }

    /// Unit normal in glTF winding.
    pub fn normal(&self) -> DVec3 {
        (self.p[1] - self.p[0])
            .cross(self.p[2] - self.p[0])
            .normalize()
    }

    /// The exact hit `(t, point, smallest barycentric)` of `ray` (its f32 values taken exactly).
    pub fn hit(&self, ray: &Ray) -> Option<(f64, DVec3, f64)> {
        let o = ray.origin.as_dvec3();
        let d = ray.dir.as_dvec3();
        let e1 = self.p[1] - self.p[0];
        let e2 = self.p[2] - self.p[0];
        let q = d.cross(e2);
        let det = e1.dot(q);
        if det == 0.0 {
            return None;
        }
        let s = o - self.p[0];
        let b1 = s.dot(q) / det;
        let r = s.cross(e1);
        let b2 = d.dot(r) / det;
        let t = e2.dot(r) / det;
        let b0 = 1.0 - b1 - b2;
        let smallest = b0.min(b1).min(b2);
        (t > 0.0 && smallest >= 0.0).then(|| {
            let p = self.p[0] * b0 + self.p[1] * b1 + self.p[2] * b2;
            (t, p, smallest)
        })
    }
}

/// The closest exact hit of `ray` among `triangles`: `(index, point, smallest barycentric)`.
pub fn closest_exact_hit(triangles: &[ExactTriangle], ray: &Ray) -> Option<(usize, DVec3, f64)> {
    triangles
        .iter()
        .enumerate()
        .filter_map(|(i, tri)| tri.hit(ray).map(|(t, p, b)| (t, i, p, b)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, i, p, b)| (i, p, b))
}

/// The settings of a white-furnace render (the path tracer, Sobol, Russian roulette, two
/// threads): what the furnace tests hold fixed while they vary the scene.
pub struct Furnace {
    pub size: u32,
    pub spp: u32,
    pub seed: u64,
    pub max_depth: u32,
    pub brdf: glint::render::BrdfModel,
}

/// `scene` seen by `camera` under a uniform environment of radiance 1 (the white furnace).
pub fn white_furnace(
    scene: &Scene,
    camera: &Camera,
    backend: BackendKind,
    f: &Furnace,
) -> glint::render::Image<Vec3> {
    let env = glint::light::environment::EnvironmentLight::constant(Vec3::ONE);
    let accel = render::prepare(scene, backend, BuildOptions::default()).expect("build");
    let mut inputs = render::RenderInputs::of_scene(scene, accel.as_ref(), camera);
    inputs.environment = Some(&env);
    let settings = RenderSettings {
        width: f.size,
        height: f.size,
        spp: f.spp,
        seed: f.seed,
        threads: 2,
        max_depth: f.max_depth,
        sampling: PixelSampling::Sobol,
        integrator: render::Integrator::Path,
        russian_roulette: true,
        brdf: f.brdf,
        ..RenderSettings::default()
    };
    let (film, _) = render::render_film(&inputs, &settings, 0..f.spp, None).expect("render");
    film.resolve().0
}
