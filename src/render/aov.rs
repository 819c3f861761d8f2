//! The value types of the auxiliary images (AOVs), apart from the code that fills them: the
//! image grid ([`Image`]), the coverage counts and their resolved layers (`render::ids`), the
//! per-instance sample counts of annotations (`render::amodal`) and the choice of geometric
//! AOVs (`render::ground_truth`). The film sums and resolves them, the tile kernels fill them;
//! keeping them here lets the film import no kernel module, so `render/`'s modules import each
//! other without a circle through `TileContext` (issue 33; `tests/structure/layering.rs` checks it).

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

/// The ID of "nothing": a pixel whose centre ray leaves the scene, an unused coverage layer.
pub const NO_ID: u32 = u32::MAX;

/// How many objects the coverage AOV lists per pixel (K).
pub const COVERAGE_LAYERS: usize = 4;

/// One pixel's sample counts per instance ID (background as [`NO_ID`]), in order of first
/// appearance. A handful of entries in practice, so a linear search beats a map.
pub type PixelCoverage = Vec<(u32, u32)>;

/// The coverage AOV of a whole image: per pixel, up to [`COVERAGE_LAYERS`] instance IDs and
/// the fraction of the pixel's samples that hit each (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct Coverage {
    /// Instance IDs by decreasing coverage; [`NO_ID`] in unused layers.
    pub ids: Image<[u32; COVERAGE_LAYERS]>,
    /// The fraction of the pixel's samples whose camera ray hit the object first, in
    /// `[0, 1]`; 0 in unused layers.
    pub fractions: Image<[f32; COVERAGE_LAYERS]>,
}

/// Adds one sample to a pixel's counts.
#[inline]
pub fn count(pixel: &mut PixelCoverage, id: u32, n: u32) {
    match pixel.iter_mut().find(|(known, _)| *known == id) {
        Some((_, c)) => *c = c.saturating_add(n),
        None => pixel.push((id, n)),
    }
}

/// The coverage layers of one pixel from its counts: objects by decreasing count (ties by
/// increasing ID), background left out, fractions of the pixel's total count.
pub fn resolve_pixel(counts: &PixelCoverage) -> ([u32; COVERAGE_LAYERS], [f32; COVERAGE_LAYERS]) {
    let total: u64 = counts.iter().map(|&(_, c)| u64::from(c)).sum();
    let mut objects: Vec<(u32, u32)> = counts
        .iter()
        .copied()
        .filter(|&(id, _)| id != NO_ID)
        .collect();
    objects.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    let mut ids = [NO_ID; COVERAGE_LAYERS];
    let mut fractions = [0.0; COVERAGE_LAYERS];
    for (slot, &(id, c)) in objects.iter().take(COVERAGE_LAYERS).enumerate() {
        ids[slot] = id;
        // In f64 so that the fraction is the correctly rounded count ratio.
        fractions[slot] = (f64::from(c) / total.max(1) as f64) as f32;
    }
    (ids, fractions)
}

/// The coverage AOV of a `width × height` image from its per-pixel counts (row-major).
pub fn resolve(width: u32, height: u32, counts: &[PixelCoverage]) -> Coverage {
    let (ids, fractions): (Vec<_>, Vec<_>) = counts.iter().map(resolve_pixel).unzip();
    Coverage {
        ids: Image {
            width,
            height,
            pixels: ids,
        },
        fractions: Image {
            width,
            height,
            pixels: fractions,
        },
    }
}

/// The per-pixel sample counts of a render's instances: what annotations are made from.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InstanceSamples {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Per pixel (row-major): the samples whose first accepted hit is on each instance ID,
    /// background ([`NO_ID`]) included, so that a pixel's counts sum to its sample count.
    pub visible: Vec<PixelCoverage>,
    /// Per pixel: the samples whose ray pierces each instance ID (never the background).
    pub amodal: Vec<PixelCoverage>,
}

impl InstanceSamples {
    /// The number of camera samples pixel `index` (row-major) received.
    pub fn samples(&self, index: usize) -> u64 {
        self.visible
            .get(index)
            .map_or(0, |p| p.iter().map(|&(_, n)| u64::from(n)).sum())
    }

    /// The count of instance `id` in `counts` (0 if absent).
    pub fn count_of(counts: &PixelCoverage, id: u32) -> u32 {
        counts
            .iter()
            .find(|&&(known, _)| known == id)
            .map_or(0, |&(_, n)| n)
    }
}

/// Which geometric AOVs to compute.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GeometricSelection {
    /// Optical-axis depth.
    pub z: bool,
    /// World-space position.
    pub position: bool,
    /// TEXCOORD_0.
    pub uv: bool,
    /// Flow to `t + Δ`.
    pub flow: bool,
    /// Flow to `t − Δ`.
    pub flow_backward: bool,
}
