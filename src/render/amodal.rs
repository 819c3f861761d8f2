//! Amodal coverage: for each pixel, every instance its camera samples' rays pierce, hidden or
//! not, counted per sample; the counts per-instance annotations (amodal masks, areas, boxes and
//! visible fractions) are made from.
//!
//! Each camera sample's ray is walked to its end with [`crate::accel::Accel::all_hits`] (an
//! any-hit traversal that never stops, on both backends), and each instance with a surface
//! along it is counted once for that sample. A pierced surface counts only where the camera
//! would see it were nothing in front: the same back-face culling and alpha rules as the
//! visible hit ([`super::visibility`], BLEND's random choice included), so a cut-out leaf's
//! amodal mask is the leaf, not its quad. The sample's visible instance is always counted:
//! amodal coverage is at least visible coverage in every pixel by construction, whatever the
//! backend's rounding at an edge.
//!
//! Only when [`AovSelection::annotations`](super::film::AovSelection::annotations) is
//! selected; otherwise the kernels' only addition is one emptiness check per batch of camera
//! rays, as for the coverage AOV. Counts are integers summed per tile, so they are the same
//! for any thread count.

pub use super::aov::InstanceSamples;
use super::film::TileSums;
use super::ids::{self, NO_ID};
use super::visibility::RayBatch;
use super::wavefront::TileContext;
use crate::accel::{Hit, Ray};

/// Records, for one batch of camera rays (`rays[i]` is tile pixel `pixels[i]`'s, `hits[i]` its
/// accepted first hit; all pixels, or those adaptive sampling has not stopped), every instance
/// each ray pierces in the amodal counts (nothing unless annotations are selected).
pub(super) fn record_amodal(
    ctx: &TileContext<'_>,
    sums: &mut TileSums,
    rays: &[Ray],
    hits: &[Option<Hit>],
    pixels: impl Iterator<Item = usize>,
    batch: RayBatch,
) {
    if sums.amodal.is_empty() {
        return;
    }
    let mut along = Vec::new();
    let mut pierced: Vec<u32> = Vec::new();
    for (index, ((pixel, ray), hit)) in pixels.zip(rays).zip(hits).enumerate() {
        let Some(pixel) = sums.amodal.get_mut(pixel) else {
            continue;
        };
        pierced.clear();
        if let Some(h) = hit {
            pierced.push(ids::instance_id(ctx.scene, h.geom_id, h.instance));
        }
        ctx.accel.all_hits(ray, &mut along);
        for h in &along {
            let seen = ctx
                .visibility
                .as_ref()
                .is_none_or(|v| v.camera_accepts(ctx, ray, h, batch, index));
            let id = ids::instance_id(ctx.scene, h.geom_id, h.instance);
            if seen && id != NO_ID && !pierced.contains(&id) {
                pierced.push(id);
            }
        }
        for &id in &pierced {
            ids::count(pixel, id, 1);
        }
    }
}
