//! Render benchmarks (`glint bench render`):
//!
//! - [`kernel_bench`]: the same render with the kernel specialised for the scene and with the
//!   fully general kernel, median wall time of each.
//! - [`raw_trace`]: the same camera and shadow rays traced with no shading at all, the
//!   ceiling a renderer's ray throughput can approach.
//!
//! - [`thread_scaling`]: the same render on 1 thread and on all, and the parallel efficiency.
//!
//! `glint bench render` drives them for a glTF scene ([`scene_to_bench`]) or, without one, a
//! procedural scene ([`procedural_scene`]), so it needs no files.

use super::timing::{Scaling, median_duration};
use crate::accel::{Accel, Coherence, Hit, Ray};
use crate::geometry::{spawn_ray, spawn_ray_to, triangle_point};
use crate::procedural::Builtin;
use crate::render::{
    self, CameraRays, KernelChoice, KernelFlags, PixelSampler, RenderError, RenderSettings,
};
use crate::scene::{self, Camera, Light, Material, Mesh, Projection, Scene};
use glam::Vec3;
use rayon::prelude::*;
use std::fmt;
use std::time::{Duration, Instant};

/// Result of [`kernel_bench`].
#[derive(Clone, Debug)]
pub struct KernelBenchReport {
    /// Median render time with the specialised kernel.
    pub specialised: Duration,
    /// Median render time with the general kernel.
    pub general: Duration,
    /// Renders of each kernel.
    pub runs: usize,
    /// Rays traced per render (equal for both kernels).
    pub rays: u64,
    /// What the specialised kernel leaves out.
    pub flags: KernelFlags,
    /// The same renders' per-hit work the specialised kernel skipped, as printed by `glint
    /// render`.
    pub not_modelled: Vec<&'static str>,
}

impl KernelBenchReport {
    /// General time / specialised time.
    pub fn speedup(&self) -> f64 {
        self.general.as_secs_f64() / self.specialised.as_secs_f64().max(1e-12)
    }
}

impl fmt::Display for KernelBenchReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mrays = |d: Duration| self.rays as f64 / d.as_secs_f64().max(1e-12) / 1e6;
        write!(
            f,
            "specialised kernel {:.3} s ({:.1} Mrays/s), general kernel {:.3} s ({:.1} Mrays/s): \
             {:.2}× (median of {}; skipped: {})",
            self.specialised.as_secs_f64(),
            mrays(self.specialised),
            self.general.as_secs_f64(),
            mrays(self.general),
            self.speedup(),
            self.runs,
            if self.not_modelled.is_empty() {
                "nothing".to_string()
            } else {
                self.not_modelled.join(", ")
            }
        )
    }
}

/// Renders `scene` `runs` times with each kernel (alternating, so drift affects both alike)
/// and reports the median time of each. `settings.kernel` is ignored.
pub fn kernel_bench(
    scene: &Scene,
    accel: &dyn Accel,
    camera: &Camera,
    settings: &RenderSettings,
    runs: usize,
) -> Result<KernelBenchReport, RenderError> {
    let runs = runs.max(1);
    let mut times = [Vec::new(), Vec::new()];
    let mut rays = 0;
    let mut flags = None;
    let mut not_modelled = Vec::new();
    for _ in 0..runs {
        for (slot, kernel) in [KernelChoice::Specialised, KernelChoice::General]
            .into_iter()
            .enumerate()
        {
            let s = RenderSettings {
                kernel,
                ..*settings
            };
            let out = render::render(scene, accel, camera, &s, None)?;
            times[slot].push(out.stats.elapsed);
            rays = out.stats.rays.traced();
            if kernel == KernelChoice::Specialised {
                flags = Some(out.stats.kernel);
                not_modelled = out.stats.not_modelled();
            }
        }
    }
    let [specialised, general] = times.map(|t| median_duration(&t));
    Ok(KernelBenchReport {
        specialised,
        general,
        runs,
        rays,
        flags: flags.unwrap_or(KernelFlags::for_scene(
            &scene::SceneFeatures::of(scene),
            KernelChoice::Specialised,
        )),
        not_modelled,
    })
}

/// Result of [`thread_scaling`]: the median render times and the scaling they give.
#[derive(Clone, Copy, Debug)]
pub struct ThreadScaling {
    /// Median render time on one thread.
    pub one: Duration,
    /// Median render time on `scaling.threads` threads.
    pub all: Duration,
    /// Speed-up and parallel efficiency from one thread to all.
    pub scaling: Scaling,
}

/// Renders with 1 thread and with `threads` threads (alternating, `runs` times each) and
/// reports the median times.
pub fn thread_scaling(
    scene: &Scene,
    accel: &dyn Accel,
    camera: &Camera,
    settings: &RenderSettings,
    threads: usize,
    runs: usize,
) -> Result<ThreadScaling, RenderError> {
    let mut times = [Vec::new(), Vec::new()];
    for _ in 0..runs.max(1) {
        for (slot, n) in [1, threads].into_iter().enumerate() {
            let s = RenderSettings {
                threads: n,
                ..*settings
            };
            times[slot].push(
                render::render(scene, accel, camera, &s, None)?
                    .stats
                    .elapsed,
            );
        }
    }
    let [one, all] = times.map(|t| median_duration(&t));
    Ok(ThreadScaling {
        one,
        all,
        scaling: Scaling::of_times(threads, one, all),
    })
}

/// Per-worker buffers of [`raw_trace`]: camera rays, hits, shadow rays, occlusion.
type RawBuffers = (Vec<Ray>, Vec<Option<Hit>>, Vec<Ray>, Vec<bool>);

/// Rays traced by [`raw_trace`] and its time.
#[derive(Clone, Copy, Debug)]
pub struct RawTrace {
    /// Wall time.
    pub elapsed: Duration,
    /// Camera rays traced.
    pub camera_rays: u64,
    /// Shadow rays traced.
    pub shadow_rays: u64,
}

impl RawTrace {
    /// Millions of rays per second.
    pub fn mrays_per_second(&self) -> f64 {
        (self.camera_rays + self.shadow_rays) as f64 / self.elapsed.as_secs_f64().max(1e-12) / 1e6
    }
}

/// Traces what a direct-lighting render of `scene` traces, with the same batches, tiles and
/// threads, but no shading: per tile and sample, the camera rays as one coherent batch, then
/// one shadow ray per hit and light (toward every light, no facing or cone test) as one batch.
pub fn raw_trace(
    scene: &Scene,
    accel: &dyn Accel,
    camera: &Camera,
    settings: &RenderSettings,
) -> Result<RawTrace, RenderError> {
    let camera_rays = CameraRays::for_render(camera, settings.width, settings.height)?;
    let sampler = PixelSampler::new(settings.sampling, settings.spp, settings.seed);
    let pool = render::thread_pool(settings.threads, accel.kind())?;
    let tiles = render::tiles::tiles(settings.width, settings.height, render::tiles::TILE_SIZE);
    let start = Instant::now();
    let counts: Vec<(u64, u64)> = pool.install(|| {
        tiles
            .par_iter()
            .map_init(
                || (Vec::new(), Vec::new(), Vec::new(), Vec::new()),
                |(rays, hits, shadows, occluded): &mut RawBuffers, tile| {
                    let (mut n_camera, mut n_shadow) = (0, 0);
                    for sample in 0..settings.spp {
                        rays.clear();
                        for local in 0..tile.pixel_count() {
                            let (x, y) = tile.pixel(local);
                            let o = sampler.offset(x, y, sample);
                            rays.push(camera_rays.ray(x as f32 + o.x, y as f32 + o.y));
                        }
                        hits.clear();
                        hits.resize(rays.len(), None);
                        accel.intersect_many(rays, hits, Coherence::Coherent);
                        n_camera += rays.len() as u64;
                        shadows.clear();
                        for light in &scene.lights {
                            for hit in hits.iter().flatten() {
                                if let Some(ray) = shadow_ray(scene, hit, light) {
                                    shadows.push(ray);
                                }
                            }
                        }
                        occluded.clear();
                        occluded.resize(shadows.len(), false);
                        accel.occluded_many(shadows, occluded, Coherence::Coherent);
                        n_shadow += shadows.len() as u64;
                    }
                    (n_camera, n_shadow)
                },
            )
            .collect()
    });
    let elapsed = start.elapsed();
    Ok(RawTrace {
        elapsed,
        camera_rays: counts.iter().map(|c| c.0).sum(),
        shadow_rays: counts.iter().map(|c| c.1).sum(),
    })
}

/// The shadow ray the renderer would spawn from `hit` toward `light` (no facing test).
fn shadow_ray(scene: &Scene, hit: &Hit, light: &Light) -> Option<Ray> {
    let mesh = scene.meshes.get(hit.geom_id as usize)?;
    let tri = mesh.indices.get(hit.prim_id as usize)?;
    let [p0, p1, p2] = mesh.world_triangle(hit.instance, *tri)?;
    let (p, err) = triangle_point(p0, p1, p2, hit.u, hit.v);
    Some(match light {
        Light::Point { position, .. } | Light::Spot { position, .. } => {
            spawn_ray_to(p, err, hit.ng, *position)
        }
        Light::Directional { direction, .. } => spawn_ray(p, err, hit.ng, -*direction),
    })
}

/// A benchmark scene that needs no files: a procedural mesh (grey Lambertian, single-sided)
/// lit by a point light and a directional light, and a camera framing it.
pub fn procedural_scene(builtin: Builtin, seed: u64) -> (Scene, Camera) {
    let owned = builtin.generate(seed);
    let mesh = Mesh {
        name: format!("procedural {}", builtin.name()),
        positions: owned.positions,
        indices: owned.indices,
        material: 0,
        ..Mesh::default()
    };
    let material = Material {
        name: "grey".into(),
        base_color: glam::Vec4::new(0.6, 0.6, 0.6, 1.0),
        metallic: 0.0,
        ..Material::default()
    };
    let eye = Vec3::new(0.0, 1.6, 2.6);
    let projection = Projection::Perspective {
        yfov: 0.9,
        aspect_ratio: None,
    };
    let camera = Camera::look_at("bench", eye, Vec3::ZERO, Vec3::Y, projection);
    let lights = vec![
        Light::Point {
            position: Vec3::new(1.5, 2.5, 2.0),
            intensity: Vec3::splat(20.0),
            range: None,
        },
        Light::Directional {
            direction: Vec3::new(-0.3, -1.0, -0.2).normalize(),
            irradiance: Vec3::splat(1.0),
        },
    ];
    let scene = Scene {
        meshes: vec![mesh],
        materials: vec![material],
        lights,
        ..Scene::default()
    };
    (scene, camera)
}

/// A glTF scene completed for benchmarking ([`scene::defaults::complete`]: its first camera or
/// the default one, its lights or the default ones) and its camera.
pub fn scene_to_bench(path: &std::path::Path) -> Result<(Scene, Camera), scene::gltf::LoadError> {
    scene_to_bench_with(path, &scene::gltf::LoadOptions::default())
}

/// Like [`scene_to_bench`], loading under `options` (asset root, texture budget).
pub fn scene_to_bench_with(
    path: &std::path::Path,
    options: &scene::gltf::LoadOptions,
) -> Result<(Scene, Camera), scene::gltf::LoadError> {
    let mut scene = scene::gltf::load_full(path, &scene::gltf::SceneSelection::default(), options)
        .map(scene::gltf::print_warnings)?;
    scene::defaults::complete(&mut scene);
    let camera = scene
        .cameras
        .first()
        .cloned()
        .unwrap_or_else(|| scene::defaults::default_camera(&scene));
    Ok((scene, camera))
}
