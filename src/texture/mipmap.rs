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
        if self.w >= 2 && self.h >= 2 && self.w.is_multiple_of(2) && self.h.is_multiple_of(2) {
            return halve_even(&src, self.w, self.h);
        }
        box_downsample(&src, self.w, self.h)
    }
}

/// [`Downsample`] of a level whose sides are both even (every level of a power-of-two
/// texture but the last): each output texel averages a 2 × 2 block, with the general
/// filter's arithmetic in its order (its taps are all ½ there: `(0 + a·½) + b·½` along
/// rows, then the same down the two row results), so the values are bit for bit
/// [`box_downsample`]'s, without its tap lists. This ran for every base texel of every
/// texture at load: 45 instructions a texel through the tap lists on DamagedHelmet.
#[inline(always)]
fn halve_even<R: TexelRead>(src: &R, w: usize, h: usize) -> Vec<Vec4> {
    let (w2, h2) = (w / 2, h / 2);
    let mut texels = Vec::with_capacity(w2 * h2);
    for y in 0..h2 {
        let (upper, lower) = (2 * y * w, (2 * y + 1) * w);
        for x in 0..w2 {
            let pair = |row: usize| {
                (Vec4::ZERO + src.read(row + 2 * x) * 0.5) + src.read(row + 2 * x + 1) * 0.5
            };
            let (top, bottom) = (pair(upper), pair(lower));
            texels.push((Vec4::ZERO + top * 0.5) + bottom * 0.5);
        }
    }
    texels
}

/// [`Downsample`] of any `w × h` level with the exact box filter (module doc).
fn box_downsample<R: TexelRead>(src: &R, w: usize, h: usize) -> Vec<Vec4> {
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

    /// The even-sided fast path gives the general filter's values bit for bit, on f32
    /// texels of every sign and size and on sRGB 8-bit codes.
    #[test]
    fn halving_even_sides_is_the_general_box_filter() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for (w, h) in [(2, 2), (2, 8), (16, 2), (64, 32), (6, 10)] {
            let values: Vec<Vec4> = (0..w * h)
                .map(|_| {
                    Vec4::from_array(std::array::from_fn(|_| {
                        (next() % 20_001) as f32 / 1000.0 - 10.0
                    }))
                })
                .collect();
            let src = ReadF32Slice(&values);
            let bits = |v: Vec<Vec4>| -> Vec<[u32; 4]> {
                v.into_iter()
                    .map(|t| t.to_array().map(f32::to_bits))
                    .collect()
            };
            assert_eq!(
                bits(halve_even(&src, w, h)),
                bits(box_downsample(&src, w, h)),
                "{w}×{h}"
            );
            let codes: Vec<u8> = (0..w * h * 3).map(|_| next() as u8).collect();
            let texels =
                Texels::from_u8(3, crate::scene::texture_decode::ColorSpace::Srgb, codes).unwrap();
            struct Both(usize, usize);
            impl TexelVisitor for Both {
                type Output = (Vec<Vec4>, Vec<Vec4>);
                fn visit<R: TexelRead>(self, r: R) -> Self::Output {
                    (
                        halve_even(&r, self.0, self.1),
                        box_downsample(&r, self.0, self.1),
                    )
                }
            }
            let (fast, general) = texels.visit(Both(w, h));
            assert_eq!(bits(fast), bits(general), "{w}×{h} sRGB8");
        }
    }

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
