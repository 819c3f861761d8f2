//! One level of a texture: a grid of texels (read as linear RGBA) and the reconstruction filters that
//! read it at a point (nearest, bilinear, bicubic) under glTF's wrap modes.
//!
//! Coordinates follow glTF: uv (0, 0) is the top-left corner of the image; texel (i, j) covers
//! `[i, i+1) × [j, j+1)` after scaling uv by the level's size, so its centre is at
//! `(i + ½, j + ½)`. The scaling and the split into integer texel and fraction are done in f64,
//! so that wrapping is exact even far from the origin (u = 10⁶ is as sharp as u = 0).

use crate::scene::WrapMode;
use crate::scene::texels::{TexelRead, TexelVisitor, Texels};
use glam::{DVec2, Vec2, Vec4};

/// Maps an integer texel coordinate into `[0, size)` under `mode`.
#[inline]
pub fn wrap(i: i64, size: u32, mode: WrapMode) -> usize {
    let n = i64::from(size.max(1));
    let wrapped = match mode {
        WrapMode::Repeat => i.rem_euclid(n),
        WrapMode::MirroredRepeat => {
            let m = i.rem_euclid(2 * n);
            if m >= n { 2 * n - 1 - m } else { m }
        }
        WrapMode::ClampToEdge => i.clamp(0, n - 1),
    };
    // In [0, n) with n ≤ u32::MAX, so it fits a usize.
    wrapped as usize
}

/// A texel grid: width × height texels, row-major, top row first, read as linear RGBA
/// (stored compactly: [`Texels`]).
#[derive(Clone, Debug, PartialEq)]
pub struct TexelGrid {
    /// Width in texels (≥ 1).
    pub width: u32,
    /// Height in texels (≥ 1).
    pub height: u32,
    /// `width · height` texels.
    pub texels: Texels,
}

/// The wrap modes of a texture's two axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Wrap {
    /// Horizontal (u, glTF `wrapS`).
    pub s: WrapMode,
    /// Vertical (v, glTF `wrapT`).
    pub t: WrapMode,
}

/// Below this magnitude every f64 is an integer plus a fraction that [`split`] finds by
/// truncation (2⁵²: from there on every f64 is an integer).
const SPLIT_EXACT: f64 = 4_503_599_627_370_496.0;

/// A texel coordinate split into its integer part and the fraction in [0, 1).
///
/// The floor is taken by truncation to an integer and a correction for negative values: the
/// baseline x86-64 target has no rounding instruction, so `f64::floor` is a library call, and
/// this is the innermost arithmetic of every filter. For |st| < 2⁵² the truncated value is
/// exact, so the result is bit for bit `(st.floor() as i64, (st - st.floor()) as f32)` (the
/// `+ 0.0` turns the fraction −0 of `st = −0` into the +0 that expression gives); larger or
/// NaN coordinates take that expression itself.
#[inline(always)]
fn split(st: f64) -> (i64, f32) {
    if st.abs() < SPLIT_EXACT {
        let t = st as i64;
        let floor = if (t as f64) > st { t - 1 } else { t };
        // |floor| < 2⁵², so `floor as f64` is exact: the same fraction as below.
        (floor, ((st - floor as f64) + 0.0) as f32)
    } else {
        let floor = st.floor();
        // `as` saturates, so an absurd coordinate clamps instead of wrapping around i64.
        (floor as i64, (st - floor) as f32)
    }
}

/// One axis of a grid with its wrap mode, ready for [`Self::wrap`]: the mode's integer
/// division is avoided for the common cases, a coordinate already inside the grid and a
/// repeating power-of-two side (where the Euclidean remainder is a mask of the two's-complement
/// bits). Texture coordinates outside [0, 1] are common (DamagedHelmet's v runs from 1 to 2),
/// and a 64-bit division costs tens of cycles.
#[derive(Clone, Copy)]
struct Axis {
    /// Texels along the axis.
    size: u64,
    /// `size − 1` (0 for an empty axis): the last index from which the next one is inside.
    last: u64,
    /// `size − 1` when the axis repeats with a power-of-two size, so that `i mod size` is
    /// `i & mask` for every i (negative ones included); `None` otherwise.
    mask: Option<u64>,
    mode: WrapMode,
}

impl Axis {
    #[inline(always)]
    fn new(size: u32, mode: WrapMode) -> Self {
        let size64 = u64::from(size);
        Self {
            size: size64,
            last: size64.saturating_sub(1),
            mask: (mode == WrapMode::Repeat && size.is_power_of_two()).then(|| size64 - 1),
            mode,
        }
    }

    /// [`wrap`] of `i` on this axis.
    #[inline(always)]
    fn wrap(&self, i: i64) -> usize {
        if (i as u64) < self.size {
            // 0 ≤ i < size ≤ u32::MAX.
            i as usize
        } else if let Some(mask) = self.mask {
            // i mod 2ᵏ: its low k bits, < size.
            (i as u64 & mask) as usize
        } else {
            wrap_other(i, self.size, self.mode)
        }
    }

    /// [`Self::wrap`] of `i` and of `i + 1` (saturating), the two columns or rows a bilinear
    /// filter reads.
    #[inline(always)]
    fn wrap_pair(&self, i: i64) -> (usize, usize) {
        if (i as u64) < self.last {
            // 0 ≤ i < i + 1 < size: both inside.
            (i as usize, i as usize + 1)
        } else {
            (self.wrap(i), self.wrap(i.saturating_add(1)))
        }
    }
}

/// [`wrap`] for the cases [`Axis::wrap`] does not take inline: one period outside a repeating
/// side of any size without the division, everything else through [`wrap`].
#[inline(never)]
fn wrap_other(i: i64, size: u64, mode: WrapMode) -> usize {
    // Invariant: `size` came from a u32.
    let n = size as i64;
    if mode == WrapMode::Repeat && (n..2 * n).contains(&i) {
        // One period past the end: i − n in [0, n).
        (i - n) as usize
    } else if mode == WrapMode::Repeat && (-n..0).contains(&i) {
        // One period before the start: i + n in [0, n).
        (i + n) as usize
    } else {
        wrap(i, size as u32, mode)
    }
}

/// One reconstruction filter at one point, run with the grid's texel reader.
#[derive(Clone, Copy)]
enum Reconstruct {
    Nearest,
    Bilinear,
    Bicubic,
}

/// The point, grid size and filter of one reconstruction ([`TexelVisitor`] over the storage).
struct Point {
    uv: Vec2,
    wrap: Wrap,
    width: u32,
    height: u32,
    filter: Reconstruct,
}

impl TexelVisitor for Point {
    type Output = Vec4;

    #[inline(always)]
    fn visit<R: TexelRead>(self, reader: R) -> Vec4 {
        let grid = Reader::sized(reader, self.width, self.height, self.wrap);
        match self.filter {
            Reconstruct::Nearest => grid.nearest(self.uv),
            Reconstruct::Bilinear => grid.bilinear(self.uv),
            Reconstruct::Bicubic => grid.bicubic(self.uv),
        }
    }
}

/// A grid's size and wrap modes with the reader of its storage format: the filters, compiled
/// per format. Filters that read many points of one level visit its storage once and reuse
/// this ([`crate::texture::filter`]), so the per-axis wrap set-up ([`Axis`]) is done once too.
pub(crate) struct Reader<R> {
    reader: R,
    /// Row length in texels.
    width: usize,
    /// Horizontal axis (u, glTF `wrapS`).
    s: Axis,
    /// Vertical axis (v, glTF `wrapT`).
    t: Axis,
    /// `(width, height)` in f64, the scale of [`Self::texel_space`].
    size: DVec2,
}

impl<R: TexelRead> Reader<R> {
    /// `grid`'s size and `wrap` with `reader`, which must read `grid`'s texels.
    #[inline(always)]
    pub(crate) fn new(reader: R, grid: &TexelGrid, wrap: Wrap) -> Self {
        Self::sized(reader, grid.width, grid.height, wrap)
    }

    #[inline(always)]
    fn sized(reader: R, width: u32, height: u32, wrap: Wrap) -> Self {
        Self {
            reader,
            width: width as usize,
            s: Axis::new(width, wrap.s),
            t: Axis::new(height, wrap.t),
            size: DVec2::new(f64::from(width), f64::from(height)),
        }
    }

    /// Texel-space position of `uv` (f64: see the module notes); a non-finite `uv` reads at
    /// (0, 0).
    #[inline(always)]
    fn texel_space(&self, uv: Vec2) -> DVec2 {
        // `uv · 0` is ±0 (equal to 0) for finite coordinates and NaN for infinite or NaN ones:
        // the same test as `is_finite`, without its per-component bit masks.
        let uv = if uv * 0.0 == Vec2::ZERO {
            uv
        } else {
            Vec2::ZERO
        };
        uv.as_dvec2() * self.size
    }

    #[inline(always)]
    fn at(&self, ix: usize, iy: usize) -> Vec4 {
        self.reader.read(iy * self.width + ix)
    }

    /// [`TexelGrid::nearest`].
    #[inline(always)]
    pub(crate) fn nearest(&self, uv: Vec2) -> Vec4 {
        let st = self.texel_space(uv);
        self.at(self.s.wrap(split(st.x).0), self.t.wrap(split(st.y).0))
    }

    /// [`TexelGrid::bilinear`].
    #[inline(always)]
    pub(crate) fn bilinear(&self, uv: Vec2) -> Vec4 {
        let st = self.texel_space(uv) - 0.5;
        let ((x, fx), (y, fy)) = (split(st.x), split(st.y));
        let (x0, x1) = self.s.wrap_pair(x);
        let (y0, y1) = self.t.wrap_pair(y);
        let top = self.at(x0, y0).lerp(self.at(x1, y0), fx);
        let bottom = self.at(x0, y1).lerp(self.at(x1, y1), fx);
        top.lerp(bottom, fy)
    }

    #[inline(always)]
    fn bicubic(&self, uv: Vec2) -> Vec4 {
        let st = self.texel_space(uv) - 0.5;
        let ((x, fx), (y, fy)) = (split(st.x), split(st.y));
        let (wx, wy) = (catmull_rom_weights(fx), catmull_rom_weights(fy));
        let xs: [usize; 4] = std::array::from_fn(|i| self.s.wrap(x.saturating_add(i as i64 - 1)));
        let ys: [usize; 4] = std::array::from_fn(|j| self.t.wrap(y.saturating_add(j as i64 - 1)));
        let mut sum = Vec4::ZERO;
        let (mut lo, mut hi) = (Vec4::splat(f32::INFINITY), Vec4::splat(f32::NEG_INFINITY));
        for (wyj, &iy) in wy.iter().zip(&ys) {
            for (wxi, &ix) in wx.iter().zip(&xs) {
                let t = self.at(ix, iy);
                sum += t * (wxi * wyj);
                lo = lo.min(t);
                hi = hi.max(t);
            }
        }
        sum.clamp(lo, hi)
    }
}

impl TexelGrid {
    /// A grid of `width × height` texels; `None` if the sizes and the texel count disagree
    /// or a side is zero.
    pub fn new(width: u32, height: u32, texels: impl Into<Texels>) -> Option<Self> {
        let texels = texels.into();
        let ok =
            width > 0 && height > 0 && texels.len() as u64 == u64::from(width) * u64::from(height);
        ok.then_some(Self {
            width,
            height,
            texels,
        })
    }

    /// Bytes the texels occupy.
    pub fn bytes(&self) -> usize {
        self.texels.bytes()
    }

    /// The texel at integer coordinates, wrapped. White if the grid is shorter than its size
    /// claims (constructors prevent it).
    #[inline]
    pub fn texel(&self, x: i64, y: i64, wrap: Wrap) -> Vec4 {
        let ix = self::wrap(x, self.width, wrap.s);
        let iy = self::wrap(y, self.height, wrap.t);
        self.texels.texel(iy * self.width as usize + ix)
    }

    #[inline]
    fn reconstruct(&self, uv: Vec2, wrap: Wrap, filter: Reconstruct) -> Vec4 {
        self.texels.visit(Point {
            uv,
            wrap,
            width: self.width,
            height: self.height,
            filter,
        })
    }

    /// The texel containing `uv`.
    #[inline]
    pub fn nearest(&self, uv: Vec2, wrap: Wrap) -> Vec4 {
        self.reconstruct(uv, wrap, Reconstruct::Nearest)
    }

    /// Bilinear interpolation between the four texel centres around `uv`.
    #[inline]
    pub fn bilinear(&self, uv: Vec2, wrap: Wrap) -> Vec4 {
        self.reconstruct(uv, wrap, Reconstruct::Bilinear)
    }

    /// Bicubic interpolation (Catmull–Rom, separable, over the 4 × 4 texel centres around
    /// `uv`). Catmull–Rom interpolates (texel centres are reproduced exactly) and is sharper
    /// than bilinear; it can overshoot at hard edges, so the result is clamped to the range of
    /// the 16 texels it read.
    #[inline]
    pub fn bicubic(&self, uv: Vec2, wrap: Wrap) -> Vec4 {
        self.reconstruct(uv, wrap, Reconstruct::Bicubic)
    }
}

/// Catmull–Rom weights of the texels at offsets −1, 0, 1, 2 for a fraction `t` in [0, 1).
/// They sum to 1 for every `t`.
#[inline]
fn catmull_rom_weights(t: f32) -> [f32; 4] {
    let (t2, t3) = (t * t, t * t * t);
    [
        0.5 * (-t3 + 2.0 * t2 - t),
        0.5 * (3.0 * t3 - 5.0 * t2 + 2.0),
        0.5 * (-3.0 * t3 + 4.0 * t2 + t),
        0.5 * (t3 - t2),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catmull_rom_weights_partition_unity_and_interpolate() {
        for k in 0..=10 {
            let w = catmull_rom_weights(k as f32 / 10.0);
            assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-6);
        }
        assert_eq!(catmull_rom_weights(0.0), [0.0, 1.0, 0.0, 0.0]);
    }

    /// `split` against `f64::floor` bit for bit: integers, halves, neighbours of integers, the
    /// signed zeros, both sides of the 2⁵¹ switch, huge and non-finite values.
    #[test]
    fn split_is_the_floor_and_its_fraction() {
        let reference = |st: f64| {
            let floor = st.floor();
            (floor as i64, ((st - floor) as f32).to_bits())
        };
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            f64::NAN,
            f64::INFINITY,
            -f64::INFINITY,
        ];
        for k in [1.0, 3.0, 1e6, 2f64.powi(51), 2f64.powi(52), 1e30] {
            for v in [k, -k, k + 0.5, -k - 0.5, k.next_up(), k.next_down()] {
                values.extend([v, -v]);
            }
        }
        let mut x = 0x1234_5678_9abc_def0u64;
        for _ in 0..100_000 {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            let scale = 2f64.powi((x >> 58) as i32 - 8);
            values.push(((x >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * scale);
        }
        for st in values {
            let (i, f) = split(st);
            assert_eq!((i, f.to_bits()), reference(st), "{st:e}");
        }
    }

    /// [`Axis::wrap`] and [`Axis::wrap_pair`] against [`wrap`] for every mode on power-of-two,
    /// other and unit sizes, at coordinates inside, one and several periods outside, and at the
    /// ends of i64.
    #[test]
    fn axis_wrap_is_wrap() {
        let modes = [
            WrapMode::Repeat,
            WrapMode::MirroredRepeat,
            WrapMode::ClampToEdge,
        ];
        for size in [1u32, 2, 3, 4, 5, 8, 1000, 1024] {
            let n = i64::from(size);
            let mut coords: Vec<i64> = (-3 * n - 2..=3 * n + 2).collect();
            coords.extend([
                i64::MIN,
                i64::MIN + 1,
                i64::MAX - 1,
                i64::MAX,
                1 << 40,
                -(1 << 40),
            ]);
            for mode in modes {
                let axis = Axis::new(size, mode);
                for &i in &coords {
                    assert_eq!(axis.wrap(i), wrap(i, size, mode), "{size} {mode:?} {i}");
                    let pair = (wrap(i, size, mode), wrap(i.saturating_add(1), size, mode));
                    assert_eq!(axis.wrap_pair(i), pair, "{size} {mode:?} {i}");
                }
            }
        }
    }

    #[test]
    fn wrap_modes() {
        assert_eq!(wrap(-1, 4, WrapMode::Repeat), 3);
        assert_eq!(wrap(-1, 4, WrapMode::MirroredRepeat), 0);
        assert_eq!(wrap(5, 4, WrapMode::MirroredRepeat), 2);
        assert_eq!(wrap(9, 4, WrapMode::ClampToEdge), 3);
        assert_eq!(wrap(i64::MIN, 4, WrapMode::ClampToEdge), 0);
    }
}
