//! Path guiding (`--guiding`): where light comes from, learned from the paths of a render's
//! first passes, so that later paths can sample those directions at rough surfaces. After
//! Müller et al. 2017, "Practical Path Guiding for Efficient Light-Transport Simulation",
//! simplified: the spatial half is their binary tree over the scene's box, split where
//! training records crowd ([`tree`]); the directional half is a fixed equal-area histogram
//! per leaf instead of their adaptive quadtree ([`directional`]).
//!
//! - **Training** ([`train`]): each training pass's paths record, at every vertex whose
//!   continuation was not a delta lobe, the luminance of the radiance that later arrived
//!   along the sampled direction over that direction's density. After the pass the records
//!   refine the tree and fill each leaf's histogram, in tile order (deterministic), blurred
//!   by one bin so a light found by few records is covered whole.
//! - **Guiding** ([`Guide`]): at a vertex whose BSDF has no delta lobe and is rough enough
//!   ([`GUIDE_MAX_PEAK`]), the continuation is drawn from the BSDF with probability
//!   [`BSDF_FRACTION`] and from the vertex's leaf otherwise (one-sample MIS); its density is
//!   the mixture `a · p_bsdf + (1 − a) · p_guide`, used alike for the path weight and for the
//!   MIS weights against light sampling, so the estimator stays unbiased. The BSDF still
//!   covers every direction the guide leaves at zero.
//!
//! The engine's side (which passes train, the mixture at a vertex) lives in
//! `render::guided`.

pub mod directional;
pub mod train;
pub mod tree;

pub use directional::Directional;
pub use train::{Record, Trainer};
pub use tree::SpatialTree;

use glam::Vec3;

/// Probability of drawing a guided vertex's continuation from its BSDF (the rest from the
/// guide): Müller et al.'s fixed ratio.
pub const BSDF_FRACTION: f32 = 0.5;

/// Vertices whose BSDF density toward the mirror direction exceeds this (1/sr) are not
/// guided: their lobe is narrower than about 1/5 sr, where half the samples spent on the
/// guide would cost more than it finds.
pub const GUIDE_MAX_PEAK: f32 = 5.0;

/// A leaf holding more training records than this in one pass is split in half.
pub const SPLIT_RECORDS: usize = 8000;

/// Most leaves of the spatial tree (each leaf's histogram is about 25 KiB).
pub const MAX_LEAVES: usize = 1024;

/// Fewest records that found light from which a leaf's histogram guides (fewer: that leaf
/// is not guided, since a histogram of a handful of hits misses most of the light it saw).
pub const MIN_RECORDS: usize = 16;

/// A learned guide, frozen while a pass renders: the spatial tree and each leaf's
/// directional distribution (`None`: that leaf is not guided).
#[derive(Clone, Debug)]
pub struct Guide {
    tree: SpatialTree,
    directional: Vec<Option<Directional>>,
}

impl Guide {
    /// The directional distribution at world point `p`, if its leaf guides.
    #[inline]
    pub fn at(&self, p: Vec3) -> Option<&Directional> {
        self.directional
            .get(self.tree.leaf_of(p))
            .and_then(Option::as_ref)
    }

    /// Number of leaves, and how many of them guide (for the render summary and tests).
    pub fn leaves(&self) -> (usize, usize) {
        (
            self.directional.len(),
            self.directional.iter().filter(|d| d.is_some()).count(),
        )
    }
}
