//! MIP maps: a texture's chain of successively halved levels, built once, in linear space.
//!
//! Each level is `max(1, ⌊w/2⌋) × max(1, ⌊h/2⌋)` of the one below. Non-power-of-two sides are
//! handled by an exact box filter rather than by resampling to a power of two: output texel i
//! of a side going from n to m texels covers the source interval `[i·n/m, (i+1)·n/m)`, and
//! every source texel is weighted by the length of its overlap with it. For even n this is the
//! usual 2-tap average; for odd n (5 → 2: each output covers 2.5 texels) no texel is dropped
//! or counted twice, so every level keeps the base level's mean exactly (up to rounding).
//! The filter is separable (rows, then columns) and never reads across the border, so it does
//! not depend on the wrap mode. Halving with ⌊·⌋ keeps the whole chain within 4/3 of the base.

use super::image::{TexelGrid, Wrap};
use crate::scene::{MagFilter, Texture};
use glam::Vec4;

/// A texture's MIP chain with its sampler settings.
#[derive(Clone, Debug)]
pub struct MipMap {
    /// Level 0 is the full-resolution image; the last level is 1 × 1.
    levels: Vec<TexelGrid>,
    /// Wrap modes of both axes.
    pub wrap: Wrap,
    /// The glTF sampler's magnification filter.
    pub mag_filter: MagFilter,
}

impl MipMap {
    /// Builds the chain of `texture`. A texture whose texel count disagrees with its size
    /// (the loader prevents it) becomes a 1 × 1 white texture rather than a panic.
    pub fn new(texture: &Texture) -> Self {
        let base = TexelGrid::new(texture.width, texture.height, texture.texels.clone())
            .unwrap_or_else(|| TexelGrid {
                width: 1,
                height: 1,
                texels: vec![Vec4::ONE],
            });
        Self::from_grid(
            base,
            Wrap {
                s: texture.wrap_s,
                t: texture.wrap_t,
            },
            texture.mag_filter,
        )
    }

    /// Builds the chain above `base`.
    pub fn from_grid(base: TexelGrid, wrap: Wrap, mag_filter: MagFilter) -> Self {
        let mut levels = vec![base];
        while let Some(last) = levels.last()
            && (last.width > 1 || last.height > 1)
        {
            let next = downsample(last);
            levels.push(next);
        }
        Self {
            levels,
            wrap,
            mag_filter,
        }
    }

    /// The levels, finest first.
    pub fn levels(&self) -> &[TexelGrid] {
        &self.levels
    }

    /// Level `i`, clamped to the chain.
    #[inline]
    pub fn level(&self, i: usize) -> &TexelGrid {
        // The chain always has its base level.
        &self.levels[i.min(self.levels.len() - 1)]
    }

    /// Number of levels (1 for a 1 × 1 texture).
    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    /// Bytes of all levels' texels.
    pub fn bytes(&self) -> usize {
        self.levels.iter().map(TexelGrid::bytes).sum()
    }
}

/// The next level: each side halved (rounding down, at least 1) with the exact box filter.
fn downsample(grid: &TexelGrid) -> TexelGrid {
    let (w, h) = (grid.width as usize, grid.height as usize);
    let (w2, h2) = ((w / 2).max(1), (h / 2).max(1));
    let wx = box_weights(w, w2);
    let wy = box_weights(h, h2);
    // Rows first: h × w2.
    let mut rows = vec![Vec4::ZERO; h * w2];
    for y in 0..h {
        let src = &grid.texels[y * w..(y + 1) * w];
        for (x2, taps) in wx.iter().enumerate() {
            rows[y * w2 + x2] = taps.iter().map(|&(i, k)| src[i] * k).sum();
        }
    }
    let mut texels = vec![Vec4::ZERO; h2 * w2];
    for (y2, taps) in wy.iter().enumerate() {
        for x2 in 0..w2 {
            texels[y2 * w2 + x2] = taps.iter().map(|&(j, k)| rows[j * w2 + x2] * k).sum();
        }
    }
    TexelGrid {
        width: w2 as u32,
        height: h2 as u32,
        texels,
    }
}

/// For each of `m` output texels along a side of `n` source texels, the source texels it
/// overlaps and their normalised weights (overlap length / output width).
fn box_weights(n: usize, m: usize) -> Vec<Vec<(usize, f32)>> {
    let scale = n as f64 / m as f64;
    (0..m)
        .map(|i| {
            let (lo, hi) = (i as f64 * scale, (i + 1) as f64 * scale);
            let first = lo.floor() as usize;
            let last = (hi.ceil() as usize).min(n);
            (first..last)
                .filter_map(|j| {
                    let overlap = (hi.min(j as f64 + 1.0) - lo.max(j as f64)).max(0.0);
                    (overlap > 0.0).then_some((j, (overlap / scale) as f32))
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_weights_cover_the_source_once() {
        for n in 1..20 {
            let m = (n / 2).max(1);
            let mut coverage = vec![0.0f32; n];
            for taps in box_weights(n, m) {
                let total: f32 = taps.iter().map(|t| t.1).sum();
                assert!((total - 1.0).abs() < 1e-6);
                for (j, k) in taps {
                    coverage[j] += k;
                }
            }
            // Each source texel contributes m/n of an output texel's worth in total.
            for c in coverage {
                assert!((c - m as f32 / n as f32).abs() < 1e-6, "n = {n}");
            }
        }
    }
}
