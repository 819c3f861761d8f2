//! Learning a [`Guide`] from one pass's training records: the spatial tree is refined where
//! the records crowd, then each leaf's directional histogram is the sum of its records'
//! weights per bin. Records are read in the order given (the scheduler's tile order), so the
//! guide is the same for any thread count.

use super::directional::{BINS, Directional, bin_of};
use super::tree::SpatialTree;
use super::{Guide, MAX_LEAVES, MIN_RECORDS, SPLIT_RECORDS};
use glam::Vec3;

/// What a path measured at one of its vertices: the incident radiance's luminance arriving
/// along `direction` divided by the density of the sample that chose `direction`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Record {
    /// The vertex, world space.
    pub position: Vec3,
    /// The sampled incident direction, world space, unit.
    pub direction: Vec3,
    /// `luminance(L_i) / p(direction)` (0 for a path that found no light).
    pub weight: f32,
}

/// The spatial tree as refined so far, kept from pass to pass.
#[derive(Clone, Debug)]
pub struct Trainer {
    tree: SpatialTree,
}

impl Trainer {
    /// A trainer over the box `lo..hi` (the scene's bounds; points outside fall into the
    /// nearest leaf).
    pub fn new(lo: Vec3, hi: Vec3) -> Self {
        Self {
            tree: SpatialTree::new(lo, hi),
        }
    }

    /// Refines the tree with `records` (leaves holding more than [`SPLIT_RECORDS`] of them
    /// are halved, up to [`MAX_LEAVES`]) and learns a guide from them alone, as the paper
    /// learns each iteration from the previous one's samples.
    pub fn learn<'r>(&mut self, records: impl Iterator<Item = &'r Record> + Clone) -> Guide {
        let mut leaf_of: Vec<u32> = records
            .clone()
            .map(|r| self.tree.leaf_of(r.position) as u32)
            .collect();
        loop {
            let mut counts = vec![0usize; self.tree.leaf_count()];
            for &l in &leaf_of {
                counts[l as usize] += 1;
            }
            let mut split_any = false;
            let mut was_split = vec![false; counts.len()];
            for (leaf, &count) in counts.iter().enumerate() {
                if count > SPLIT_RECORDS
                    && self.tree.leaf_count() < MAX_LEAVES
                    && self.tree.split(leaf).is_some()
                {
                    was_split[leaf] = true;
                    split_any = true;
                }
            }
            if !split_any {
                break;
            }
            for (r, l) in records.clone().zip(leaf_of.iter_mut()) {
                if was_split[*l as usize] {
                    *l = self.tree.leaf_of(r.position) as u32;
                }
            }
        }
        let leaves = self.tree.leaf_count();
        let mut sums = vec![0.0f32; leaves * BINS];
        let mut lit = vec![0usize; leaves];
        for (r, &l) in records.zip(&leaf_of) {
            let l = l as usize;
            if r.weight.is_finite() && r.weight > 0.0 {
                lit[l] += 1;
                sums[l * BINS + bin_of(r.direction)] += r.weight;
            }
        }
        let directional = sums
            .chunks_exact(BINS)
            .zip(&lit)
            .map(|(bins, &lit)| {
                if lit >= MIN_RECORDS {
                    Directional::from_weights(&blurred(bins))
                } else {
                    None
                }
            })
            .collect();
        Guide {
            tree: self.tree.clone(),
            directional,
        }
    }
}

/// A histogram blurred by the 3 × 3 binomial kernel (φ wraps around, cos θ is clamped at the
/// poles): a light a few records found lends some density to the bins beside them, which it
/// usually covers too, so BSDF samples there are not weighted against a guide that misses
/// them.
fn blurred(bins: &[f32]) -> Vec<f32> {
    use super::directional::{PHI_BINS, Z_BINS};
    const K: [f32; 3] = [0.25, 0.5, 0.25];
    let at = |row: usize, col: usize| bins[row * PHI_BINS + col];
    let mut along = vec![0.0f32; BINS];
    for row in 0..Z_BINS {
        for col in 0..PHI_BINS {
            let left = (col + PHI_BINS - 1) % PHI_BINS;
            let right = (col + 1) % PHI_BINS;
            along[row * PHI_BINS + col] =
                K[0] * at(row, left) + K[1] * at(row, col) + K[2] * at(row, right);
        }
    }
    let mut out = vec![0.0f32; BINS];
    for row in 0..Z_BINS {
        let (below, above) = (row.saturating_sub(1), (row + 1).min(Z_BINS - 1));
        for col in 0..PHI_BINS {
            out[row * PHI_BINS + col] = K[0] * along[below * PHI_BINS + col]
                + K[1] * along[row * PHI_BINS + col]
                + K[2] * along[above * PHI_BINS + col];
        }
    }
    out
}
