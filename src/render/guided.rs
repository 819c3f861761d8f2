//! Path guiding in the path tracer (`--guiding`, [`crate::guiding`]): which passes train the
//! guide, the one-sample mixture of BSDF and guide at a vertex, and the training log that
//! turns what a path later finds into records for the vertices it passed.
//!
//! **Schedule.** A fixed-spp render trains on passes of 1, 2, 4, … samples per pixel while
//! they fit in a quarter of the samples ([`training_passes`]); a progressive render trains on
//! its passes up to [`PROGRESSIVE_TRAINING_SPP`]. Each training pass renders with the guide
//! learned from the previous one (none for the first), and every pass's samples go to the
//! image: each pass is unbiased given the guide it used, which depends only on earlier
//! passes. After training the guide is frozen.
//!
//! **Training log.** While a pass trains, one path in `stride` (by pixel and sample index, so
//! a pass records at most [`MAX_TRAINING_PATHS`] paths) logs each vertex whose continuation
//! was not a delta lobe with the throughput `β` after that continuation. Every contribution
//! `c` the path adds later (emission hit, environment escape, unblocked light sample) adds
//! `c / β` — the radiance it brought in along the sampled direction — to each logged vertex
//! before it. At the end of the sample the log becomes [`Record`]s.

use crate::bsdf::{Bsdf, BsdfFlags, Frame};
use crate::guiding::{BSDF_FRACTION, Directional, GUIDE_MAX_PEAK, Guide, Record};
use crate::material::SurfaceBsdf;
use glam::{Vec2, Vec3};

/// Samples a progressive render trains on (its passes starting below this count).
pub const PROGRESSIVE_TRAINING_SPP: u32 = 16;

/// Most paths one training pass records (a path logs a few records of 28 bytes each).
pub const MAX_TRAINING_PATHS: u64 = 1 << 20;

/// The training passes of a fixed-spp render of `spp` samples: 1, 2, 4, … while their total
/// stays within a quarter of `spp` (at least the first pass of 1). 16 spp → 1, 2; 128 spp →
/// 1, 2, 4, 8, 16.
pub fn training_passes(spp: u32) -> Vec<u32> {
    let budget = (spp / 4).max(1);
    let mut passes = Vec::new();
    let (mut total, mut next) = (0u32, 1u32);
    while total + next <= budget && total + next < spp {
        passes.push(next);
        total += next;
        next *= 2;
    }
    passes
}

/// Pass sizes of a render of `spp` samples whose passes must end at each of the samples
/// totals of `a` and of `b` (two pass schedules, each summing to at most `spp`): the union
/// of their boundaries, then the rest.
pub fn merged_schedule(spp: u32, a: &[u32], b: &[u32]) -> Vec<u32> {
    let ends = |s: &[u32]| -> Vec<u32> {
        s.iter()
            .scan(0u32, |t, &p| {
                *t += p;
                Some(*t)
            })
            .collect()
    };
    let mut bounds: Vec<u32> = ends(a).into_iter().chain(ends(b)).chain([spp]).collect();
    bounds.retain(|&e| e > 0 && e <= spp);
    bounds.sort_unstable();
    bounds.dedup();
    let mut last = 0;
    bounds
        .into_iter()
        .map(|e| {
            let pass = e - last;
            last = e;
            pass
        })
        .collect()
}

/// What guiding does during one pass, as the tile context holds it.
#[derive(Clone, Debug, Default)]
pub(crate) struct Guiding {
    /// The guide learned so far, frozen for this pass.
    pub guide: Option<Guide>,
    /// While training: one path in this many logs its vertices.
    pub record_stride: Option<u64>,
}

impl Guiding {
    /// Whether the path of sample `sample` of the pixel with row-major index `pixel` logs
    /// its vertices this pass.
    #[inline]
    pub fn records(&self, pixel: u64, sample: u32) -> bool {
        self.record_stride.is_some_and(|s| {
            pixel
                .wrapping_mul(7919)
                .wrapping_add(u64::from(sample))
                .is_multiple_of(s)
        })
    }

    /// The directional distribution that guides the continuation at world point `p` of a
    /// vertex with BSDF `bsdf` seen from local `wo`: only where the guide has one, the BSDF
    /// has no delta lobe, and its lobe is wide ([`GUIDE_MAX_PEAK`] at the mirror direction).
    #[inline]
    pub fn at(&self, p: Vec3, bsdf: &SurfaceBsdf, wo: Vec3) -> Option<&Directional> {
        let guide = self.guide.as_ref()?;
        let flags = bsdf.flags();
        if flags.contains(BsdfFlags::SPECULAR) || !flags.has_density() {
            return None;
        }
        let directional = guide.at(p)?;
        let mirror = Vec3::new(-wo.x, -wo.y, wo.z);
        (bsdf.pdf(wo, mirror) <= GUIDE_MAX_PEAK).then_some(directional)
    }
}

/// The density of the mixture at local direction `wl` (world `wi`): `a · p_bsdf + (1 − a) ·
/// p_guide`, or the BSDF's alone where nothing guides.
#[inline]
pub(crate) fn mixture_pdf(
    guide: Option<&Directional>,
    bsdf: &SurfaceBsdf,
    wo: Vec3,
    wl: Vec3,
    wi: Vec3,
) -> f32 {
    let p_bsdf = bsdf.pdf(wo, wl);
    match guide {
        Some(g) => BSDF_FRACTION * p_bsdf + (1.0 - BSDF_FRACTION) * g.pdf(wi),
        None => p_bsdf,
    }
}

/// A continuation drawn from the mixture of BSDF and guide.
#[derive(Clone, Copy, Debug)]
pub(crate) struct GuidedSample {
    /// World direction, unit.
    pub wi: Vec3,
    /// `f · |cos θi| / p_mixture`.
    pub weight: Vec3,
    /// The mixture's density of `wi`.
    pub pdf: f32,
    /// Whether `wi` is on the other side of the surface from `wo`.
    pub transmission: bool,
}

/// Draws a continuation from the mixture: the BSDF with probability [`BSDF_FRACTION`]
/// (`u_lobe` rescaled chooses its lobe), else `guide` (from `u`). `None` where the drawn
/// direction carries nothing.
#[inline]
pub(crate) fn sample(
    guide: &Directional,
    bsdf: &SurfaceBsdf,
    frame: &Frame,
    wo: Vec3,
    u_lobe: f32,
    u: Vec2,
) -> Option<GuidedSample> {
    let (wl, wi) = if u_lobe < BSDF_FRACTION {
        let bs = bsdf.sample(wo, u_lobe / BSDF_FRACTION, u)?;
        if bs.delta {
            // Unreachable: guided BSDFs have no delta lobe.
            return None;
        }
        (bs.wi, frame.to_world(bs.wi).normalize_or_zero())
    } else {
        let (wi, _) = guide.sample(u);
        (frame.to_local(wi), wi)
    };
    let pdf = mixture_pdf(Some(guide), bsdf, wo, wl, wi);
    let f = bsdf.eval(wo, wl);
    // Also rejects a NaN density.
    if pdf.is_nan() || pdf <= 0.0 || f == Vec3::ZERO {
        return None;
    }
    Some(GuidedSample {
        wi,
        weight: f * (wl.z.abs() / pdf),
        pdf,
        transmission: wl.z * wo.z < 0.0,
    })
}

/// No logged vertex (a path that does not train, or has logged none yet).
pub(crate) const NO_RECORD: u32 = u32::MAX;

/// A logged vertex of a training path.
#[derive(Clone, Copy, Debug)]
struct LoggedVertex {
    position: Vec3,
    direction: Vec3,
    pdf: f32,
    /// Throughput after the continuation (the factor between radiance arriving along
    /// `direction` and what it adds to the pixel).
    beta: Vec3,
    /// Radiance found so far along `direction`.
    radiance: Vec3,
    /// The path's previous logged vertex, or [`NO_RECORD`].
    previous: u32,
}

/// The logged vertices of one sample index's training paths in a tile.
#[derive(Default)]
pub(crate) struct TrainingLog {
    vertices: Vec<LoggedVertex>,
}

impl TrainingLog {
    /// Logs a vertex of the path whose last logged vertex is `previous`; returns its index
    /// (the path's new last one).
    #[inline]
    pub fn push(
        &mut self,
        position: Vec3,
        direction: Vec3,
        pdf: f32,
        beta: Vec3,
        previous: u32,
    ) -> u32 {
        let Ok(index) = u32::try_from(self.vertices.len()) else {
            return previous;
        };
        if index == NO_RECORD {
            return previous;
        }
        self.vertices.push(LoggedVertex {
            position,
            direction,
            pdf,
            beta,
            radiance: Vec3::ZERO,
            previous,
        });
        index
    }

    /// Credits a contribution `value` of the path whose last logged vertex is `last` to each
    /// of its logged vertices.
    #[inline]
    pub fn credit(&mut self, mut last: u32, value: Vec3) {
        while let Some(v) = self.vertices.get_mut(last as usize) {
            let b = v.beta;
            let safe = |c: f32, b: f32| if b > 0.0 { c / b } else { 0.0 };
            v.radiance += Vec3::new(safe(value.x, b.x), safe(value.y, b.y), safe(value.z, b.z));
            last = v.previous;
        }
    }

    /// Moves the logged vertices into `records` as training records, emptying the log.
    pub fn drain_into(&mut self, records: &mut Vec<Record>) {
        records.extend(self.vertices.drain(..).map(|v| Record {
            position: v.position,
            direction: v.direction,
            weight: if v.pdf > 0.0 {
                crate::color::luminance(v.radiance).max(0.0) / v.pdf
            } else {
                0.0
            },
        }));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schedules_train_on_a_quarter_and_merge_boundaries() {
        assert_eq!(training_passes(16), vec![1, 2]);
        assert_eq!(training_passes(128), vec![1, 2, 4, 8, 16]);
        assert_eq!(training_passes(1), Vec::<u32>::new());
        assert_eq!(training_passes(4), vec![1]);
        let merged = merged_schedule(128, &[1, 2, 4, 8, 16], &[16, 16, 32, 64]);
        assert_eq!(merged, vec![1, 2, 4, 8, 1, 15, 1, 32, 64]);
        assert_eq!(merged.iter().sum::<u32>(), 128);
        assert_eq!(merged_schedule(16, &[1, 2], &[]), vec![1, 2, 13]);
    }

    #[test]
    fn credit_reaches_every_earlier_vertex_divided_by_its_throughput() {
        let mut log = TrainingLog::default();
        let a = log.push(Vec3::ZERO, Vec3::Z, 1.0, Vec3::splat(0.5), NO_RECORD);
        let b = log.push(Vec3::ONE, Vec3::X, 2.0, Vec3::splat(0.25), a);
        log.credit(b, Vec3::splat(1.0));
        log.credit(a, Vec3::splat(1.0));
        let mut records = Vec::new();
        log.drain_into(&mut records);
        // a: 1/0.5 + 1/0.5 = 4 over pdf 1; b: 1/0.25 = 4 over pdf 2.
        assert!((records[0].weight - 4.0).abs() < 1e-5);
        assert!((records[1].weight - 2.0).abs() < 1e-5);
    }
}
