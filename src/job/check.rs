//! What a job asks for, checked and resolved before and while it runs: [`Job::check`] refuses
//! impossible option combinations before any work; [`Job::camera`] picks the camera;
//! the job's added lights are read and its partial sample range is checked here too.

use super::{CameraChoice, EnvironmentSource, Job, JobError, LightSource, Samples, SceneSource};
use crate::output::OutputFormat;
use crate::output::{OutputPlan, PlanError};
use crate::render::{MAX_IMAGE_SIDE, MAX_PIXELS};
use crate::scene::defaults::{self, Completed};
use crate::scene::light_spec;
use crate::scene::{Camera, Light, Projection, Scene};
use std::ops::Range;
use std::path::Path;

/// Most samples per pixel a job accepts (2^24): beyond it f32 sample sums stop resolving a
/// single sample's contribution.
pub const MAX_SPP: u32 = 1 << 24;

/// Whether `p` is finite and within the ray queries' coordinate bound
/// ([`crate::accel::MAX_COORDINATE`]), as every glTF position must be.
fn within_bounds(p: glam::Vec3) -> bool {
    p.is_finite() && p.abs().max_element() <= crate::accel::MAX_COORDINATE
}

impl Job {
    /// Rejects option combinations that cannot be honoured, before any work is done. Returns
    /// notes for the user (options that have no effect).
    pub fn check(&self) -> Result<Vec<String>, JobError> {
        let mut notes = Vec::new();
        let bad = |m: String| Err(JobError::Options(m));
        if self.settings.spp == 0 {
            return bad("--spp must be at least 1".into());
        }
        if self.settings.spp > MAX_SPP {
            return bad(format!(
                "--spp {} is above the limit of {MAX_SPP}; render shards (--shard) and merge \
                 them for more",
                self.settings.spp
            ));
        }
        let partial = matches!(self.samples, Samples::Range(_) | Samples::Shard { .. });
        if partial && self.settings.aovs.any_ids() {
            return bad(
                "--aov instance_id, material_id and coverage are whole-image results, not \
                 sums that merge: render them without --sample-range/--shard"
                    .into(),
            );
        }
        if partial && self.settings.aovs.any_geometric() {
            return bad(
                "--aov z, position, uv, flow and flow_backward are whole-image results: render \
                 them without --sample-range/--shard"
                    .into(),
            );
        }
        let flows = self.settings.aovs.flow || self.settings.aovs.flow_backward;
        if flows && self.selection.time.is_none() {
            return bad(
                "--aov flow/flow_backward need an animation time: give --time SECONDS (flow \
                 goes to time ± --flow-dt)"
                    .into(),
            );
        }
        if let Some(dt) = self.flow_dt
            && !(dt > 0.0 && dt.is_finite())
        {
            return bad(format!("--flow-dt {dt}: give a positive number of seconds"));
        }
        if partial && self.settings.aovs.annotations {
            return bad(
                "--annotations are counts over every sample of the image, not sums that merge: \
                 render them without --sample-range/--shard"
                    .into(),
            );
        }
        if partial && self.settings.adaptive.is_some() {
            return bad(
                "--adaptive decides per pixel from the whole render's samples: render without \
                 --sample-range/--shard, or give --adaptive 0"
                    .into(),
            );
        }
        if self.denoise && !crate::denoise::AVAILABLE {
            return Err(crate::denoise::DenoiseError::Unavailable.into());
        }
        if partial && self.denoise {
            return bad(
                "--denoise works on a whole image, not on sums that merge: render without \
                 --sample-range/--shard"
                    .into(),
            );
        }
        // The bound the loader puts on a glTF file's cameras, for the job's own.
        let placed = match &self.camera {
            CameraChoice::LookAt {
                position, target, ..
            } => Some((*position, *target)),
            CameraChoice::Given(camera) => {
                Some((camera.world_from_camera.w_axis.truncate(), glam::Vec3::ZERO))
            }
            _ => None,
        };
        if let Some((position, target)) = placed
            && !(within_bounds(position) && within_bounds(target))
        {
            return bad(format!(
                "the camera at {position} looking at {target} lies beyond ±{:e}, where f32 rays \
                 lose all precision (the bound glTF cameras get)",
                crate::accel::MAX_COORDINATE
            ));
        }
        if self.width == Some(0) || self.height == Some(0) {
            return bad("--width and --height must be at least 1".into());
        }
        let side = self.width.max(self.height).unwrap_or(0);
        let pixels = u64::from(self.width.unwrap_or(1)) * u64::from(self.height.unwrap_or(1));
        if side > MAX_IMAGE_SIDE || pixels > MAX_PIXELS {
            return bad(format!(
                "--width/--height {}×{} exceed the limits of {} per side and {} pixels",
                self.width.map_or("auto".to_string(), |w| w.to_string()),
                self.height.map_or("auto".to_string(), |h| h.to_string()),
                MAX_IMAGE_SIDE,
                MAX_PIXELS
            ));
        }
        // Outputs that would replace an input or each other, and files that are not regular
        // (the scene's own buffers and images are left to the command's plan: reading a
        // large .gltf's JSON for every job of a batch would cost more than the check).
        self.plan_files_with(&mut OutputPlan::new(), "", false)
            .map_err(|e| JobError::Options(e.to_string()))?;
        let Some(out) = &self.output else {
            return Ok(notes);
        };
        let format = OutputFormat::from_path(&out.path)?;
        let path = out.path.display();
        if format == OutputFormat::Png && self.settings.aovs.any() {
            return bad(format!(
                "{path}: --aov needs an EXR output (AOVs are linear data); use -o NAME.exr"
            ));
        }
        if out.sidecar && partial {
            return bad(format!(
                "{path}: --sidecar describes a finished image, not a partial render's sums: \
                 render the whole image with --sidecar"
            ));
        }
        if format == OutputFormat::Png && partial {
            return bad(format!(
                "{path}: a partial render (--sample-range, --shard) writes sample sums to EXR; \
                 use -o NAME.exr and combine the parts with glint merge"
            ));
        }
        if format == OutputFormat::Exr && out.png16 {
            return bad(format!(
                "{path}: --png16 applies to PNG output; EXR is always 32-bit float"
            ));
        }
        if format == OutputFormat::Exr && out.exposure_ev != 0.0 {
            notes
                .push("note: --exposure applies to PNG only; the EXR holds linear radiance".into());
        }
        if !out.exposure_ev.is_finite() {
            return bad(format!("--exposure {} is not a number", out.exposure_ev));
        }
        let folder = match out.path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        if !folder.is_dir() {
            return bad(format!(
                "cannot write {path}: the folder {} does not exist; create it first",
                folder.display()
            ));
        }
        Ok(notes)
    }

    /// Bytes the render's own buffers take at `width` × `height`: the film (two half-sample
    /// radiance and weight buffers, alpha), each AOV's film buffer, resolved image and encoder
    /// copy, the ID passes' per-pixel coverage counts and centre hits, the denoiser's inputs and
    /// output, and the image's resolved and encoded copies. An estimate from the buffers'
    /// element sizes (within a factor of about 1.5 of the peak measured), not counting the
    /// scene, which its own budgets bound.
    pub fn memory_estimate(&self, width: u32, height: u32) -> u64 {
        let aovs = &self.settings.aovs;
        // Film: 2 × (Vec3 + f32) + alpha; resolved image and alpha; the encoder's copy.
        let mut per_pixel: u64 = 2 * (12 + 4) + 4 + 16 + 16;
        let mut add = |wanted: bool, bytes: u64| {
            if wanted {
                per_pixel += bytes;
            }
        };
        let denoise = self.denoise;
        add(aovs.albedo || denoise, 3 * 12);
        add(aovs.normal || denoise, 3 * 12);
        add(aovs.depth, 3 * 4);
        add(aovs.instance_id, 3 * 4);
        add(aovs.material_id, 3 * 4);
        // Coverage counts per pixel (a small vector of (id, count)), resolved layers.
        add(aovs.coverage, 64 + 2 * 32);
        add(aovs.any_ids() || aovs.any_geometric(), 48);
        add(aovs.z, 2 * 4);
        add(aovs.position, 2 * 12);
        add(aovs.uv, 2 * 8);
        add(aovs.flow, 2 * 8);
        add(aovs.flow_backward, 2 * 8);
        add(aovs.annotations, 2 * 64);
        add(self.settings.adaptive.is_some(), 16);
        // The denoiser's colour input and output, and the noisy layer kept and encoded.
        add(denoise, 4 * 12);
        u64::from(width) * u64::from(height) * per_pixel
    }

    /// Refuses a render whose [`Self::memory_estimate`] exceeds the job's memory budget
    /// ([`Job::max_memory`], else the default), before any buffer is allocated.
    pub fn check_memory(&self, width: u32, height: u32) -> Result<(), JobError> {
        use crate::output::budget::{human_bytes, memory_budget};
        let budget = self.max_memory.unwrap_or_else(memory_budget);
        let estimate = self.memory_estimate(width, height);
        if estimate > budget {
            return Err(JobError::Options(format!(
                "a {width}×{height} render with these AOVs needs about {} of buffers, more than \
                 the memory budget of {} (--max-memory; the default is half of physical \
                 memory): render smaller, with fewer AOVs, or in tiles of the image with \
                 --shard and glint merge",
                human_bytes(estimate),
                human_bytes(budget)
            )));
        }
        Ok(())
    }

    /// Whether the job writes a camera sidecar beside its image (`--sidecar`, or
    /// `--annotations`, which the sidecar holds).
    pub fn writes_sidecar(&self) -> bool {
        self.output
            .as_ref()
            .is_some_and(|o| o.sidecar || self.settings.aovs.annotations)
            && !matches!(self.samples, Samples::Range(_) | Samples::Shard { .. })
    }

    /// Adds the files this job writes (its image or partial EXR, its sidecar) and reads (the
    /// scene with its buffers and images, lights files, the environment map) to `plan`
    /// ([`OutputPlan`]); `origin` names the job in messages (`[[job]] 2`; empty for a single
    /// render). Fails when an output would replace an input or another output, or a file is
    /// not a regular file.
    pub fn plan_files(&self, plan: &mut OutputPlan, origin: &str) -> Result<(), PlanError> {
        self.plan_files_with(plan, origin, true)
    }

    /// [`Self::plan_files`]; the scene's buffers and images only when `scene_files`.
    fn plan_files_with(
        &self,
        plan: &mut OutputPlan,
        origin: &str,
        scene_files: bool,
    ) -> Result<(), PlanError> {
        let of = if origin.is_empty() {
            String::new()
        } else {
            format!(" of {origin}")
        };
        if let SceneSource::File(path) = &self.scene {
            let label = path.display().to_string();
            if scene_files {
                plan.scene(path, &label)?;
            } else {
                plan.input(path, format!("the scene {label}"))?;
            }
        }
        for light in &self.lights {
            if let LightSource::File(path) = light {
                plan.input(path, "a lights file")?;
            }
        }
        if let Some(EnvironmentSource::File { path, .. }) = &self.environment {
            plan.input(path, "the environment map")?;
        }
        if let Some(out) = &self.output {
            let partial = matches!(self.samples, Samples::Range(_) | Samples::Shard { .. });
            let kind = if partial {
                "the partial EXR"
            } else {
                "the image"
            };
            plan.output(&out.path, format!("{kind}{of}"))?;
            if self.writes_sidecar() {
                plan.output(
                    &crate::output::sidecar_path(&out.path),
                    format!("the sidecar{of} (named after {})", out.path.display()),
                )?;
            }
        }
        Ok(())
    }

    /// Checks the camera choice against `scene` (a camera index that exists) without building
    /// the camera: a default camera may need the scene's rest pose loaded ([`Self::camera`]).
    pub fn check_camera(&self, scene: &Scene) -> Result<(), JobError> {
        if let CameraChoice::Index(i) = &self.camera {
            defaults::camera_for(scene, Some(*i))?;
        }
        Ok(())
    }

    /// The camera the job renders through in `scene`, with the announcement of a default one.
    pub fn camera(&self, scene: &Scene) -> Result<Completed<Camera>, JobError> {
        Ok(match &self.camera {
            CameraChoice::First if scene.cameras.is_empty() && self.selection.time.is_some() => {
                // A sequence renders one file at many times; a camera framed from each time's
                // bounds would move from frame to frame (and the flow to the next frame would
                // not match it). The default camera frames the file as it is stored, with no
                // animation sampled: the same camera at every time.
                let at_rest = crate::scene::gltf::SceneSelection {
                    time: None,
                    ..self.selection.clone()
                };
                let rest = self.scene.load_quietly(&at_rest, &self.load_options)?;
                defaults::camera_for(&rest, None)?
            }
            CameraChoice::First => defaults::camera_for(scene, None)?,
            CameraChoice::Index(i) => defaults::camera_for(scene, Some(*i))?,
            CameraChoice::Given(camera) => Completed {
                value: camera.clone(),
                added: None,
            },
            CameraChoice::LookAt {
                name,
                position,
                target,
                up,
                yfov,
            } => {
                let yfov = match yfov {
                    Some(y) => *y,
                    None => match defaults::camera_for(scene, None)?.value.projection {
                        Projection::Perspective { yfov, .. } => yfov,
                        Projection::Orthographic { .. } => {
                            match defaults::default_camera(scene).projection {
                                Projection::Perspective { yfov, .. } => yfov,
                                Projection::Orthographic { .. } => {
                                    defaults::DEFAULT_YFOV_DEGREES.to_radians()
                                }
                            }
                        }
                    },
                };
                let projection = Projection::Perspective {
                    yfov,
                    aspect_ratio: None,
                };
                Completed {
                    value: Camera::look_at(name, *position, *target, *up, projection),
                    added: None,
                }
            }
        })
    }

    /// The lights the job adds, parsed and read.
    pub(super) fn extra_lights(&self) -> Result<Vec<Light>, JobError> {
        let mut lights = Vec::new();
        for source in &self.lights {
            match source {
                LightSource::Light(light) => lights.push(light.clone()),
                LightSource::Spec(spec) => {
                    lights.push(light_spec::parse_light(spec).map_err(|source| {
                        JobError::LightSpec {
                            spec: spec.clone(),
                            source,
                        }
                    })?)
                }
                LightSource::File(path) => {
                    lights.extend(light_spec::load_lights_file(path).map_err(JobError::LightsFile)?)
                }
            }
        }
        // The bound the loader puts on a glTF file's lights, for the job's own.
        for light in &lights {
            if let Light::Point { position, .. } | Light::Spot { position, .. } = light
                && !within_bounds(*position)
            {
                return Err(JobError::Options(format!(
                    "an added light is at {position}, beyond ±{:e} where f32 rays lose all \
                     precision (the bound glTF lights get)",
                    crate::accel::MAX_COORDINATE
                )));
            }
        }
        Ok(lights)
    }

    /// The samples of a partial job, checked against `spp`; `None` for a full one.
    pub(super) fn partial_samples(&self) -> Result<Option<Range<u32>>, JobError> {
        let spp = self.settings.spp;
        let samples = match self.samples {
            Samples::Range(ref r) => r.clone(),
            Samples::Shard { index, count } => {
                crate::render::partial::shard_samples(spp, index, count)
            }
            Samples::All | Samples::Progressive(_) => return Ok(None),
        };
        if samples.is_empty() || samples.end > spp {
            return Err(JobError::Options(format!(
                "samples {}..{} are not a non-empty part of the {spp} samples per pixel; pick a \
                 range within 0..{spp} (or fewer shards than samples)",
                samples.start, samples.end
            )));
        }
        Ok(Some(samples))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::job::OutputSpec;

    #[test]
    fn bad_options_are_refused_before_any_work() {
        let dir = tempfile::tempdir().unwrap();
        let job = |path: &str, f: &dyn Fn(&mut Job)| {
            let mut job = Job {
                output: Some(OutputSpec {
                    path: dir.path().join(path),
                    ..OutputSpec::default()
                }),
                ..Job::default()
            };
            f(&mut job);
            job.check()
        };
        assert!(job("a.png", &|_| {}).is_ok());
        assert!(job("a.png", &|j| j.settings.aovs.depth = true).is_err());
        assert!(job("a.png", &|j| j.samples = Samples::Range(0..2)).is_err());
        assert!(job("a.exr", &|j| j.output.as_mut().unwrap().png16 = true).is_err());
        assert!(job("a.png", &|j| j.settings.spp = 0).is_err());
        assert!(job("missing/a.png", &|_| {}).is_err());
        // ID AOVs are not sums: a partial render cannot carry them.
        let partial_ids = |j: &mut Job| {
            j.settings.aovs.coverage = true;
            j.samples = Samples::Shard { index: 0, count: 2 };
        };
        assert!(job("a.exr", &partial_ids).is_err());
        assert!(job("a.exr", &|j| j.settings.aovs.instance_id = true).is_ok());
        assert!(job("a.png", &|j| j.settings.aovs.material_id = true).is_err());
        let notes = job("a.exr", &|j| j.output.as_mut().unwrap().exposure_ev = 1.0).unwrap();
        assert_eq!(notes.len(), 1);
    }
}
