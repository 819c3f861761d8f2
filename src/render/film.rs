//! The film: accumulates samples per pixel and resolves them into images.
//!
//! Reconstruction is a box filter over the pixel (the average of its samples); the film is a
//! small type so that a later pixel filter can change how samples are weighted and spread.

use super::tiles::Tile;
use glam::Vec3;

/// A row-major image, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Image<T> {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width × height` values.
    pub pixels: Vec<T>,
}

impl<T: Copy> Image<T> {
    /// An image filled with `value`.
    pub fn filled(width: u32, height: u32, value: T) -> Self {
        Self {
            width,
            height,
            pixels: vec![value; width as usize * height as usize],
        }
    }

    /// The value at `(x, y)`; `None` outside the image.
    pub fn get(&self, x: u32, y: u32) -> Option<T> {
        if x >= self.width || y >= self.height {
            return None;
        }
        self.pixels
            .get(y as usize * self.width as usize + x as usize)
            .copied()
    }
}

/// Which auxiliary images (AOVs) to produce alongside the radiance.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AovSelection {
    /// Reflectance ρ at the first hit (0 for misses and unlit back faces).
    pub albedo: bool,
    /// World-space unit shading normal at the first hit, facing the camera (0 for misses).
    pub normal: bool,
    /// Distance from the camera to the first hit in scene units (0 for misses).
    pub depth: bool,
}

impl AovSelection {
    /// Whether any AOV is selected.
    pub fn any(&self) -> bool {
        self.albedo || self.normal || self.depth
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
}

/// Per-pixel sums of one tile's samples, in the tile's row-major order.
#[derive(Clone, Debug, Default)]
pub struct TileSums {
    /// Σ radiance (W/(m²·sr)).
    pub radiance: Vec<Vec3>,
    /// Σ albedo, if selected (else empty).
    pub albedo: Vec<Vec3>,
    /// Σ normal, if selected.
    pub normal: Vec<Vec3>,
    /// Σ depth, if selected.
    pub depth: Vec<f32>,
}

impl TileSums {
    /// Zeroed sums for `pixels` pixels and the selected AOVs.
    pub fn new(pixels: usize, aovs: AovSelection) -> Self {
        let sized = |on: bool| if on { pixels } else { 0 };
        Self {
            radiance: vec![Vec3::ZERO; pixels],
            albedo: vec![Vec3::ZERO; sized(aovs.albedo)],
            normal: vec![Vec3::ZERO; sized(aovs.normal)],
            depth: vec![0.0; sized(aovs.depth)],
        }
    }
}

/// The whole image's sums.
#[derive(Clone, Debug)]
pub struct Film {
    samples_per_pixel: u32,
    radiance: Image<Vec3>,
    albedo: Option<Image<Vec3>>,
    normal: Option<Image<Vec3>>,
    depth: Option<Image<f32>>,
}

impl Film {
    /// An empty film; every pixel will receive `samples_per_pixel` samples.
    pub fn new(width: u32, height: u32, samples_per_pixel: u32, aovs: AovSelection) -> Self {
        Self {
            samples_per_pixel: samples_per_pixel.max(1),
            radiance: Image::filled(width, height, Vec3::ZERO),
            albedo: aovs
                .albedo
                .then(|| Image::filled(width, height, Vec3::ZERO)),
            normal: aovs
                .normal
                .then(|| Image::filled(width, height, Vec3::ZERO)),
            depth: aovs.depth.then(|| Image::filled(width, height, 0.0)),
        }
    }

    /// Adds a tile's sums at the tile's place.
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
        add(&mut self.radiance, tile, &sums.radiance);
        if let Some(image) = &mut self.albedo {
            add(image, tile, &sums.albedo);
        }
        if let Some(image) = &mut self.normal {
            add(image, tile, &sums.normal);
        }
        if let Some(image) = &mut self.depth {
            add(image, tile, &sums.depth);
        }
    }

    /// The unresolved sums: radiance and the selected AOVs, each summed (not averaged) over
    /// the pixel's samples, and the number of samples every pixel received. Partial renders
    /// write these so that parts can be merged before dividing.
    pub fn into_sums(self) -> (Image<Vec3>, Aovs, u32) {
        (
            self.radiance,
            Aovs {
                albedo: self.albedo,
                normal: self.normal,
                depth: self.depth,
            },
            self.samples_per_pixel,
        )
    }

    /// Box-filter reconstruction: each pixel's sum divided by its sample count.
    pub fn resolve(self) -> (Image<Vec3>, Aovs) {
        let inv = 1.0 / self.samples_per_pixel as f32;
        let scale3 = |mut image: Image<Vec3>| {
            image.pixels.iter_mut().for_each(|p| *p *= inv);
            image
        };
        let depth = self.depth.map(|mut image| {
            image.pixels.iter_mut().for_each(|p| *p *= inv);
            image
        });
        (
            scale3(self.radiance),
            Aovs {
                albedo: self.albedo.map(scale3),
                normal: self.normal.map(scale3),
                depth,
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_land_in_place_and_average() {
        let aovs = AovSelection {
            depth: true,
            ..Default::default()
        };
        let mut film = Film::new(3, 2, 2, aovs);
        let tile = Tile {
            x0: 1,
            y0: 1,
            width: 2,
            height: 1,
        };
        let mut sums = TileSums::new(2, aovs);
        sums.radiance[1] = Vec3::splat(4.0);
        sums.depth[0] = 6.0;
        film.add_tile(&tile, &sums);
        let (image, aovs) = film.resolve();
        assert_eq!(image.get(2, 1), Some(Vec3::splat(2.0)));
        assert_eq!(image.get(0, 0), Some(Vec3::ZERO));
        assert_eq!(aovs.depth.unwrap().get(1, 1), Some(3.0));
        assert!(aovs.albedo.is_none());
    }
}
