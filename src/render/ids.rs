//! Exact ID images: which object and material each pixel shows, and which objects cover it
//! in what proportion.
//!
//! - `instance_id` and `material_id` ([`AovSelection::instance_id`],
//!   [`AovSelection::material_id`]): what the ray through the pixel's *centre* hits, traced
//!   once per render apart from the samples (so the radiance is untouched and the ID is a
//!   point sample, not an average of IDs, which would be meaningless). The instance ID is the
//!   glTF node index of the mesh instance ([`crate::scene::Mesh::node`]; the mesh's index for
//!   meshes made in code), the material ID the index into [`crate::scene::Scene::materials`]
//!   (the glTF material index; glint's default material, for primitives without one, comes
//!   after the file's). Pixels whose centre ray misses hold [`NO_ID`].
//! - `coverage` ([`AovSelection::coverage`]): for each pixel, the instance IDs of up to
//!   [`COVERAGE_LAYERS`] objects that the pixel's camera samples hit first, with the
//!   fraction of the pixel's samples that hit each: exact counts over every sample rendered
//!   (cryptomatte's idea without its hashes and without its fitted weights). The fractions
//!   count samples, each once: samples land where the pixel filter puts them (for the default
//!   box filter, uniformly over the pixel), and a filter's negative lobes do not enter. Objects
//!   are listed by decreasing count, ties by increasing ID; unused layers hold [`NO_ID`] and
//!   0. Samples that miss every object are counted as background, which is not listed: the
//!   listed fractions plus the background's sum to 1 when no more than
//!   [`COVERAGE_LAYERS`] objects cover the pixel.
//!
//! Both are integers summed per tile and added to the film in tile order, so they are the
//! same for any thread count. Neither costs anything when not selected: the centre rays are
//! not traced and the kernels' only addition is one emptiness check per batch of camera rays.

pub use super::aov::{
    COVERAGE_LAYERS, Coverage, NO_ID, PixelCoverage, count, resolve, resolve_pixel,
};
use super::film::{AovSelection, TileSums};
use super::stats::RayCounts;
use super::tiles::Tile;
use super::visibility::{RayBatch, RayKind};
use super::wavefront::TileContext;
use crate::accel::Hit;
use crate::scene::Scene;

/// The instance ID of copy `instance` of mesh `geom_id` (its glTF node, else the mesh's
/// index).
#[inline]
pub fn instance_id(scene: &Scene, geom_id: u32, instance: u32) -> u32 {
    scene
        .meshes
        .get(geom_id as usize)
        .and_then(|m| m.node_of(instance))
        .unwrap_or(geom_id)
}

/// The instance ID of a hit.
#[inline]
fn hit_instance_id(scene: &Scene, hit: &Hit) -> u32 {
    instance_id(scene, hit.geom_id, hit.instance)
}

/// The material ID of a hit's mesh.
#[inline]
fn material_id(scene: &Scene, hit: &Hit) -> u32 {
    scene
        .meshes
        .get(hit.geom_id as usize)
        .and_then(|m| u32::try_from(m.material).ok())
        .unwrap_or(NO_ID)
}

/// Records the first hits of one batch of camera rays, `hits[i]` being that of the `i`-th tile
/// pixel in `pixels` (all of them, or those adaptive sampling has not stopped), in the coverage
/// counts (nothing unless the coverage AOV is selected).
#[inline]
pub(super) fn record_coverage(
    ctx: &TileContext<'_>,
    sums: &mut TileSums,
    hits: &[Option<Hit>],
    pixels: impl Iterator<Item = usize>,
) {
    if sums.coverage.is_empty() {
        return;
    }
    for (pixel, hit) in pixels.zip(hits) {
        let id = hit.map_or(NO_ID, |h| hit_instance_id(ctx.scene, &h));
        if let Some(pixel) = sums.coverage.get_mut(pixel) {
            count(pixel, id, 1);
        }
    }
}

/// Traces the ray through the centre of each of `tile`'s pixels and stores what it hits in
/// `sums.instance_id` / `sums.material_id` (those selected), counting the rays as camera rays.
pub(super) fn trace_centre_ids(
    ctx: &TileContext<'_>,
    aovs: AovSelection,
    tile: &Tile,
    sums: &mut TileSums,
    counts: &mut RayCounts,
) {
    if !(aovs.instance_id || aovs.material_id) {
        return;
    }
    let (rays, mut hits) = ctx.trace_pixel_centres(tile);
    // The camera's visibility rules (alpha cut-outs, culling), as the render and the
    // geometric AOVs' centre hits follow them: an ID is what the pixel shows.
    if let Some(visibility) = &ctx.visibility {
        // The batch identity the geometric AOVs' centre rays use, so both decide alike.
        let batch = RayBatch::new(tile, u32::MAX, 0);
        visibility.resolve_hits(ctx, &rays, &mut hits, RayKind::Camera, batch, counts);
    }
    counts.camera += rays.len() as u64;
    let ids = |f: fn(&Scene, &Hit) -> u32| -> Vec<u32> {
        hits.iter()
            .map(|h| h.map_or(NO_ID, |h| f(ctx.scene, &h)))
            .collect()
    };
    if aovs.instance_id {
        sums.instance_id = ids(hit_instance_id);
    }
    if aovs.material_id {
        sums.material_id = ids(material_id);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layers_sort_by_count_then_id_and_leave_out_the_background() {
        let mut pixel = PixelCoverage::new();
        for (id, n) in [(7, 3), (NO_ID, 4), (2, 3), (9, 1), (5, 2), (1, 1), (7, 2)] {
            count(&mut pixel, id, n);
        }
        // 7: 5, 2: 3, 5: 2, then 1 and 9 tie at 1 (1 first); background 4 of 16.
        let (ids, fractions) = resolve_pixel(&pixel);
        assert_eq!(ids, [7, 2, 5, 1]);
        assert_eq!(fractions, [5.0 / 16.0, 3.0 / 16.0, 2.0 / 16.0, 1.0 / 16.0]);
    }

    #[test]
    fn unused_layers_hold_no_id() {
        let (ids, fractions) = resolve_pixel(&vec![(NO_ID, 8)]);
        assert_eq!(ids, [NO_ID; COVERAGE_LAYERS]);
        assert_eq!(fractions, [0.0; COVERAGE_LAYERS]);
        let (ids, fractions) = resolve_pixel(&vec![(3, 1), (NO_ID, 1)]);
        assert_eq!(ids, [3, NO_ID, NO_ID, NO_ID]);
        assert_eq!(fractions, [0.5, 0.0, 0.0, 0.0]);
        // A pixel with no samples at all (cannot happen in a render) is empty, not NaN.
        assert_eq!(resolve_pixel(&Vec::new()).1, [0.0; COVERAGE_LAYERS]);
    }
}
