//! The environment light: radiance arriving from infinitely far away, from a constant colour
//! or an equirectangular (latitude-longitude) image.
//!
//! # Mapping
//!
//! Blender's, after its glTF import, so an HDRI looks the same in both. For a unit world
//! direction `d = (x, y, z)` (glTF, +Y up) and the rotation `rot` (radians, a right-handed turn
//! of the environment about +Y):
//!
//! ```text
//! u = frac(0.5 + (atan2(z, x) + rot) / 2π)    from the image's left edge
//! v = acos(y) / π                              from its top row
//! ```
//!
//! so with `rot = 0`, +X is the image centre, −Z is u = 0.25, +Z is u = 0.75 and −X the seam.
//! The inverse, used to turn a sampled `(u, v)` into a direction, is
//! `φ = 2π(u − ½) − rot`, `θ = πv`, `d = (sin θ cos φ, cos θ, sin θ sin φ)`.
//!
//! # Lookup
//!
//! [`Interpolation::Bilinear`] (the default) matches Blender's "Linear" environment texture:
//! texel `(i, j)` has its centre at `((i + ½)/w, (j + ½)/h)`, and a lookup blends the four
//! nearest centres, wrapping around in u (the seam is continuous) and clamping in v (a
//! lookup above the top row's centre takes the top row). [`Interpolation::Nearest`] returns
//! the texel containing `(u, v)`. `strength` multiplies every texel.
//!
//! # Importance sampling
//!
//! A [`Distribution2D`] over `sw × sh` cells of the unit square, cell `(a, b)` weighted by
//! `c(L(u_a, v_b)) · sin θ_b`, where `(u_a, v_b)` is the cell's centre, `θ_b = π v_b` its polar
//! angle, `L` the *looked-up* radiance and `c` the average of its three channels (pbrt-v4's
//! choice: a saturated lamp is sampled in proportion to its own channel, which luminance would
//! under-weight by up to ~4.6× for blue).
//!
//! For nearest lookup the cells are the texels (`s = 1`). For bilinear lookup the map is
//! supersampled, [`SUPERSAMPLING`] cells per texel along each axis (as Cycles builds its
//! importance map), so that the density follows the lookup inside a texel instead of being
//! constant over it: next to an isolated bright texel the bilinear lookup falls off linearly,
//! and a per-texel constant density leaves `L/p` up to 16× its cell mean at the corners.
//! With `s` even every cell lies inside one bilinear patch (between four texel centres), where
//! the lookup is bilinear, so its value at the cell centre is exactly its mean over the cell.
//! Size rule: `s` is 2 where that makes at most [`MAX_SAMPLING_CELLS`] cells (4096 × 2048,
//! about 64 MiB of tables), else 1, so a 1k × 512 or 2k × 1k HDRI gets 2 × 2 cells per texel
//! and a 4k or 8k one its own texels (whose lookup already varies little across a cell).
//! Two, not Cycles' four: the tables are read at random, so their size is cache misses on
//! every light sample, and building them is start-up. Measured under `studio.exr` (1k × 512)
//! at 128 spp, 256 × 256: 4 × 4 cells cost 4–5 % more CPU per render than 2 × 2 (paired, three
//! runs each) for 0.4–0.6 % lower relMSE, and one cell per texel gives 1–3 % more relMSE
//! than 2 × 2 for no saving (docs/speed.md, "Where the remaining factor sits"). A sampled `(u, v)` with density `p(u, v)` becomes a direction with the
//! solid-angle density
//!
//! ```text
//! p(ω) = p(u, v) / (2π² sin θ)      (dω = 2π² sin θ du dv)
//! ```
//!
//! with θ the direction's own polar angle. The estimator is unbiased: with `s = 1` the cell
//! weight is the exact cell average of the lookup (the separable blend `⅛ L_{i−1} + ¾ L_i +
//! ⅛ L_{i+1}` in each axis for bilinear), and with `s` even the centre value is a blend of the
//! same four texels as every point of the cell with all four weights positive; either way the
//! density is positive wherever the radiance is (the two poles, a set of measure zero,
//! aside). A constant environment is sampled uniformly over
//! the sphere (`p = 1/4π`).

mod fast_angle;
mod load;

pub use fast_angle::MAX_ERROR as FAST_ANGLE_MAX_ERROR;

pub use load::{DEFAULT_PIXEL_BUDGET, EnvImage, read_env_image};

use crate::sampling::distribution::{Distribution2D, ONE_MINUS_EPSILON};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI, TAU};
use std::path::{Path, PathBuf};

/// Cells per texel along each axis of a bilinear map's sampling distribution (module doc):
/// even, so that every cell lies inside one bilinear patch.
pub const SUPERSAMPLING: usize = 2;
const _: () = assert!(SUPERSAMPLING.is_multiple_of(2));

/// Most cells of a sampling distribution before [`SUPERSAMPLING`] is reduced (4096 × 2048).
pub const MAX_SAMPLING_CELLS: usize = 4096 * 2048;

/// An environment that cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum EnvironmentError {
    /// The file cannot be opened or read.
    #[error("environment {}: {source}; check the --env path", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// Neither an OpenEXR nor a Radiance HDR file.
    #[error(
        "environment {}: not an OpenEXR (.exr) or Radiance HDR (.hdr) file; convert it to one of those, e.g. `oiiotool in.png -o out.exr`",
        path.display()
    )]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// The header cannot be read.
    #[error("environment {} ({format}): {message}; the file may be truncated or not an equirectangular image", path.display())]
    Decode {
        /// The file.
        path: PathBuf,
        /// "OpenEXR" or "Radiance HDR".
        format: &'static str,
        /// The decoder's message.
        message: String,
    },
    /// The EXR's pixels cannot be decoded (an unsupported compression, missing R, G, B
    /// channels, or damaged data).
    #[error(
        "environment {} (OpenEXR, {compression} compression): cannot read its RGB pixels: {message}; if the compression is the problem, convert it, e.g. `oiiotool in.exr --compression zip -o out.exr` or re-save it from Blender with ZIP compression",
        path.display()
    )]
    ExrPixels {
        /// The file.
        path: PathBuf,
        /// The compression named in its header.
        compression: String,
        /// The decoder's message.
        message: String,
    },
    /// The image has no pixels.
    #[error("environment {}: the image has no pixels", path.display())]
    Empty {
        /// The file.
        path: PathBuf,
    },
    /// The image is over the pixel budget (checked before decoding).
    #[error(
        "environment {}: {width}×{height} texels exceed the budget of {budget}; downscale it, e.g. `oiiotool in.exr --resize 8192x4096 -o out.exr`",
        path.display()
    )]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Columns in the header.
        width: u64,
        /// Rows in the header.
        height: u64,
        /// The budget in texels.
        budget: u64,
    },
    /// Some texels are NaN or infinite.
    #[error(
        "environment {}: {count} texels are not finite (NaN or infinite), the first at column {x}, row {y}; repair the image (e.g. clamp it in an image editor) before using it as a light",
        path.display()
    )]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// How many texels.
        count: usize,
        /// Column of the first.
        x: usize,
        /// Row of the first (from the top).
        y: usize,
    },
    /// A parameter is out of range.
    #[error(
        "environment: {what} {value} must be {must}; fix --env-strength, --env-rotation or --background"
    )]
    Parameter {
        /// Which parameter.
        what: &'static str,
        /// Its value.
        value: String,
        /// What it must be.
        must: &'static str,
    },
    /// The texel count does not match the size.
    #[error("environment: {texels} texels for a {width}×{height} image")]
    Size {
        /// Columns.
        width: usize,
        /// Rows.
        height: usize,
        /// Texels given.
        texels: usize,
    },
}

/// How an image environment is looked up between texel centres.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Interpolation {
    /// The texel containing the direction.
    Nearest,
    /// Blend of the four nearest texel centres (Blender's "Linear"), the default.
    #[default]
    Bilinear,
}

/// Options for an image environment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvOptions {
    /// Multiplies the radiance (finite, ≥ 0).
    pub strength: f32,
    /// A right-handed turn of the environment about +Y, in degrees (finite).
    pub rotation_deg: f32,
    /// The lookup between texel centres.
    pub interpolation: Interpolation,
    /// The most texels an image may have (checked before decoding a file).
    pub pixel_budget: u64,
    /// Cells per texel along each axis of the sampling distribution; `None` (the default)
    /// applies the module doc's rule ([`SUPERSAMPLING`] for bilinear lookup within
    /// [`MAX_SAMPLING_CELLS`], 1 for nearest). For experiments; an odd count above 1 is
    /// rounded up to even (its cells would straddle bilinear patches).
    pub cells_per_texel: Option<usize>,
}

impl Default for EnvOptions {
    fn default() -> Self {
        Self {
            strength: 1.0,
            rotation_deg: 0.0,
            interpolation: Interpolation::Bilinear,
            pixel_budget: DEFAULT_PIXEL_BUDGET,
            cells_per_texel: None,
        }
    }
}

/// A direction sampled from the environment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvSample {
    /// Unit world direction toward the environment.
    pub wi: Vec3,
    /// Radiance arriving along `-wi` (strength applied), W/(m²·sr).
    pub radiance: Vec3,
    /// Density of `wi` with respect to solid angle (> 0).
    pub pdf: f32,
}

/// Which distribution environment directions are drawn from (module doc, "MIS
/// compensation").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EnvSampling {
    /// Proportional to the lookup: the only choice where nothing else samples the
    /// environment (light sampling alone, the direct integrator).
    #[default]
    Full,
    /// Proportional to the lookup's excess over its mean, `max(c − c̄, 0)`: only where BSDF
    /// sampling, combined by MIS, covers every direction too.
    Compensated,
}

#[derive(Clone, Debug)]
struct Map {
    width: usize,
    height: usize,
    texels: Vec<Vec3>,
    interpolation: Interpolation,
    /// Whether some texel is not black (else there is nothing to sample).
    emits: bool,
    /// The two distributions, each built on first use (a render uses one): `None` when its
    /// weights are all zero.
    full: std::sync::OnceLock<Option<Distribution2D>>,
    compensated: std::sync::OnceLock<Option<Distribution2D>>,
    /// Cells of the distributions per texel along each axis.
    cells_per_texel: usize,
}

#[derive(Clone, Debug)]
enum Kind {
    Constant(Vec3),
    Map(Box<Map>),
}

/// The environment light (see the module doc for the mapping, lookup and sampling).
#[derive(Clone, Debug)]
pub struct EnvironmentLight {
    kind: Kind,
    /// Rotation about +Y in radians.
    rotation: f32,
}

impl EnvironmentLight {
    /// Loads an equirectangular `.hdr` or `.exr` with bilinear lookup and the default pixel
    /// budget; `strength` multiplies the radiance, `rotation_deg` turns it about +Y.
    pub fn from_file(
        path: &Path,
        strength: f32,
        rotation_deg: f32,
    ) -> Result<Self, EnvironmentError> {
        Self::from_file_with(
            path,
            &EnvOptions {
                strength,
                rotation_deg,
                ..EnvOptions::default()
            },
        )
    }

    /// Loads an equirectangular `.hdr` or `.exr` with the given options.
    pub fn from_file_with(path: &Path, options: &EnvOptions) -> Result<Self, EnvironmentError> {
        check_options(options)?;
        let image = read_env_image(path, options.pixel_budget)?;
        Self::from_image(image, options)
    }

    /// An environment from texels already in memory (row 0 at the top). Negative channels
    /// are clamped to 0; non-finite ones are an error.
    pub fn from_image(image: EnvImage, options: &EnvOptions) -> Result<Self, EnvironmentError> {
        check_options(options)?;
        let EnvImage {
            width,
            height,
            mut texels,
        } = image;
        if width.checked_mul(height) != Some(texels.len()) || texels.is_empty() {
            return Err(EnvironmentError::Size {
                width,
                height,
                texels: texels.len(),
            });
        }
        if let Some(k) = texels.iter().position(|t| !t.is_finite()) {
            return Err(EnvironmentError::NonFinite {
                path: PathBuf::from("(in memory)"),
                count: texels.iter().filter(|t| !t.is_finite()).count(),
                x: k % width,
                y: k / width,
            });
        }
        for t in &mut texels {
            *t = t.max(Vec3::ZERO) * options.strength;
        }
        let map = Map {
            width,
            height,
            emits: texels.iter().any(|t| t.max_element() > 0.0),
            texels,
            interpolation: options.interpolation,
            full: std::sync::OnceLock::new(),
            compensated: std::sync::OnceLock::new(),
            cells_per_texel: options
                .cells_per_texel
                .map(|s| if s > 1 { s + s % 2 } else { 1 })
                .unwrap_or_else(|| cells_per_texel(width, height, options.interpolation)),
        };
        Ok(Self {
            kind: Kind::Map(Box::new(map)),
            rotation: options.rotation_deg.to_radians(),
        })
    }

    /// A uniform environment of the given radiance in every direction. Negative or
    /// non-finite channels are taken as 0.
    pub fn constant(radiance: Vec3) -> Self {
        let r = Vec3::select(radiance.cmpge(Vec3::ZERO), radiance, Vec3::ZERO);
        let r = Vec3::select(r.is_finite_mask(), r, Vec3::ZERO);
        Self {
            kind: Kind::Constant(r),
            rotation: 0.0,
        }
    }

    /// Whether the radiance is the same in every direction (an integrator may then sample
    /// the BSDF alone, or use a cosine-weighted direction).
    pub fn is_constant(&self) -> bool {
        matches!(self.kind, Kind::Constant(_))
    }

    /// Whether the environment emits nothing anywhere (no sampling, no lookups needed).
    pub fn is_black(&self) -> bool {
        match &self.kind {
            Kind::Constant(c) => *c == Vec3::ZERO,
            Kind::Map(m) => !m.emits,
        }
    }

    /// The image size `(width, height)`, `None` for a constant environment.
    pub fn size(&self) -> Option<(usize, usize)> {
        match &self.kind {
            Kind::Constant(_) => None,
            Kind::Map(m) => Some((m.width, m.height)),
        }
    }

    /// The rotation about +Y in radians.
    pub fn rotation(&self) -> f32 {
        self.rotation
    }

    /// The image coordinates `(u, v) ∈ [0, 1)²` of a unit world direction (module doc), both
    /// angles from the polynomial `atan2` of [`fast_angle`]: `u` within
    /// `FAST_ANGLE_MAX_ERROR / 2π` (modulo 1) and `v` within `FAST_ANGLE_MAX_ERROR / π` of the
    /// exact mapping's (under 10⁻³ texel on an 8192-wide map). Every lookup and every density
    /// goes through this one mapping, so escaped rays and environment samples weigh each other
    /// consistently; it is a quarter of the C library's `atan2f` instructions, and every ray
    /// that leaves the scene pays it.
    #[inline]
    pub fn direction_to_uv(&self, d: Vec3) -> Vec2 {
        self.map_direction(d).0
    }

    /// [`direction_to_uv`](Self::direction_to_uv) and `sin θ = √(x² + z²)` (not `√(1 − y²)`:
    /// accurate near the poles, where `1 − y²` cancels), which the mapping computes anyway
    /// and every density divides by.
    #[inline]
    fn map_direction(&self, d: Vec3) -> (Vec2, f32) {
        let phi = fast_angle::fast_atan2(d.z, d.x);
        let u = 0.5 + (phi + self.rotation) / TAU;
        // One turn up or down covers every rotation within ±π; `rem_euclid` (a library call)
        // only for larger ones.
        let u = if (0.0..1.0).contains(&u) {
            u
        } else if (-1.0..0.0).contains(&u) {
            u + 1.0
        } else if (1.0..2.0).contains(&u) {
            u - 1.0
        } else {
            u.rem_euclid(1.0)
        };
        // atan2(sin θ, cos θ) rather than acos(y): accurate near the poles too.
        let sin_theta = (d.x * d.x + d.z * d.z).sqrt();
        let v = fast_angle::fast_atan2(sin_theta, d.y) * FRAC_1_PI;
        // `max` first: a NaN direction reads (·, 0), not NaN (`clamp` would keep the NaN).
        #[allow(clippy::manual_clamp)]
        let v = v.max(0.0).min(ONE_MINUS_EPSILON);
        // A tiny negative plus one rounds to 1.0; keep u inside [0, 1).
        (Vec2::new(u.min(ONE_MINUS_EPSILON), v), sin_theta)
    }

    /// The solid-angle density of `dist` (a distribution over the image) at the direction
    /// whose mapping is `(uv, sin θ)`: the image density over the mapping's Jacobian
    /// `2π² sin θ`; 0 at the poles.
    #[inline]
    fn solid_angle_density(dist: &Distribution2D, uv: Vec2, sin_theta: f32) -> f32 {
        if sin_theta <= 0.0 {
            return 0.0;
        }
        dist.pdf(uv) / (2.0 * PI * PI * sin_theta)
    }

    /// The unit world direction of image coordinates `(u, v)` (inverse of
    /// [`direction_to_uv`](Self::direction_to_uv)).
    #[inline]
    pub fn uv_to_direction(&self, uv: Vec2) -> Vec3 {
        let phi = TAU * (uv.x - 0.5) - self.rotation;
        let theta = PI * uv.y;
        let (sin_t, cos_t) = theta.sin_cos();
        let (sin_p, cos_p) = phi.sin_cos();
        Vec3::new(sin_t * cos_p, cos_t, sin_t * sin_p)
    }

    /// Radiance arriving from the unit world direction `d` (travelling along `-d`).
    #[inline]
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        match &self.kind {
            Kind::Constant(c) => *c,
            Kind::Map(m) => m.lookup(self.direction_to_uv(d)),
        }
    }

    /// The radiance at image coordinates `uv ∈ [0, 1)²` (what [`radiance`](Self::radiance)
    /// reads after mapping its direction), with the map's interpolation.
    #[inline]
    pub fn radiance_at(&self, uv: Vec2) -> Vec3 {
        match &self.kind {
            Kind::Constant(c) => *c,
            Kind::Map(m) => m.lookup(uv),
        }
    }

    /// Samples a direction with density ∝ the lookup's channel average (module doc); `None`
    /// when the environment is black (or, with vanishing probability, at a pole).
    #[inline]
    pub fn sample(&self, u: Vec2) -> Option<EnvSample> {
        self.sample_with(u, EnvSampling::Full)
    }

    /// Builds the distribution `mode` draws from now rather than on the first sample (a
    /// render calls it while it sets up, so that no worker waits for it).
    pub fn prepare(&self, mode: EnvSampling) {
        if let Kind::Map(m) = &self.kind {
            m.distribution(mode);
        }
    }

    /// [`sample`](Self::sample) from the distribution `mode`; the compensated one of a
    /// constant environment (or of a map nowhere brighter than its mean) is empty: `None`.
    #[inline]
    pub fn sample_with(&self, u: Vec2, mode: EnvSampling) -> Option<EnvSample> {
        match &self.kind {
            Kind::Constant(c) => {
                if *c == Vec3::ZERO || mode == EnvSampling::Compensated {
                    return None;
                }
                let z = 1.0 - 2.0 * u.y;
                let r = (1.0 - z * z).max(0.0).sqrt();
                let (s, co) = (TAU * u.x).sin_cos();
                Some(EnvSample {
                    wi: Vec3::new(r * co, z, r * s),
                    radiance: *c,
                    pdf: 0.25 * FRAC_1_PI,
                })
            }
            Kind::Map(m) => {
                let (uv, pdf_uv) = m.distribution(mode).as_ref()?.sample(u);
                let sin_theta = (PI * uv.y).sin();
                if pdf_uv <= 0.0 || sin_theta <= 0.0 {
                    return None;
                }
                Some(EnvSample {
                    wi: self.uv_to_direction(uv),
                    radiance: m.lookup(uv),
                    pdf: pdf_uv / (2.0 * PI * PI * sin_theta),
                })
            }
        }
    }

    /// The solid-angle density with which [`sample`](Self::sample) returns the unit world
    /// direction `d` (for MIS when a BSDF-sampled ray escapes).
    #[inline]
    pub fn pdf(&self, d: Vec3) -> f32 {
        self.pdf_with(d, EnvSampling::Full)
    }

    /// The solid-angle density of [`sample_with`](Self::sample_with) `mode` at `d`.
    #[inline]
    pub fn pdf_with(&self, d: Vec3, mode: EnvSampling) -> f32 {
        match &self.kind {
            Kind::Constant(c) => {
                if *c == Vec3::ZERO || mode == EnvSampling::Compensated {
                    0.0
                } else {
                    0.25 * FRAC_1_PI
                }
            }
            Kind::Map(m) => {
                let Some(dist) = m.distribution(mode) else {
                    return 0.0;
                };
                let (uv, sin_theta) = self.map_direction(d);
                Self::solid_angle_density(dist, uv, sin_theta)
            }
        }
    }

    /// [`radiance`](Self::radiance) and [`pdf`](Self::pdf) of the unit direction `d` at once,
    /// mapping `d` to the image once (for an escaped ray weighed by MIS). The same values as
    /// the two calls.
    #[inline]
    pub fn radiance_and_pdf(&self, d: Vec3) -> (Vec3, f32) {
        self.radiance_and_pdf_with(d, EnvSampling::Full)
    }

    /// [`radiance_and_pdf`](Self::radiance_and_pdf) with the density of `mode`.
    #[inline]
    pub fn radiance_and_pdf_with(&self, d: Vec3, mode: EnvSampling) -> (Vec3, f32) {
        match &self.kind {
            Kind::Constant(_) => (self.radiance(d), self.pdf_with(d, mode)),
            Kind::Map(m) => {
                let (uv, sin_theta) = self.map_direction(d);
                let radiance = m.lookup(uv);
                let pdf = m
                    .distribution(mode)
                    .as_ref()
                    .map_or(0.0, |dist| Self::solid_angle_density(dist, uv, sin_theta));
                (radiance, pdf)
            }
        }
    }

    /// The radiance averaged over the sphere, `(1/4π) ∮ L dω` (for a map, each texel weighted
    /// by its solid angle): a measure of the environment's power for choosing between it and
    /// other lights.
    pub fn average_radiance(&self) -> Vec3 {
        match &self.kind {
            Kind::Constant(c) => *c,
            Kind::Map(m) => {
                let mut sum = glam::DVec3::ZERO;
                for j in 0..m.height {
                    let t0 = PI * j as f32 / m.height as f32;
                    let t1 = PI * (j + 1) as f32 / m.height as f32;
                    // Solid angle of one texel of row j, over 4π.
                    let w = f64::from((t0.cos() - t1.cos()) / (2.0 * m.width as f32));
                    let row: glam::DVec3 = m.texels[j * m.width..(j + 1) * m.width]
                        .iter()
                        .map(|t| t.as_dvec3())
                        .sum();
                    sum += row * w;
                }
                sum.as_vec3()
            }
        }
    }
}

impl Map {
    #[inline]
    fn texel(&self, i: usize, j: usize) -> Vec3 {
        self.texels[j * self.width + i]
    }

    #[inline]
    fn lookup(&self, uv: Vec2) -> Vec3 {
        let (w, h) = (self.width, self.height);
        match self.interpolation {
            Interpolation::Nearest => {
                let i = ((uv.x * w as f32) as usize).min(w - 1);
                let j = ((uv.y * h as f32) as usize).min(h - 1);
                self.texel(i, j)
            }
            Interpolation::Bilinear => {
                // uv ∈ [0, 1)², so x, y ∈ [−0.5, size − 0.5): the floor is −1 below 0 and
                // the truncation above, found without `floorf` or integer division (this
                // runs for every escaped ray). Wrap in u, clamp in v.
                let x = uv.x * w as f32 - 0.5;
                let y = uv.y * h as f32 - 0.5;
                let (i0, fx) = if x < 0.0 {
                    (w - 1, x + 1.0)
                } else {
                    let i = (x as usize).min(w - 1);
                    (i, x - i as f32)
                };
                let i1 = if i0 + 1 == w { 0 } else { i0 + 1 };
                let (j0, j1, fy) = if y < 0.0 {
                    (0, 0, y + 1.0)
                } else {
                    let j = y as usize;
                    ((j).min(h - 1), (j + 1).min(h - 1), y - j as f32)
                };
                let top = self.texel(i0, j0).lerp(self.texel(i1, j0), fx);
                let bottom = self.texel(i0, j1).lerp(self.texel(i1, j1), fx);
                top.lerp(bottom, fy)
            }
        }
    }
}

fn check_options(o: &EnvOptions) -> Result<(), EnvironmentError> {
    if !(o.strength.is_finite() && o.strength >= 0.0) {
        return Err(EnvironmentError::Parameter {
            what: "strength",
            value: o.strength.to_string(),
            must: "finite and non-negative",
        });
    }
    if !o.rotation_deg.is_finite() {
        return Err(EnvironmentError::Parameter {
            what: "rotation",
            value: o.rotation_deg.to_string(),
            must: "finite (degrees)",
        });
    }
    Ok(())
}

/// Cells per texel along each axis of the sampling distribution (module doc's memory rule).
fn cells_per_texel(w: usize, h: usize, interp: Interpolation) -> usize {
    if interp == Interpolation::Nearest {
        return 1;
    }
    [SUPERSAMPLING, 1]
        .into_iter()
        .find(|&s| w.saturating_mul(h).saturating_mul(s * s) <= MAX_SAMPLING_CELLS)
        .unwrap_or(1)
}

/// The weight of a radiance in the sampling distribution: the average of its channels.
#[inline]
fn channel_average(l: Vec3) -> f32 {
    (l.x + l.y + l.z) * (1.0 / 3.0)
}

impl Map {
    /// The distribution of `mode`, built on first use.
    #[inline]
    fn distribution(&self, mode: EnvSampling) -> &Option<Distribution2D> {
        let cell = match mode {
            EnvSampling::Full => &self.full,
            EnvSampling::Compensated => &self.compensated,
        };
        cell.get_or_init(|| {
            let s = self.cells_per_texel;
            let weights = self.sampling_weights(mode);
            Distribution2D::new(&weights, self.width * s, self.height * s)
        })
    }

    /// Per cell of the sampling distribution, the channel average `c` of the lookup's mean
    /// over the cell (or, compensated, `max(c − c̄, 0)` with `c̄` its mean over the sphere)
    /// times the cell centre's sin θ (module doc).
    fn sampling_weights(&self, mode: EnvSampling) -> Vec<f32> {
        let s = self.cells_per_texel;
        let (sw, sh) = (self.width * s, self.height * s);
        let mut cells = if s == 1 {
            texel_averages(self.width, self.height, &self.texels, self.interpolation)
        } else if self.interpolation == Interpolation::Bilinear {
            self.bilinear_at_cell_centres(sw, sh)
        } else {
            let mut out = vec![0.0f32; sw * sh];
            for (b, row) in out.chunks_exact_mut(sw).enumerate() {
                let v = (b as f32 + 0.5) / sh as f32;
                for (a, cell) in row.iter_mut().enumerate() {
                    let u = (a as f32 + 0.5) / sw as f32;
                    *cell = channel_average(self.lookup(Vec2::new(u, v)));
                }
            }
            out
        };
        let sin_row = |b: usize| (PI * (b as f32 + 0.5) / sh as f32).sin();
        if mode == EnvSampling::Compensated {
            // The solid-angle mean: cells weighted by sin θ.
            let (mut sum, mut area) = (0.0f64, 0.0f64);
            for (b, row) in cells.chunks_exact(sw).enumerate() {
                let sin = f64::from(sin_row(b));
                sum += sin * row.iter().map(|&c| f64::from(c)).sum::<f64>();
                area += sin * sw as f64;
            }
            let mean = (sum / area.max(f64::MIN_POSITIVE)) as f32;
            for c in &mut cells {
                *c = (*c - mean).max(0.0);
            }
        }
        for (b, row) in cells.chunks_exact_mut(sw).enumerate() {
            let sin = sin_row(b);
            for c in row {
                *c *= sin;
            }
        }
        cells
    }
}

impl Map {
    /// The channel average of the bilinear lookup at the centre of every cell of an
    /// `sw × sh` grid: the same numbers as `channel_average(lookup(centre))` (the same
    /// operations in the same order), computed separably: each texel row is interpolated
    /// along u once for the cell columns (its neighbours, weights and wrap found once per
    /// column), and each cell row blends two such rows along v. A 1024 × 512 map at 4 × 4
    /// cells per texel needs 8 M blends instead of 8 M full lookups (floors, wraps, four
    /// texel reads each), which made up most of a render's start-up.
    fn bilinear_at_cell_centres(&self, sw: usize, sh: usize) -> Vec<f32> {
        let (w, h) = (self.width, self.height);
        // Per cell column: the two texel columns and the weight of the right one, as
        // `lookup` computes them from the cell centre's u.
        let columns: Vec<(usize, usize, f32)> = (0..sw)
            .map(|a| {
                let u = (a as f32 + 0.5) / sw as f32;
                let x = u * w as f32 - 0.5;
                let x0 = x.floor();
                let i0 = (x0 as i64 + w as i64).rem_euclid(w as i64) as usize;
                (i0, (i0 + 1) % w, x - x0)
            })
            .collect();
        let along_u = |j: usize, out: &mut Vec<Vec3>| {
            let row = &self.texels[j * w..(j + 1) * w];
            out.clear();
            out.extend(
                columns
                    .iter()
                    .map(|&(i0, i1, fx)| row[i0].lerp(row[i1], fx)),
            );
        };
        // The two texel rows the current cell row blends, interpolated along u.
        let (mut upper, mut lower) = (Vec::with_capacity(sw), Vec::with_capacity(sw));
        let mut rows_held: Option<(usize, usize)> = None;
        let mut out = vec![0.0f32; sw * sh];
        for (b, cells) in out.chunks_exact_mut(sw).enumerate() {
            let v = (b as f32 + 0.5) / sh as f32;
            let y = v * h as f32 - 0.5;
            let y0 = y.floor();
            let fy = y - y0;
            let j0 = (y0.max(0.0) as usize).min(h - 1);
            let j1 = ((y0 + 1.0).max(0.0) as usize).min(h - 1);
            if rows_held != Some((j0, j1)) {
                if rows_held.is_some_and(|(_, held_lower)| held_lower == j0) {
                    std::mem::swap(&mut upper, &mut lower);
                } else {
                    along_u(j0, &mut upper);
                }
                along_u(j1, &mut lower);
                rows_held = Some((j0, j1));
            }
            for ((cell, top), bottom) in cells.iter_mut().zip(&upper).zip(&lower) {
                *cell = channel_average(top.lerp(*bottom, fy));
            }
        }
        out
    }
}

/// Per texel, the channel average of the lookup averaged over the texel.
fn texel_averages(w: usize, h: usize, texels: &[Vec3], interp: Interpolation) -> Vec<f32> {
    let lum: Vec<f32> = texels.iter().map(|&t| channel_average(t)).collect();
    match interp {
        Interpolation::Nearest => lum,
        Interpolation::Bilinear => {
            // ⅛ ¾ ⅛ along u (wrapping), then along v (clamped).
            let mut across = vec![0.0f32; w * h];
            for j in 0..h {
                let row = &lum[j * w..(j + 1) * w];
                for i in 0..w {
                    let l = row[(i + w - 1) % w];
                    let r = row[(i + 1) % w];
                    across[j * w + i] = 0.125 * l + 0.75 * row[i] + 0.125 * r;
                }
            }
            let mut out = vec![0.0f32; w * h];
            for j in 0..h {
                let up = j.saturating_sub(1);
                let down = (j + 1).min(h - 1);
                for i in 0..w {
                    out[j * w + i] = 0.125 * across[up * w + i]
                        + 0.75 * across[j * w + i]
                        + 0.125 * across[down * w + i];
                }
            }
            out
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(w: usize, h: usize) -> EnvImage {
        let texels = (0..w * h)
            .map(|k| {
                let (i, j) = (k % w, k / w);
                Vec3::new(
                    (i as f32 + 0.5) / w as f32,
                    (j as f32 + 0.5) / h as f32,
                    1.0,
                )
            })
            .collect();
        EnvImage {
            width: w,
            height: h,
            texels,
        }
    }

    #[test]
    fn radiance_and_pdf_at_once_are_the_two_calls() {
        let env = EnvironmentLight::from_image(ramp(16, 8), &EnvOptions::default()).unwrap();
        for k in 0..200 {
            let d = Vec3::new(
                (k as f32 * 0.7).sin(),
                (k as f32 * 0.31).cos(),
                (k as f32 * 1.3).sin(),
            )
            .normalize();
            let (l, p) = env.radiance_and_pdf(d);
            assert_eq!(
                l.to_array().map(f32::to_bits),
                env.radiance(d).to_array().map(f32::to_bits)
            );
            assert_eq!(p.to_bits(), env.pdf(d).to_bits());
        }
        let c = EnvironmentLight::constant(Vec3::ONE);
        assert_eq!(c.radiance_and_pdf(Vec3::Y), (Vec3::ONE, c.pdf(Vec3::Y)));
    }

    #[test]
    fn separable_cell_weights_are_the_lookups_at_cell_centres() {
        // Odd sizes and 2, 4 and 6 cells per texel, on an irregular map: the separable
        // computation must give exactly the lookup's numbers (same operations, same order).
        let (w, h) = (13, 7);
        let texels = (0..w * h)
            .map(|k| {
                let x = k as f32;
                Vec3::new(
                    (x * 0.37).sin().abs() * 5.0,
                    (x * 1.91).cos().abs(),
                    if k % 11 == 0 { 300.0 } else { 0.02 },
                )
            })
            .collect();
        let image = EnvImage {
            width: w,
            height: h,
            texels,
        };
        for s in [2, 4, 6] {
            let env = EnvironmentLight::from_image(
                image.clone(),
                &EnvOptions {
                    cells_per_texel: Some(s),
                    ..EnvOptions::default()
                },
            )
            .unwrap();
            let Kind::Map(map) = &env.kind else {
                panic!("a map")
            };
            let (sw, sh) = (w * s, h * s);
            let fast = map.bilinear_at_cell_centres(sw, sh);
            for b in 0..sh {
                for a in 0..sw {
                    let uv = Vec2::new((a as f32 + 0.5) / sw as f32, (b as f32 + 0.5) / sh as f32);
                    let slow = channel_average(map.lookup(uv));
                    assert_eq!(
                        fast[b * sw + a].to_bits(),
                        slow.to_bits(),
                        "s {s} ({a}, {b})"
                    );
                }
            }
        }
    }

    #[test]
    fn uv_and_direction_are_inverse() {
        let env = EnvironmentLight::from_image(
            ramp(8, 4),
            &EnvOptions {
                rotation_deg: 33.0,
                ..EnvOptions::default()
            },
        )
        .unwrap();
        for k in 0..100 {
            let uv = Vec2::new((k as f32 * 0.618_034).fract(), 0.005 + 0.0099 * k as f32);
            let back = env.direction_to_uv(env.uv_to_direction(uv));
            let du = (back.x - uv.x).abs();
            assert!(
                du.min(1.0 - du) < 1e-5 && (back.y - uv.y).abs() < 1e-4,
                "{uv} {back}"
            );
        }
    }

    #[test]
    fn bilinear_reproduces_a_linear_ramp_between_centres() {
        let env = EnvironmentLight::from_image(ramp(16, 8), &EnvOptions::default()).unwrap();
        let Kind::Map(m) = &env.kind else {
            unreachable!()
        };
        for &(u, v) in &[(0.3, 0.4), (0.5, 0.5), (0.9, 0.1), (0.05, 0.9)] {
            let l = m.lookup(Vec2::new(u, v));
            assert!(
                (l.x - u).abs() < 1e-5 && (l.y - v).abs() < 1e-5,
                "{u} {v}: {l}"
            );
        }
        // Wraps across the seam: halfway between the last and first column centres.
        let l = m.lookup(Vec2::new(0.0, 0.5));
        assert!((l.x - 0.5).abs() < 1e-5);
        // Clamps at the poles.
        assert!((m.lookup(Vec2::new(0.5, 0.0)).y - 1.0 / 16.0).abs() < 1e-6);
    }

    #[test]
    fn black_and_bad_parameters() {
        let black = EnvImage {
            width: 2,
            height: 1,
            texels: vec![Vec3::ZERO; 2],
        };
        let env = EnvironmentLight::from_image(black, &EnvOptions::default()).unwrap();
        assert!(env.is_black() && env.sample(Vec2::splat(0.5)).is_none());
        assert_eq!(env.pdf(Vec3::X), 0.0);
        let bad = EnvOptions {
            strength: -1.0,
            ..EnvOptions::default()
        };
        assert!(EnvironmentLight::from_image(ramp(2, 2), &bad).is_err());
        let nan = EnvImage {
            width: 1,
            height: 1,
            texels: vec![Vec3::new(f32::NAN, 0.0, 0.0)],
        };
        assert!(matches!(
            EnvironmentLight::from_image(nan, &EnvOptions::default()),
            Err(EnvironmentError::NonFinite { .. })
        ));
        assert!(EnvironmentLight::constant(Vec3::ZERO).is_black());
        assert!(EnvironmentLight::constant(Vec3::ONE).is_constant());
    }
}
