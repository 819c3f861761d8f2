//! What a [`Job`](super::Job) is made of besides its settings: the camera it renders through,
//! the lights and environment it adds, which samples it renders and where the image goes.

use crate::light::environment::{EnvironmentError, EnvironmentLight};
use crate::render::StopRule;
use crate::scene::{Camera, Light};
use glam::Vec3;
use std::ops::Range;
use std::path::PathBuf;

/// Which camera a job renders through.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum CameraChoice {
    /// The scene's first camera, or the default camera if it has none.
    #[default]
    First,
    /// The scene's camera with this index (from 0).
    Index(usize),
    /// A perspective camera placed by position ([`Camera::look_at`]).
    LookAt {
        /// Name in messages.
        name: String,
        /// Camera position, world space.
        position: Vec3,
        /// The point looked at.
        target: Vec3,
        /// The world direction that appears up.
        up: Vec3,
        /// Vertical field of view in radians; `None` keeps the field of view of the camera
        /// [`CameraChoice::First`] picks, or of the default camera if that one is orthographic.
        yfov: Option<f32>,
    },
    /// This camera, as given.
    Given(Camera),
}

/// Lights a job adds to the scene's own, in the job's
/// [`light_units`](super::Job::light_units).
#[derive(Clone, Debug, PartialEq)]
pub enum LightSource {
    /// A light, as given.
    Light(Light),
    /// A light spec (format in docs/render.md, "Scenes without a camera or lights"), parsed
    /// when the job runs.
    Spec(String),
    /// A lights file, read when the job runs.
    File(PathBuf),
}

/// The environment a job renders under: a light at infinity seen by rays that leave the scene.
#[derive(Clone, Debug, PartialEq)]
pub enum EnvironmentSource {
    /// An equirectangular `.hdr` or `.exr` (mapping in [`crate::light::environment`]).
    File {
        /// The image.
        path: PathBuf,
        /// Radiance multiplier.
        strength: f32,
        /// Right-handed turn about +Y, degrees.
        rotation_deg: f32,
    },
    /// A uniform environment of this radiance, W/(m²·sr).
    Constant(Vec3),
}

impl EnvironmentSource {
    /// Loads (or builds) the environment light.
    pub fn light(&self) -> Result<EnvironmentLight, EnvironmentError> {
        match self {
            EnvironmentSource::File {
                path,
                strength,
                rotation_deg,
            } => EnvironmentLight::from_file(path, *strength, *rotation_deg),
            EnvironmentSource::Constant(radiance) => Ok(EnvironmentLight::constant(*radiance)),
        }
    }
}

/// Which samples of [`RenderSettings::spp`](crate::render::RenderSettings::spp) a job renders.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Samples {
    /// All of `0..spp`, resolved into an image.
    #[default]
    All,
    /// Only these sample indices, written as a partial EXR of sums for `glint merge`.
    Range(Range<u32>),
    /// Shard `index` of `count` of `0..spp` (a balanced split), as a partial EXR.
    Shard {
        /// Which shard, from 0.
        index: u32,
        /// How many shards.
        count: u32,
    },
    /// Passes of samples until the rule says stop (`spp` is then ignored).
    Progressive(StopRule),
}

/// Where and how a job's image is written.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OutputSpec {
    /// The file; its extension (.png or .exr) picks the format.
    pub path: PathBuf,
    /// Exposure in stops for PNG output (radiance × 2^EV).
    pub exposure_ev: f32,
    /// 16 bits per channel in PNG output.
    pub png16: bool,
    /// Write the camera sidecar `OUT.json` beside the image (`--sidecar`;
    /// [`crate::output::sidecar`]).
    pub sidecar: bool,
}
