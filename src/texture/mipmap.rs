//! MIP maps: a texture's chain of successively halved levels, built once, in linear space,
//! each level stored in its base level's format (8-bit stays 8-bit).
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
use crate::scene::texels::{TexelRead, TexelVisitor, Texels};
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
    /// Builds the chain of `texture`; the base level shares the texture's storage. A texture
    /// whose texel count disagrees with its size (the loader prevents it) becomes a 1 × 1
    /// white texture rather than a panic.
    pub fn new(texture: &Texture) -> Self {
        let base = TexelGrid::new(texture.width, texture.height, texture.texels.clone())
            .unwrap_or_else(|| TexelGrid {
                width: 1,
                height: 1,
                texels: Texels::from_linear(vec![Vec4::ONE]),
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

    /// Builds the chain above `base`. Each level is filtered in linear f32 from the previous
    /// level's f32 values (the base's as stored), then stored in the base's format
    /// ([`Texels::quantized_like`]), so quantization errors do not accumulate up the chain:
    /// every level is within half a code step of the exact f32 chain.
    pub fn from_grid(base: TexelGrid, wrap: Wrap, mag_filter: MagFilter) -> Self {
        let (mut w, mut h) = (base.width as usize, base.height as usize);
        let format = base.texels.clone();
        let mut levels = vec![base];
        // The previous level in f32; `None` while it is the base (read from its storage).
        let mut previous: Option<Vec<Vec4>> = None;
        while w > 1 || h > 1 {
            let next = match &previous {
                None => format.visit(Downsample { w, h }),
                Some(values) => Downsample { w, h }.visit(ReadF32Slice(values)),
            };
            (w, h) = ((w / 2).max(1), (h / 2).max(1));
            let stored = if format.bits() == 32 {
                // f32 storage keeps the values themselves.
                Texels::from_linear(next.clone())
            } else {
                format.quantized_like(&next)
            };
            levels.push(TexelGrid {
                // Sides only shrink, so they fit the base's u32.
                width: w as u32,
                height: h as u32,
                texels: stored,
            });
            previous = Some(next);
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

    /// Texels of the base level (what bytes per texel are counted against).
    pub fn base_texels(&self) -> usize {
        self.level(0).texels.len()
    }
}

/// f32 values as a texel reader (the previous level while the chain is built).
#[derive(Clone, Copy)]
struct ReadF32Slice<'a>(&'a [Vec4]);

impl TexelRead for ReadF32Slice<'_> {
    #[inline(always)]
    fn read(&self, index: usize) -> Vec4 {
        self.0.get(index).copied().unwrap_or(Vec4::ONE)
    }
}

/// The next level of a `w × h` level: each side halved (rounding down, at least 1) with the
/// exact box filter, in f32. Rows then columns, one output row at a time, so that no
/// intermediate image is held; the arithmetic (order included) is that of a full row pass
/// followed by a full column pass.
struct Downsample {
    w: usize,
    h: usize,
}

impl TexelVisitor for Downsample {
    type Output = Vec<Vec4>;

    fn visit<R: TexelRead>(self, src: R) -> Vec<Vec4> {
        let Self { w, h } = self;
        let (w2, h2) = ((w / 2).max(1), (h / 2).max(1));
        let wx = box_weights(w, w2);
        let wy = box_weights(h, h2);
        let mut texels = Vec::with_capacity(w2 * h2);
        let mut row = vec![Vec4::ZERO; w2];
        let mut out = vec![Vec4::ZERO; w2];
        for taps_y in &wy {
            out.fill(Vec4::ZERO);
            for &(j, kj) in taps_y {
                // Source row j filtered horizontally, then weighted into the output row.
                for (r, taps) in row.iter_mut().zip(&wx) {
                    *r = taps
                        .iter()
                        .fold(Vec4::ZERO, |acc, &(i, k)| acc + src.read(j * w + i) * k);
                }
                for (o, r) in out.iter_mut().zip(&row) {
                    *o += *r * kj;
                }
            }
            texels.extend_from_slice(&out);
        }
        texels
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
