//! Compact texel storage: a texture's texels kept at the precision its file had.
//!
//! An 8-bit image stays 8-bit in memory, a 16-bit PNG stays 16-bit, float images stay f32.
//! Each channel code is turned into a linear value only when it is read, through a table
//! (256 entries for 8-bit codes, 65 536 for 16-bit ones) holding exactly the value the decoder
//! used to store: the sRGB EOTF of `code / max` for the colour channels of colour textures,
//! `code / max` for data textures and for alpha. Filtering therefore happens in linear space,
//! on the same numbers as with linear f32 storage; only the bytes held differ.
//!
//! Channels are stored as the image needs them ([`Texels::channels`]): 1 (grey, R = G = B,
//! opaque), 2 (grey and alpha), 3 (RGB, opaque) or 4 (RGBA). A missing alpha reads 1 and a
//! grey texel reads the same value in R, G and B, so the layout never changes a value read.
//!
//! Coarser MIP levels are computed in linear f32 and stored back in the base level's format by
//! [`Texels::quantized_like`]: each value is replaced by the code whose *linear* value is
//! nearest (ties to the lower code), so the error a level gains is at most half the gap
//! between the two neighbouring codes' linear values.

use super::texture_decode::{ColorSpace, srgb_to_linear};
use glam::{DVec3, Vec4};
use std::sync::{Arc, OnceLock};

/// Linear value of each code of one channel at one precision.
type Table8 = [f32; 256];
/// The 16-bit counterpart of [`Table8`].
type Table16 = [f32; 65536];

/// The stored codes or values.
#[derive(Clone)]
enum Data {
    /// 8-bit codes, `channels` per texel.
    U8(Arc<[u8]>),
    /// 16-bit codes, `channels` per texel.
    U16(Arc<[u16]>),
    /// Linear RGBA floats (HDR images, tests, and anything built from floats).
    F32(Arc<[Vec4]>),
}

/// A texture's texels: row-major, top row first, stored compactly (see the module notes).
/// Cloning shares the storage.
#[derive(Clone)]
pub struct Texels {
    data: Data,
    /// Channels per texel in `data` (1–4; 4 for f32).
    channels: u8,
    /// How colour codes are decoded (f32 storage is already linear).
    space: ColorSpace,
    /// Number of texels.
    len: usize,
}

impl std::fmt::Debug for Texels {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "Texels({} × {} {}, {:?})",
            self.len,
            self.channels,
            self.precision_name(),
            self.space
        )
    }
}

impl PartialEq for Texels {
    /// Equal when every texel reads the same linear value.
    fn eq(&self, other: &Self) -> bool {
        self.len == other.len && (0..self.len).all(|i| self.texel(i) == other.texel(i))
    }
}

impl From<Vec<Vec4>> for Texels {
    fn from(texels: Vec<Vec4>) -> Self {
        Self::from_linear(texels)
    }
}

/// Linear value of each 8-bit code: the sRGB EOTF of `code / 255`, or `code / 255`.
fn table8(space: ColorSpace) -> &'static Table8 {
    static SRGB: OnceLock<Table8> = OnceLock::new();
    static LINEAR: OnceLock<Table8> = OnceLock::new();
    let (cell, srgb) = match space {
        ColorSpace::Srgb => (&SRGB, true),
        ColorSpace::Linear => (&LINEAR, false),
    };
    cell.get_or_init(|| {
        std::array::from_fn(|code| {
            // `code` < 256, so the conversion to f32 is exact.
            let encoded = code as f32 / 255.0;
            if srgb {
                srgb_to_linear(encoded)
            } else {
                encoded
            }
        })
    })
}

/// Linear value of each 16-bit code: the sRGB EOTF of `code / 65535`, or `code / 65535`.
fn table16(space: ColorSpace) -> &'static Table16 {
    static SRGB: OnceLock<Box<Table16>> = OnceLock::new();
    static LINEAR: OnceLock<Box<Table16>> = OnceLock::new();
    let (cell, srgb) = match space {
        ColorSpace::Srgb => (&SRGB, true),
        ColorSpace::Linear => (&LINEAR, false),
    };
    cell.get_or_init(|| {
        // Built on the heap: 256 KiB is too much for a worker thread's stack.
        let values: Vec<f32> = (0..=u16::MAX)
            .map(|code| {
                let encoded = f32::from(code) / 65535.0;
                if srgb {
                    srgb_to_linear(encoded)
                } else {
                    encoded
                }
            })
            .collect();
        // Invariant: the range 0..=u16::MAX has exactly 65 536 elements.
        values
            .into_boxed_slice()
            .try_into()
            .expect("65536 table entries")
    })
}

/// Reads one texel as linear RGBA. Implemented for each storage format so that filters are
/// compiled once per format ([`Texels::visit`]) and the inner loops carry no format switch.
pub trait TexelRead: Copy {
    /// The texel at `index` (row-major); white if out of range (constructors prevent it).
    fn read(&self, index: usize) -> Vec4;
}

/// Expands the `N` channel values of a compact layout to RGBA.
#[inline(always)]
fn expand<const N: usize>(c: [f32; 4]) -> Vec4 {
    match N {
        1 => Vec4::new(c[0], c[0], c[0], 1.0),
        2 => Vec4::new(c[0], c[0], c[0], c[1]),
        3 => Vec4::new(c[0], c[1], c[2], 1.0),
        _ => Vec4::new(c[0], c[1], c[2], c[3]),
    }
}

/// Whether channel `k` of an `N`-channel layout is alpha (linear whatever the colour space).
#[inline(always)]
const fn is_alpha<const N: usize>(k: usize) -> bool {
    (N == 2 && k == 1) || (N == 4 && k == 3)
}

/// Reader of 8-bit texels with `N` channels.
#[derive(Clone, Copy)]
pub struct Read8<'a, const N: usize> {
    /// The codes, one `N`-array per texel (one bounds check per read).
    data: &'a [[u8; N]],
    color: &'static Table8,
    alpha: &'static Table8,
}

impl<'a, const N: usize> Read8<'a, N> {
    /// The reader of `codes` (`N` per texel; a trailing partial texel, which constructors
    /// prevent, is not read).
    #[inline(always)]
    fn new(codes: &'a [u8], color: &'static Table8, alpha: &'static Table8) -> Self {
        Self {
            data: codes.as_chunks::<N>().0,
            color,
            alpha,
        }
    }
}

impl<const N: usize> TexelRead for Read8<'_, N> {
    #[inline(always)]
    fn read(&self, index: usize) -> Vec4 {
        let Some(codes) = self.data.get(index) else {
            return Vec4::ONE;
        };
        let mut c = [0.0; 4];
        for k in 0..N {
            let table = if is_alpha::<N>(k) {
                self.alpha
            } else {
                self.color
            };
            c[k] = table[usize::from(codes[k])];
        }
        expand::<N>(c)
    }
}

/// Reader of 16-bit texels with `N` channels.
#[derive(Clone, Copy)]
pub struct Read16<'a, const N: usize> {
    /// The codes, one `N`-array per texel (one bounds check per read).
    data: &'a [[u16; N]],
    color: &'static Table16,
    alpha: &'static Table16,
}

impl<'a, const N: usize> Read16<'a, N> {
    /// The reader of `codes` (`N` per texel; a trailing partial texel, which constructors
    /// prevent, is not read).
    #[inline(always)]
    fn new(codes: &'a [u16], color: &'static Table16, alpha: &'static Table16) -> Self {
        Self {
            data: codes.as_chunks::<N>().0,
            color,
            alpha,
        }
    }
}

impl<const N: usize> TexelRead for Read16<'_, N> {
    #[inline(always)]
    fn read(&self, index: usize) -> Vec4 {
        let Some(codes) = self.data.get(index) else {
            return Vec4::ONE;
        };
        let mut c = [0.0; 4];
        for k in 0..N {
            let table = if is_alpha::<N>(k) {
                self.alpha
            } else {
                self.color
            };
            c[k] = table[usize::from(codes[k])];
        }
        expand::<N>(c)
    }
}

/// Reader of linear f32 RGBA texels.
#[derive(Clone, Copy)]
pub struct ReadF32<'a> {
    data: &'a [Vec4],
}

impl TexelRead for ReadF32<'_> {
    #[inline(always)]
    fn read(&self, index: usize) -> Vec4 {
        self.data.get(index).copied().unwrap_or(Vec4::ONE)
    }
}

/// Work done with a [`TexelRead`] of whatever format the texels have ([`Texels::visit`]).
pub trait TexelVisitor {
    /// What the work returns.
    type Output;
    /// Does the work with `reader`.
    fn visit<R: TexelRead>(self, reader: R) -> Self::Output;
}

/// Work done with the readers of two texel stores at once ([`Texels::visit_pair`]): the two
/// levels a trilinear lookup blends.
pub trait TexelPairVisitor {
    /// What the work returns.
    type Output;
    /// Does the work with `a` (the first store's reader) and `b` (the second's).
    fn visit<R: TexelRead>(self, a: R, b: R) -> Self::Output;
}

/// Reads any storage one texel at a time ([`Texels::texel`]): the pair reader for two stores of
/// different formats, which MIP chains never have (every level keeps the base's format), so
/// that case is correct rather than fast.
#[derive(Clone, Copy)]
pub struct ReadAny<'a>(&'a Texels);

impl TexelRead for ReadAny<'_> {
    #[inline]
    fn read(&self, index: usize) -> Vec4 {
        self.0.texel(index)
    }
}

/// Nearest code to a linear value `v` in a monotone `table`: the code whose entry is closest
/// to `v`, ties to the lower code. Values outside the table's range clamp to its ends.
#[cfg(test)]
fn nearest_code(table: &[f32], v: f32) -> usize {
    let v = if v.is_nan() { 0.0 } else { v };
    // First code whose value is ≥ v; the answer is it or the one below.
    nearest_of(table, v, table.partition_point(|&t| t < v))
}

/// The nearer of codes `above − 1` and `above` to `v` (ties to the lower), `above` being the
/// first code whose value is ≥ `v`.
#[inline(always)]
fn nearest_of(table: &[f32], v: f32, above: usize) -> usize {
    if above == 0 {
        return 0;
    }
    if above >= table.len() {
        return table.len() - 1;
    }
    let below = above - 1;
    if v - table[below] <= table[above] - v {
        below
    } else {
        above
    }
}

/// [`nearest_code`] with the search narrowed by a guide table indexed by the value's f32 bits,
/// for building MIP levels (a 2048² texture's chain has 1.4 M texels to quantize, and a full
/// binary search per channel was a third of DamagedHelmet's start-up instructions).
///
/// A positive f32's bits order like its value, so dropping the low [`GUIDE_SHIFT`] bits puts
/// `v` in a bucket `[f(k), f(k + 1))` with `f(k) = from_bits(k << GUIDE_SHIFT)`, a relative
/// width of 2⁻⁸. `guide[k]` is the number of entries below `f(k)`, so the first entry ≥ `v` lies
/// in `guide[k] ..= guide[k + 1]`: one or two 8-bit codes (sRGB codes are at least 0.9 % apart
/// in linear terms), a few dozen 16-bit ones. The result is [`nearest_code`]'s exactly (tests
/// compare them on every code, values between codes, out-of-range values and NaN).
struct CodeSearch<'t> {
    table: &'t [f32],
    guide: &'t [u32],
}

/// Low bits of an f32 dropped to index a [`CodeSearch`] guide (8 mantissa bits kept).
const GUIDE_SHIFT: u32 = 15;

impl<'t> CodeSearch<'t> {
    /// The guide of `table` (monotone, finite, non-negative, non-empty): one entry per bucket
    /// up to the one holding the table's last value, and one past it.
    fn guide(table: &[f32]) -> Vec<u32> {
        let top = table.last().map_or(0, |t| t.to_bits() >> GUIDE_SHIFT);
        (0..=top + 1)
            .map(|k| {
                let start = f32::from_bits(k << GUIDE_SHIFT);
                // Invariant: tables have at most 65 536 entries.
                table.partition_point(|&t| t < start) as u32
            })
            .collect()
    }

    fn new(table: &'t [f32], guide: &'t [u32]) -> Self {
        Self { table, guide }
    }

    /// The nearest code to `v` (see [`nearest_code`]).
    #[inline]
    fn nearest(&self, v: f32) -> usize {
        let table = self.table;
        // NaN reads as 0; at or below the first entry (zero, negative) the answer is code 0,
        // so `v` is positive below.
        let v = if v.is_nan() { 0.0 } else { v };
        if table.first().is_none_or(|&t| v <= t) {
            return 0;
        }
        let k = (v.to_bits() >> GUIDE_SHIFT) as usize;
        let above = match (self.guide.get(k), self.guide.get(k + 1)) {
            (Some(&first), Some(&last)) => {
                let (first, last) = (first as usize, (last as usize).min(table.len()));
                first + table[first..last].partition_point(|&t| t < v)
            }
            // Beyond the last bucket: above every entry.
            _ => table.len(),
        };
        nearest_of(table, v, above)
    }
}

/// The guide of [`table8`]`(space)` for [`CodeSearch`].
fn guide8(space: ColorSpace) -> &'static [u32] {
    static SRGB: OnceLock<Vec<u32>> = OnceLock::new();
    static LINEAR: OnceLock<Vec<u32>> = OnceLock::new();
    let cell = match space {
        ColorSpace::Srgb => &SRGB,
        ColorSpace::Linear => &LINEAR,
    };
    cell.get_or_init(|| CodeSearch::guide(table8(space)))
}

/// The guide of [`table16`]`(space)` for [`CodeSearch`].
fn guide16(space: ColorSpace) -> &'static [u32] {
    static SRGB: OnceLock<Vec<u32>> = OnceLock::new();
    static LINEAR: OnceLock<Vec<u32>> = OnceLock::new();
    let cell = match space {
        ColorSpace::Srgb => &SRGB,
        ColorSpace::Linear => &LINEAR,
    };
    cell.get_or_init(|| CodeSearch::guide(table16(space)))
}

/// Channel `k` of an `n`-channel layout taken from linear RGBA `v`, and whether it is alpha
/// (see [`Texels::quantized_like`]).
#[inline(always)]
fn pick(v: Vec4, n: usize, k: usize) -> (f32, bool) {
    match (n, k) {
        (1 | 2, 0) => (v.x, false),
        (2, _) => (v.w, true),
        (_, 3) => (v.w, true),
        (_, k) => (v[k], false),
    }
}

/// `values` quantized to `n` channels per texel with the colour and alpha searches.
fn quantize<T>(
    values: &[Vec4],
    n: usize,
    color: &CodeSearch<'_>,
    alpha: &CodeSearch<'_>,
    code: impl Fn(usize) -> T,
) -> Vec<T> {
    let mut codes = Vec::with_capacity(values.len() * n);
    for &v in values {
        for k in 0..n {
            let (x, is_alpha) = pick(v, n, k);
            let search = if is_alpha { alpha } else { color };
            codes.push(code(search.nearest(x)));
        }
    }
    codes
}

impl Texels {
    /// Linear RGBA floats (stored as given).
    pub fn from_linear(texels: Vec<Vec4>) -> Self {
        Self {
            len: texels.len(),
            data: Data::F32(texels.into()),
            channels: 4,
            space: ColorSpace::Linear,
        }
    }

    /// 8-bit codes, `channels` (1–4) per texel in `space`; `None` if `channels` is out of range
    /// or the codes are not a whole number of texels.
    pub fn from_u8(channels: u8, space: ColorSpace, codes: Vec<u8>) -> Option<Self> {
        let n = usize::from(channels);
        ((1..=4).contains(&n) && codes.len().is_multiple_of(n)).then(|| Self {
            len: codes.len() / n,
            data: Data::U8(codes.into()),
            channels,
            space,
        })
    }

    /// 16-bit codes, `channels` (1–4) per texel in `space`; `None` as for [`Self::from_u8`].
    pub fn from_u16(channels: u8, space: ColorSpace, codes: Vec<u16>) -> Option<Self> {
        let n = usize::from(channels);
        ((1..=4).contains(&n) && codes.len().is_multiple_of(n)).then(|| Self {
            len: codes.len() / n,
            data: Data::U16(codes.into()),
            channels,
            space,
        })
    }

    /// Number of texels.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there are no texels.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Channels stored per texel (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA).
    pub fn channels(&self) -> u8 {
        self.channels
    }

    /// How colour channels are decoded.
    pub fn space(&self) -> ColorSpace {
        self.space
    }

    /// Bits per stored channel: 8, 16 or 32 (float).
    pub fn bits(&self) -> u32 {
        match self.data {
            Data::U8(_) => 8,
            Data::U16(_) => 16,
            Data::F32(_) => 32,
        }
    }

    fn precision_name(&self) -> &'static str {
        match self.data {
            Data::U8(_) => "u8",
            Data::U16(_) => "u16",
            Data::F32(_) => "f32",
        }
    }

    /// Bytes the stored texels occupy.
    pub fn bytes(&self) -> usize {
        match &self.data {
            Data::U8(d) => d.len(),
            Data::U16(d) => d.len() * 2,
            Data::F32(d) => d.len() * std::mem::size_of::<Vec4>(),
        }
    }

    /// The linear RGBA value of texel `index` (white out of range). For one-off reads; filters
    /// go through [`Self::visit`].
    pub fn texel(&self, index: usize) -> Vec4 {
        struct One(usize);
        impl TexelVisitor for One {
            type Output = Vec4;
            fn visit<R: TexelRead>(self, reader: R) -> Vec4 {
                reader.read(self.0)
            }
        }
        self.visit(One(index))
    }

    /// The texels in order, as linear RGBA.
    pub fn iter(&self) -> impl Iterator<Item = Vec4> + '_ {
        (0..self.len).map(|i| self.texel(i))
    }

    /// All texels as linear RGBA floats (the f32 storage of the same values).
    pub fn to_linear(&self) -> Vec<Vec4> {
        (0..self.len).map(|i| self.texel(i)).collect()
    }

    /// The mean linear RGB over all texels, summed in f64 in texel order.
    pub fn mean_rgb(&self) -> DVec3 {
        let n = self.len.max(1) as f64;
        let sum = (0..self.len).fold(DVec3::ZERO, |acc, i| {
            acc + self.texel(i).truncate().as_dvec3()
        });
        sum / n
    }

    /// Runs `visitor` with the reader of this storage's format.
    #[inline]
    pub fn visit<V: TexelVisitor>(&self, visitor: V) -> V::Output {
        match &self.data {
            Data::F32(data) => visitor.visit(ReadF32 { data }),
            Data::U8(data) => {
                let (color, alpha) = (table8(self.space), table8(ColorSpace::Linear));
                match self.channels {
                    1 => visitor.visit(Read8::<1>::new(data, color, alpha)),
                    2 => visitor.visit(Read8::<2>::new(data, color, alpha)),
                    3 => visitor.visit(Read8::<3>::new(data, color, alpha)),
                    _ => visitor.visit(Read8::<4>::new(data, color, alpha)),
                }
            }
            Data::U16(data) => {
                let (color, alpha) = (table16(self.space), table16(ColorSpace::Linear));
                match self.channels {
                    1 => visitor.visit(Read16::<1>::new(data, color, alpha)),
                    2 => visitor.visit(Read16::<2>::new(data, color, alpha)),
                    3 => visitor.visit(Read16::<3>::new(data, color, alpha)),
                    _ => visitor.visit(Read16::<4>::new(data, color, alpha)),
                }
            }
        }
    }

    /// Runs `visitor` with the readers of this storage and `other`, dispatched on the format
    /// once for both: one compiled instance per format when they share it (precision, channel
    /// layout and colour space, as the levels of one MIP chain do), [`ReadAny`] otherwise.
    #[inline]
    pub fn visit_pair<V: TexelPairVisitor>(&self, other: &Texels, visitor: V) -> V::Output {
        let same_layout = self.channels == other.channels && self.space == other.space;
        match (&self.data, &other.data) {
            (Data::F32(a), Data::F32(b)) => visitor.visit(ReadF32 { data: a }, ReadF32 { data: b }),
            (Data::U8(a), Data::U8(b)) if same_layout => {
                let (color, alpha) = (table8(self.space), table8(ColorSpace::Linear));
                let (a, b) = (&a[..], &b[..]);
                match self.channels {
                    1 => visitor.visit(
                        Read8::<1>::new(a, color, alpha),
                        Read8::<1>::new(b, color, alpha),
                    ),
                    2 => visitor.visit(
                        Read8::<2>::new(a, color, alpha),
                        Read8::<2>::new(b, color, alpha),
                    ),
                    3 => visitor.visit(
                        Read8::<3>::new(a, color, alpha),
                        Read8::<3>::new(b, color, alpha),
                    ),
                    _ => visitor.visit(
                        Read8::<4>::new(a, color, alpha),
                        Read8::<4>::new(b, color, alpha),
                    ),
                }
            }
            (Data::U16(a), Data::U16(b)) if same_layout => {
                let (color, alpha) = (table16(self.space), table16(ColorSpace::Linear));
                let (a, b) = (&a[..], &b[..]);
                match self.channels {
                    1 => visitor.visit(
                        Read16::<1>::new(a, color, alpha),
                        Read16::<1>::new(b, color, alpha),
                    ),
                    2 => visitor.visit(
                        Read16::<2>::new(a, color, alpha),
                        Read16::<2>::new(b, color, alpha),
                    ),
                    3 => visitor.visit(
                        Read16::<3>::new(a, color, alpha),
                        Read16::<3>::new(b, color, alpha),
                    ),
                    _ => visitor.visit(
                        Read16::<4>::new(a, color, alpha),
                        Read16::<4>::new(b, color, alpha),
                    ),
                }
            }
            _ => visitor.visit(ReadAny(self), ReadAny(other)),
        }
    }

    /// `values` (linear RGBA) stored in this storage's format: the same precision, channel
    /// layout and colour space, each channel the nearest code in linear terms (see the module
    /// notes). Channels the layout lacks are dropped (alpha of an opaque layout, G and B of a
    /// grey one: a MIP level of such a base has them equal to what is kept).
    pub fn quantized_like(&self, values: &[Vec4]) -> Self {
        let n = usize::from(self.channels);
        let data = match &self.data {
            Data::F32(_) => return Self::from_linear(values.to_vec()),
            Data::U8(_) => {
                let color = CodeSearch::new(table8(self.space), guide8(self.space));
                let alpha = CodeSearch::new(table8(ColorSpace::Linear), guide8(ColorSpace::Linear));
                // Invariant: a 256-entry table's index fits a u8.
                Data::U8(quantize(values, n, &color, &alpha, |c| c as u8).into())
            }
            Data::U16(_) => {
                let color = CodeSearch::new(table16(self.space), guide16(self.space));
                let alpha =
                    CodeSearch::new(table16(ColorSpace::Linear), guide16(ColorSpace::Linear));
                // Invariant: a 65 536-entry table's index fits a u16.
                Data::U16(quantize(values, n, &color, &alpha, |c| c as u16).into())
            }
        };
        Self {
            len: values.len(),
            data,
            channels: self.channels,
            space: self.space,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_read_the_values_the_rgba_decoder_stored() {
        let srgb = table8(ColorSpace::Srgb);
        let grey = Texels::from_u8(1, ColorSpace::Srgb, vec![0, 128, 255]).unwrap();
        assert_eq!(
            grey.texel(1),
            Vec4::new(srgb[128], srgb[128], srgb[128], 1.0)
        );
        let ga = Texels::from_u8(2, ColorSpace::Srgb, vec![128, 51]).unwrap();
        assert_eq!(ga.texel(0), Vec4::new(srgb[128], srgb[128], srgb[128], 0.2));
        let rgb = Texels::from_u8(3, ColorSpace::Linear, vec![0, 51, 255]).unwrap();
        assert_eq!(rgb.texel(0), Vec4::new(0.0, 0.2, 1.0, 1.0));
        assert_eq!(rgb.texel(7), Vec4::ONE, "out of range reads white");
        let rgba16 = Texels::from_u16(4, ColorSpace::Srgb, vec![32768, 0, 65535, 0]).unwrap();
        let t = rgba16.texel(0);
        assert!((t.x - srgb_to_linear(32768.0 / 65535.0)).abs() < 1e-7);
        assert_eq!((t.y, t.z, t.w), (0.0, 1.0, 0.0));
        assert_eq!(rgba16.bytes(), 8);
        assert!(Texels::from_u8(3, ColorSpace::Linear, vec![0; 4]).is_none());
        assert!(Texels::from_u8(5, ColorSpace::Linear, vec![0; 5]).is_none());
    }

    /// The guided search gives the full search's code for every code's own value, values
    /// between and around neighbouring codes, out-of-range values and NaN, at both precisions
    /// and in both colour spaces.
    #[test]
    fn guided_quantization_is_the_full_search() {
        let check = |table: &[f32], guide: &[u32], step: usize| {
            let search = CodeSearch::new(table, guide);
            let mut values = vec![-1.0, -0.0, 0.0, 1.0, 2.0, f32::NAN, f32::INFINITY];
            for code in (0..table.len()).step_by(step) {
                let t = table[code];
                values.extend([t, f32::from_bits(t.to_bits() + 1), t * 0.999_999]);
                if let Some(&next) = table.get(code + 1) {
                    for f in [0.25, 0.4999, 0.5, 0.5001, 0.75] {
                        values.push(t + f * (next - t));
                    }
                }
            }
            for v in values {
                assert_eq!(search.nearest(v), nearest_code(table, v), "{v}");
            }
        };
        for space in [ColorSpace::Srgb, ColorSpace::Linear] {
            check(table8(space), guide8(space), 1);
            check(table16(space), guide16(space), 7);
        }
    }

    /// Quantization picks the nearest code in linear terms: every code's own value comes back
    /// as that code, and a value between two codes goes to the nearer one.
    #[test]
    fn quantization_is_nearest_in_linear_space() {
        for space in [ColorSpace::Srgb, ColorSpace::Linear] {
            let table = table8(space);
            for code in 0..256 {
                assert_eq!(nearest_code(table, table[code]), code);
            }
            for code in 0..255 {
                let (a, b) = (table[code], table[code + 1]);
                assert_eq!(nearest_code(table, a + 0.49 * (b - a)), code);
                assert_eq!(nearest_code(table, a + 0.51 * (b - a)), code + 1);
            }
            assert_eq!(nearest_code(table, -1.0), 0);
            assert_eq!(nearest_code(table, 2.0), 255);
            assert_eq!(nearest_code(table, f32::NAN), 0);
        }
        let base = Texels::from_u8(3, ColorSpace::Srgb, vec![0; 3]).unwrap();
        let q = base.quantized_like(&[Vec4::new(0.5, 0.25, 1.0, 0.3)]);
        assert_eq!(q.channels(), 3);
        assert_eq!(q.texel(0).w, 1.0, "an opaque layout stays opaque");
        for k in 0..3 {
            assert!((q.texel(0)[k] - [0.5, 0.25, 1.0][k]).abs() < 0.005);
        }
    }
}
