//! The film: accumulates samples per pixel and resolves them into images.
//!
//! Each sample carries the weight its pixel filter gave it ([`super::filter`]); a pixel is
//! `Σ w·L / Σ w` over its own samples only (filter importance sampling: no splats into
//! neighbours), so the result does not depend on the order tiles finish in.

pub use super::aov::Image;
use super::aov::{self, Coverage, GeometricSelection, InstanceSamples, PixelCoverage};
use super::tiles::Tile;
use crate::accel::Hit;
use glam::{Vec2, Vec3};

/// Which auxiliary images (AOVs) to produce alongside the radiance.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AovSelection {
    /// Reflectance ρ at the first hit (0 for misses and unlit back faces).
    pub albedo: bool,
    /// World-space unit shading normal at the first hit, facing the camera (0 for misses).
    pub normal: bool,
    /// Distance from the camera to the first hit in scene units (0 for misses).
    pub depth: bool,
    /// glTF node index of the instance the pixel centre's ray hits ([`super::ids`]).
    pub instance_id: bool,
    /// Material index of the surface the pixel centre's ray hits ([`super::ids`]).
    pub material_id: bool,
    /// Up to [`ids::COVERAGE_LAYERS`] instance IDs per pixel with the fraction of its
    /// samples each covers ([`super::ids`]).
    pub coverage: bool,
    /// Depth along the optical axis at the pixel centre's first hit
    /// ([`super::ground_truth`]).
    pub z: bool,
    /// World-space point of the pixel centre's first hit.
    pub position: bool,
    /// TEXCOORD_0 at the pixel centre's first hit.
    pub uv: bool,
    /// Optical flow to `t + Δ`, pixels.
    pub flow: bool,
    /// Optical flow to `t − Δ`, pixels.
    pub flow_backward: bool,
    /// Per-instance sample counts, visible and amodal ([`super::amodal`]), for per-instance
    /// annotations (masks, areas, boxes): not an image, so allowed with PNG outputs.
    pub annotations: bool,
}

impl AovSelection {
    /// Whether any AOV is selected.
    pub fn any(&self) -> bool {
        self.albedo || self.normal || self.depth || self.any_ids() || self.any_geometric()
    }

    /// Whether any of the geometric AOVs ([`super::ground_truth`]) is selected.
    pub fn any_geometric(&self) -> bool {
        self.z || self.position || self.uv || self.flow || self.flow_backward
    }

    /// The geometric AOVs selected.
    pub fn geometric(&self) -> GeometricSelection {
        GeometricSelection {
            z: self.z,
            position: self.position,
            uv: self.uv,
            flow: self.flow,
            flow_backward: self.flow_backward,
        }
    }

    /// Whether any of the ID AOVs ([`super::ids`]) is selected.
    pub fn any_ids(&self) -> bool {
        self.instance_id || self.material_id || self.coverage
    }

    /// Every image AOV by name, as `--aov`, job files and Python's `aovs=` spell them: the one
    /// list (the command line's `AovName` is tested against it).
    pub const NAMES: [&'static str; 11] = [
        "albedo",
        "normal",
        "depth",
        "instance_id",
        "material_id",
        "coverage",
        "z",
        "position",
        "uv",
        "flow",
        "flow_backward",
    ];

    /// The flag of the AOV called `name` (one of [`Self::NAMES`]), `None` for another name.
    pub fn flag_mut(&mut self, name: &str) -> Option<&mut bool> {
        Some(match name {
            "albedo" => &mut self.albedo,
            "normal" => &mut self.normal,
            "depth" => &mut self.depth,
            "instance_id" => &mut self.instance_id,
            "material_id" => &mut self.material_id,
            "coverage" => &mut self.coverage,
            "z" => &mut self.z,
            "position" => &mut self.position,
            "uv" => &mut self.uv,
            "flow" => &mut self.flow,
            "flow_backward" => &mut self.flow_backward,
            _ => return None,
        })
    }

    /// The selection of the AOVs named (no annotations); `Err` carries the first unknown name.
    pub fn from_names<'a>(names: impl IntoIterator<Item = &'a str>) -> Result<Self, &'a str> {
        let mut selection = Self::default();
        for name in names {
            *selection.flag_mut(name).ok_or(name)? = true;
        }
        Ok(selection)
    }
}

/// The auxiliary images of a render, each the box-filtered average over the pixel's samples.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Aovs {
    /// See [`AovSelection::albedo`].
    pub albedo: Option<Image<Vec3>>,
    /// See [`AovSelection::normal`].
    pub normal: Option<Image<Vec3>>,
    /// See [`AovSelection::depth`].
    pub depth: Option<Image<f32>>,
    /// Coverage: the filter-weighted fraction of camera samples whose ray hit the scene (1
    /// inside objects, 0 where only the environment is seen, fractional on edges). Always
    /// computed (one add per camera hit); EXR outputs carry it as their `A` channel.
    pub alpha: Option<Image<f32>>,
    /// See [`AovSelection::instance_id`]; [`aov::NO_ID`] where the centre ray misses.
    pub instance_id: Option<Image<u32>>,
    /// See [`AovSelection::material_id`]; [`aov::NO_ID`] where the centre ray misses.
    pub material_id: Option<Image<u32>>,
    /// See [`AovSelection::coverage`].
    pub coverage: Option<Coverage>,
    /// The first hit of each pixel centre's ray (`None`: a miss), kept when a geometric AOV
    /// is selected; [`super::ground_truth::resolve`] turns it into the images below.
    pub centre_hits: Option<Image<Option<Hit>>>,
    /// See [`AovSelection::z`]; NaN where invalid (see [`super::ground_truth`]).
    pub z: Option<Image<f32>>,
    /// See [`AovSelection::position`]; NaN where invalid.
    pub position: Option<Image<Vec3>>,
    /// See [`AovSelection::uv`]; NaN where invalid.
    pub uv: Option<Image<Vec2>>,
    /// See [`AovSelection::flow`]; NaN where invalid.
    pub flow: Option<Image<Vec2>>,
    /// See [`AovSelection::flow_backward`]; NaN where invalid.
    pub flow_backward: Option<Image<Vec2>>,
    /// See [`AovSelection::annotations`].
    pub instance_samples: Option<InstanceSamples>,
    /// Samples each pixel took: present when adaptive sampling ran ([`super::adaptive`]);
    /// EXR outputs carry it as the uint32 channel `samples`.
    pub samples: Option<Image<u32>>,
}

/// Per-pixel sums of one tile's samples, in the tile's row-major order.
///
/// Radiance and filter weights are kept in two halves, even and odd sample indices: two
/// independent estimates of each pixel, whose difference estimates the pixel's variance
/// (progressive rendering's error estimate). The integrator adds a sample's radiance to
/// `pending` and calls [`TileSums::end_sample`] once the sample index is done, so each half is
/// a sum over whole samples in sample order, independent of how rays were batched.
#[derive(Clone, Debug, Default)]
pub struct TileSums {
    /// Σ w·L over even sample indices (W/(m²·sr)); `w` is the filter weight.
    pub radiance_even: Vec<Vec3>,
    /// Σ w·L over odd sample indices.
    pub radiance_odd: Vec<Vec3>,
    /// Σ w over even sample indices.
    pub weight_even: Vec<f32>,
    /// Σ w over odd sample indices.
    pub weight_odd: Vec<f32>,
    /// w·L of the sample index in flight (already filter-weighted).
    pub pending: Vec<Vec3>,
    /// Σ w·albedo, if selected (else empty).
    pub albedo: Vec<Vec3>,
    /// Σ w·normal, if selected.
    pub normal: Vec<Vec3>,
    /// Σ w·depth, if selected.
    pub depth: Vec<f32>,
    /// Σ w over samples whose camera ray hit the scene (coverage).
    pub alpha: Vec<f32>,
    /// Centre-ray instance IDs: filled by the first pass only (empty otherwise, and when not
    /// selected).
    pub instance_id: Vec<u32>,
    /// Centre-ray material IDs, as `instance_id`.
    pub material_id: Vec<u32>,
    /// Per-pixel sample counts per instance ID, if coverage or annotations are selected.
    pub coverage: Vec<PixelCoverage>,
    /// Centre-ray first hits: filled by the first pass only, when a geometric AOV is
    /// selected (empty otherwise).
    pub centre_hits: Vec<Option<Hit>>,
    /// Per-pixel sample counts of every instance the rays pierce, if annotations are selected.
    pub amodal: Vec<PixelCoverage>,
}

impl TileSums {
    /// Zeroed sums for `pixels` pixels and the selected AOVs.
    pub fn new(pixels: usize, aovs: AovSelection) -> Self {
        let sized = |on: bool| if on { pixels } else { 0 };
        Self {
            radiance_even: vec![Vec3::ZERO; pixels],
            radiance_odd: vec![Vec3::ZERO; pixels],
            weight_even: vec![0.0; pixels],
            weight_odd: vec![0.0; pixels],
            pending: vec![Vec3::ZERO; pixels],
            albedo: vec![Vec3::ZERO; sized(aovs.albedo)],
            normal: vec![Vec3::ZERO; sized(aovs.normal)],
            depth: vec![0.0; sized(aovs.depth)],
            alpha: vec![0.0; pixels],
            instance_id: Vec::new(),
            material_id: Vec::new(),
            centre_hits: Vec::new(),
            coverage: vec![PixelCoverage::new(); sized(aovs.coverage || aovs.annotations)],
            amodal: vec![PixelCoverage::new(); sized(aovs.annotations)],
        }
    }

    /// Folds the pending radiance of sample index `sample` into its half and clears it.
    /// `weights[i]` is the filter weight pixel `i`'s sample carried.
    pub fn end_sample(&mut self, sample: u32, weights: &[f32]) {
        let (radiance, weight) = if sample.is_multiple_of(2) {
            (&mut self.radiance_even, &mut self.weight_even)
        } else {
            (&mut self.radiance_odd, &mut self.weight_odd)
        };
        for (i, pending) in self.pending.iter_mut().enumerate() {
            if let (Some(r), Some(w), Some(&sample_w)) =
                (radiance.get_mut(i), weight.get_mut(i), weights.get(i))
            {
                *r += *pending;
                *w += sample_w;
            }
            *pending = Vec3::ZERO;
        }
    }
}

/// The whole image's sums, accumulated over one or more passes.
#[derive(Clone, Debug)]
pub struct Film {
    radiance_even: Image<Vec3>,
    radiance_odd: Image<Vec3>,
    weight_even: Image<f32>,
    weight_odd: Image<f32>,
    albedo: Option<Image<Vec3>>,
    normal: Option<Image<Vec3>>,
    depth: Option<Image<f32>>,
    alpha: Image<f32>,
    instance_id: Option<Image<u32>>,
    material_id: Option<Image<u32>>,
    coverage: Option<Vec<PixelCoverage>>,
    centre_hits: Option<Image<Option<Hit>>>,
    amodal: Option<Vec<PixelCoverage>>,
    selection: AovSelection,
}

/// Floor of the relative-error denominator, as a fraction of the image's mean luminance:
/// keeps black pixels (whose relative error is undefined) from dominating the estimate.
pub const RELATIVE_ERROR_FLOOR: f32 = 0.1;

/// The `ε` of the relative error: [`RELATIVE_ERROR_FLOOR`] × `image`'s mean luminance (never
/// zero), so dark pixels are not judged by a relative error of a near-zero value.
pub(super) fn error_floor(image: &Image<Vec3>) -> f64 {
    let n = image.pixels.len().max(1) as f64;
    let mean = image
        .pixels
        .iter()
        .map(|&p| luminance(p) as f64)
        .sum::<f64>()
        / n;
    (RELATIVE_ERROR_FLOOR as f64 * mean).max(f64::MIN_POSITIVE)
}

impl Film {
    /// An empty film.
    pub fn new(width: u32, height: u32, aovs: AovSelection) -> Self {
        let zero3 = || Image::filled(width, height, Vec3::ZERO);
        Self {
            radiance_even: zero3(),
            radiance_odd: zero3(),
            weight_even: Image::filled(width, height, 0.0),
            weight_odd: Image::filled(width, height, 0.0),
            albedo: aovs.albedo.then(zero3),
            normal: aovs.normal.then(zero3),
            depth: aovs.depth.then(|| Image::filled(width, height, 0.0)),
            alpha: Image::filled(width, height, 0.0),
            instance_id: aovs
                .instance_id
                .then(|| Image::filled(width, height, aov::NO_ID)),
            material_id: aovs
                .material_id
                .then(|| Image::filled(width, height, aov::NO_ID)),
            coverage: (aovs.coverage || aovs.annotations)
                .then(|| vec![PixelCoverage::new(); width as usize * height as usize]),
            centre_hits: aovs
                .any_geometric()
                .then(|| Image::filled(width, height, None)),
            amodal: aovs
                .annotations
                .then(|| vec![PixelCoverage::new(); width as usize * height as usize]),
            selection: aovs,
        }
    }

    /// Width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.radiance_even.width, self.radiance_even.height)
    }

    /// Adds a tile's sums at the tile's place. Each pixel belongs to one tile, so the order
    /// in which tiles are added does not change any pixel's value.
    pub fn add_tile(&mut self, tile: &Tile, sums: &TileSums) {
        fn add<T: Copy + std::ops::AddAssign>(image: &mut Image<T>, tile: &Tile, src: &[T]) {
            let width = image.width as usize;
            for (local, value) in src.iter().enumerate().take(tile.pixel_count()) {
                let (x, y) = tile.pixel(local);
                if let Some(dst) = image.pixels.get_mut(y as usize * width + x as usize) {
                    *dst += *value;
                }
            }
        }
        add(&mut self.radiance_even, tile, &sums.radiance_even);
        add(&mut self.radiance_odd, tile, &sums.radiance_odd);
        add(&mut self.weight_even, tile, &sums.weight_even);
        add(&mut self.weight_odd, tile, &sums.weight_odd);
        if let Some(image) = &mut self.albedo {
            add(image, tile, &sums.albedo);
        }
        if let Some(image) = &mut self.normal {
            add(image, tile, &sums.normal);
        }
        if let Some(image) = &mut self.depth {
            add(image, tile, &sums.depth);
        }
        add(&mut self.alpha, tile, &sums.alpha);
        // IDs are set, not summed: only the pass that traced the centre rays has them.
        fn set(image: &mut Image<u32>, tile: &Tile, src: &[u32]) {
            let width = image.width as usize;
            for (local, &value) in src.iter().enumerate().take(tile.pixel_count()) {
                let (x, y) = tile.pixel(local);
                if let Some(dst) = image.pixels.get_mut(y as usize * width + x as usize) {
                    *dst = value;
                }
            }
        }
        if let Some(image) = &mut self.instance_id {
            set(image, tile, &sums.instance_id);
        }
        if let Some(image) = &mut self.material_id {
            set(image, tile, &sums.material_id);
        }
        if let Some(image) = &mut self.centre_hits {
            let width = image.width as usize;
            for (local, &hit) in sums.centre_hits.iter().enumerate().take(tile.pixel_count()) {
                let (x, y) = tile.pixel(local);
                if let Some(dst) = image.pixels.get_mut(y as usize * width + x as usize) {
                    *dst = hit;
                }
            }
        }
        fn add_counts(image: &mut [PixelCoverage], width: u32, tile: &Tile, src: &[PixelCoverage]) {
            for (local, counts) in src.iter().enumerate().take(tile.pixel_count()) {
                let (x, y) = tile.pixel(local);
                if let Some(dst) = image.get_mut(y as usize * width as usize + x as usize) {
                    for &(id, n) in counts {
                        aov::count(dst, id, n);
                    }
                }
            }
        }
        let width = self.radiance_even.width;
        if let Some(coverage) = &mut self.coverage {
            add_counts(coverage, width, tile, &sums.coverage);
        }
        if let Some(amodal) = &mut self.amodal {
            add_counts(amodal, width, tile, &sums.amodal);
        }
    }

    /// The unresolved sums: `Σ w·L` and the AOVs' `Σ w·value` per pixel, and `Σ w`. Partial
    /// renders write these so that parts can be merged before dividing.
    pub fn into_sums(self) -> (Image<Vec3>, Aovs, Image<f32>) {
        let add3 = |a: Image<Vec3>, b: &Image<Vec3>| Image {
            pixels: a
                .pixels
                .iter()
                .zip(&b.pixels)
                .map(|(x, y)| *x + *y)
                .collect(),
            ..a
        };
        let radiance = add3(self.radiance_even, &self.radiance_odd);
        let weight = Image {
            pixels: (self.weight_even.pixels.iter().zip(&self.weight_odd.pixels))
                .map(|(x, y)| x + y)
                .collect(),
            ..self.weight_even
        };
        (
            radiance,
            // Partial renders carry no ID AOVs (jobs refuse them): IDs are not sums.
            Aovs {
                albedo: self.albedo,
                normal: self.normal,
                depth: self.depth,
                alpha: Some(self.alpha),
                ..Aovs::default()
            },
            weight,
        )
    }

    fn total_weight(&self, i: usize) -> f32 {
        self.weight_even.pixels[i] + self.weight_odd.pixels[i]
    }

    /// The reconstructed radiance `Σ w·L / Σ w` (0 where no weight arrived).
    pub fn radiance(&self) -> Image<Vec3> {
        let (width, height) = self.size();
        let pixels = (0..self.radiance_even.pixels.len())
            .map(|i| {
                let sum = self.radiance_even.pixels[i] + self.radiance_odd.pixels[i];
                safe_div3(sum, self.total_weight(i))
            })
            .collect();
        Image {
            width,
            height,
            pixels,
        }
    }

    /// Per-pixel variance of the reconstructed radiance, estimated from the two halves `A`
    /// (even samples) and `B` (odd): `Var(I) ≈ (A − B)²/4` per channel, exact in expectation
    /// when the halves are independent and equally weighted. With Sobol points the halves are
    /// correlated and the whole is better than either half, so this overestimates.
    pub fn variance(&self) -> Image<Vec3> {
        let (width, height) = self.size();
        let pixels = (0..self.radiance_even.pixels.len())
            .map(|i| {
                let a = safe_div3(self.radiance_even.pixels[i], self.weight_even.pixels[i]);
                let b = safe_div3(self.radiance_odd.pixels[i], self.weight_odd.pixels[i]);
                let d = a - b;
                d * d * 0.25
            })
            .collect();
        Image {
            width,
            height,
            pixels,
        }
    }

    /// Estimated relative RMS error of the image: `sqrt(mean_p Var(Y_p) / (Y_p² + ε²))` over
    /// luminance `Y`, with `ε` = [`RELATIVE_ERROR_FLOOR`] × the mean luminance. Returns
    /// infinity while some pixel has only one half (fewer than 2 samples).
    pub fn relative_error(&self) -> f64 {
        if self
            .weight_odd
            .pixels
            .iter()
            .chain(&self.weight_even.pixels)
            .any(|&w| w == 0.0)
        {
            return f64::INFINITY;
        }
        let image = self.radiance();
        let variance = self.variance();
        let n = image.pixels.len().max(1) as f64;
        let floor = error_floor(&image);
        let sum: f64 = image
            .pixels
            .iter()
            .zip(&variance.pixels)
            .map(|(&p, &v)| {
                let y = luminance(p) as f64;
                luminance(v) as f64 / (y * y + floor * floor)
            })
            .sum();
        (sum / n).sqrt()
    }

    /// Reconstruction: radiance and AOVs, each `Σ w·value / Σ w`.
    pub fn resolve(&self) -> (Image<Vec3>, Aovs) {
        let (width, height) = self.size();
        let weight = |i: usize| self.total_weight(i);
        let scale3 = |image: &Image<Vec3>| Image {
            width: image.width,
            height: image.height,
            pixels: image
                .pixels
                .iter()
                .enumerate()
                .map(|(i, &p)| safe_div3(p, weight(i)))
                .collect(),
        };
        let scale1 = |image: &Image<f32>| Image {
            width: image.width,
            height: image.height,
            pixels: image
                .pixels
                .iter()
                .enumerate()
                .map(|(i, &d)| if weight(i) != 0.0 { d / weight(i) } else { 0.0 })
                .collect(),
        };
        (
            self.radiance(),
            Aovs {
                albedo: self.albedo.as_ref().map(scale3),
                normal: self.normal.as_ref().map(scale3),
                depth: self.depth.as_ref().map(scale1),
                alpha: Some(scale1(&self.alpha)),
                instance_id: self.instance_id.clone(),
                material_id: self.material_id.clone(),
                coverage: self
                    .coverage
                    .as_ref()
                    .filter(|_| self.selection.coverage)
                    .map(|counts| aov::resolve(width, height, counts)),
                centre_hits: self.centre_hits.clone(),
                instance_samples: match (&self.coverage, &self.amodal) {
                    (Some(visible), Some(amodal)) => Some(InstanceSamples {
                        width,
                        height,
                        visible: visible.clone(),
                        amodal: amodal.clone(),
                    }),
                    _ => None,
                },
                ..Aovs::default()
            },
        )
    }
}

pub use crate::color::luminance;

#[inline]
fn safe_div3(sum: Vec3, weight: f32) -> Vec3 {
    if weight != 0.0 {
        sum / weight
    } else {
        Vec3::ZERO
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_aov_name_selects_one_distinct_aov_and_others_are_refused() {
        let all = AovSelection::from_names(AovSelection::NAMES).unwrap();
        assert!(all.any() && all.any_ids() && all.any_geometric() && !all.annotations);
        let mut seen = Vec::new();
        for name in AovSelection::NAMES {
            let one = AovSelection::from_names([name]).unwrap();
            assert!(one.any(), "{name}");
            assert!(
                !seen.contains(&one),
                "{name} selects what another name does"
            );
            seen.push(one);
        }
        assert_eq!(AovSelection::from_names(["albedo", "bogus"]), Err("bogus"));
    }

    #[test]
    fn tiles_land_in_place_and_average() {
        let aovs = AovSelection {
            depth: true,
            ..Default::default()
        };
        let mut film = Film::new(3, 2, aovs);
        let tile = Tile {
            x0: 1,
            y0: 1,
            width: 2,
            height: 1,
        };
        let mut sums = TileSums::new(2, aovs);
        for sample in 0..2 {
            sums.pending[1] = Vec3::splat(2.0 + sample as f32);
            sums.end_sample(sample, &[1.0, 1.0]);
        }
        sums.depth[0] = 6.0;
        film.add_tile(&tile, &sums);
        // Halves 2 and 3: variance (2 − 3)²/4.
        assert_eq!(film.variance().get(2, 1), Some(Vec3::splat(0.25)));
        let (image, aovs) = film.resolve();
        assert_eq!(image.get(2, 1), Some(Vec3::splat(2.5)));
        assert_eq!(image.get(0, 0), Some(Vec3::ZERO));
        assert_eq!(aovs.depth.unwrap().get(1, 1), Some(3.0));
        assert!(aovs.albedo.is_none());
    }
}
