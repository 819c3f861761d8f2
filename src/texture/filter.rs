//! Filtered texture lookups: what a pixel's footprint on the texture averages to.
//!
//! The footprint is the pixel's image in texture space to first order: the derivatives of uv
//! with respect to film x and y (from ray differentials), `∂uv/∂x` and `∂uv/∂y`. In texels
//! (scaled by the base level's size) their lengths ρx, ρy say how many texels one pixel
//! spans along each film axis.
//!
//! - `Nearest`, `Bilinear`, `Bicubic`: the base level only, footprint ignored (they alias
//!   under minification; for experiments and references).
//! - `Trilinear`: the isotropic level of detail `λ = log2(max(ρx, ρy))` (the OpenGL
//!   definition), bilinear on levels ⌊λ⌋ and ⌊λ⌋+1, blended by the fraction. Sharp where
//!   the footprint is round, blurry where it is long (a plane seen at a grazing angle).
//! - `Anisotropic`: λ from the *minor* axis, and ⌈major/minor⌉ trilinear probes spaced along
//!   the major axis (as GPU anisotropic filtering does), the ratio capped at
//!   [`MAX_ANISOTROPY`] so a grazing footprint costs at most that many probes.
//!
//! Below one texel per pixel (λ ≤ 0, magnification) `Trilinear` and `Anisotropic` use the
//! glTF sampler's magnification filter (nearest or bilinear) on the base level. A footprint
//! that is not finite (a differential that could not be carried) reads the coarsest level,
//! the texture's mean: blurry, never NaN.

use super::image::{Reader, TexelGrid, Wrap};
use super::mipmap::MipMap;
use crate::scene::MagFilter;
use crate::scene::texels::{TexelPairVisitor, TexelRead, TexelVisitor};
use glam::{Vec2, Vec4};

/// Largest major/minor axis ratio the anisotropic filter honours (probes per lookup).
pub const MAX_ANISOTROPY: f32 = 16.0;

/// How textures are filtered; `--texture-filter`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TextureFilter {
    /// Nearest texel of the base level (no MIP maps; the glTF sampler is ignored).
    Nearest,
    /// Bilinear on the base level (no MIP maps).
    Bilinear,
    /// Bicubic (Catmull–Rom) on the base level (no MIP maps).
    Bicubic,
    /// Trilinear MIP mapping from the isotropic footprint.
    Trilinear,
    /// Anisotropic: several trilinear probes along the footprint's major axis.
    #[default]
    Anisotropic,
}

impl TextureFilter {
    /// Whether the filter reads the footprint, so that ray differentials are worth computing.
    pub fn uses_footprint(self) -> bool {
        matches!(self, Self::Trilinear | Self::Anisotropic)
    }

    /// Name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Nearest => "nearest",
            Self::Bilinear => "bilinear",
            Self::Bicubic => "bicubic",
            Self::Trilinear => "trilinear",
            Self::Anisotropic => "anisotropic",
        }
    }
}

/// A pixel's footprint in uv space: the derivatives of uv with respect to film x and y.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct UvFootprint {
    /// ∂uv/∂x (per pixel, already scaled for the sample count).
    pub duv_dx: Vec2,
    /// ∂uv/∂y.
    pub duv_dy: Vec2,
}

impl UvFootprint {
    /// The footprint in texels of a `width × height` level.
    #[inline]
    fn in_texels(&self, width: u32, height: u32) -> (Vec2, Vec2) {
        let size = Vec2::new(width as f32, height as f32);
        (self.duv_dx * size, self.duv_dy * size)
    }
}

/// The isotropic level of detail of `footprint` on `mip`: log2 of the longer axis in base
/// texels. −∞ for a zero footprint, +∞ for a non-finite one.
pub fn isotropic_lod(mip: &MipMap, footprint: &UvFootprint) -> f32 {
    let base = mip.level(0);
    let (dx, dy) = footprint.in_texels(base.width, base.height);
    let rho = dx.length().max(dy.length());
    if rho.is_nan() {
        f32::INFINITY
    } else {
        rho.log2()
    }
}

/// Filters `mip` at `uv` over `footprint` with `filter`.
pub fn lookup(mip: &MipMap, uv: Vec2, footprint: &UvFootprint, filter: TextureFilter) -> Vec4 {
    let base = mip.level(0);
    match filter {
        TextureFilter::Nearest => base.nearest(uv, mip.wrap),
        TextureFilter::Bilinear => base.bilinear(uv, mip.wrap),
        TextureFilter::Bicubic => base.bicubic(uv, mip.wrap),
        TextureFilter::Trilinear => trilinear(mip, uv, isotropic_lod(mip, footprint)),
        TextureFilter::Anisotropic => anisotropic(mip, uv, footprint),
    }
}

/// Trilinear interpolation at level of detail `lod` (magnification below 0, the coarsest
/// level for +∞ or NaN).
fn trilinear(mip: &MipMap, uv: Vec2, lod: f32) -> Vec4 {
    probe_mean(mip, Probes::one(uv), lod)
}

/// Where a lookup at one level of detail reads; every probe of a lookup shares it.
#[derive(Clone, Copy)]
enum Levels {
    /// The base level with the sampler's magnification filter (`lod ≤ 0`).
    Magnify,
    /// The coarsest level, bilinear (`lod` at or above it, or NaN).
    Coarsest,
    /// Bilinear on levels `fine` and `fine + 1`, blended by `f` (the fraction of `lod`).
    Pair { fine: usize, f: f32 },
}

impl Levels {
    #[inline]
    fn at(mip: &MipMap, lod: f32) -> Self {
        let top = (mip.level_count() - 1) as f32;
        if lod <= 0.0 {
            return Self::Magnify;
        }
        if lod.is_nan() || lod >= top {
            return Self::Coarsest;
        }
        // 0 < lod < top < 64 (each level halves a u32 side): truncation is the floor, and
        // both conversions are exact, so this is `lod.floor()` and `lod - lod.floor()`
        // without the floor's library call.
        let fine = lod as u32;
        Self::Pair {
            fine: fine as usize,
            f: lod - fine as f32,
        }
    }
}

/// The probe points of one lookup: `uv` alone, or the centres of `count` equal segments of
/// the footprint's major axis `step`, which spans −½ … +½ of it around `uv`.
#[derive(Clone, Copy)]
struct Probes {
    uv: Vec2,
    step: Vec2,
    count: u32,
}

impl Probes {
    fn one(uv: Vec2) -> Self {
        Self {
            uv,
            step: Vec2::ZERO,
            count: 1,
        }
    }

    /// The mean of `probe` over the points (the single point's value itself for one).
    #[inline(always)]
    fn mean<P: Probe>(&self, probe: &P) -> Vec4 {
        if self.count == 1 {
            return probe.at(self.uv);
        }
        let mut sum = Vec4::ZERO;
        for i in 0..self.count {
            let offset = (i as f32 + 0.5) / self.count as f32 - 0.5;
            sum += probe.at(self.uv + self.step * offset);
        }
        sum / self.count as f32
    }
}

/// One probe's reconstruction at a point: a trait rather than a closure so that it is
/// inlined into the probe loop (with the level's size and wrap rules held in registers).
trait Probe {
    fn at(&self, uv: Vec2) -> Vec4;
}

/// Nearest or bilinear on one level.
struct OneLevelProbe<R> {
    level: Reader<R>,
    nearest: bool,
}

impl<R: TexelRead> Probe for OneLevelProbe<R> {
    #[inline(always)]
    fn at(&self, uv: Vec2) -> Vec4 {
        if self.nearest {
            self.level.nearest(uv)
        } else {
            self.level.bilinear(uv)
        }
    }
}

/// Bilinear on two levels, blended by `f`.
struct TwoLevelProbe<R> {
    fine: Reader<R>,
    coarse: Reader<R>,
    f: f32,
}

impl<R: TexelRead> Probe for TwoLevelProbe<R> {
    #[inline(always)]
    fn at(&self, uv: Vec2) -> Vec4 {
        self.fine
            .bilinear(uv)
            .lerp(self.coarse.bilinear(uv), self.f)
    }
}

/// The mean of the trilinear probes at `lod`: the levels chosen once, and each level's storage
/// format dispatched once for all probes (the per-probe arithmetic is that of
/// [`TexelGrid::bilinear`] and [`TexelGrid::nearest`]).
fn probe_mean(mip: &MipMap, probes: Probes, lod: f32) -> Vec4 {
    let wrap = mip.wrap;
    match Levels::at(mip, lod) {
        Levels::Magnify => mip.level(0).texels.visit(OneLevel {
            grid: mip.level(0),
            probes,
            wrap,
            nearest: mip.mag_filter == MagFilter::Nearest,
        }),
        Levels::Coarsest => {
            let grid = mip.level(mip.level_count() - 1);
            grid.texels.visit(OneLevel {
                grid,
                probes,
                wrap,
                nearest: false,
            })
        }
        Levels::Pair { fine, f } => {
            let (a, b) = (mip.level(fine), mip.level(fine + 1));
            a.texels.visit_pair(
                &b.texels,
                TwoLevels {
                    grids: (a, b),
                    f,
                    probes,
                    wrap,
                },
            )
        }
    }
}

/// Probes on one level, nearest or bilinear.
struct OneLevel<'a> {
    grid: &'a TexelGrid,
    probes: Probes,
    wrap: Wrap,
    nearest: bool,
}

impl TexelVisitor for OneLevel<'_> {
    type Output = Vec4;

    #[inline(always)]
    fn visit<R: TexelRead>(self, reader: R) -> Vec4 {
        self.probes.mean(&OneLevelProbe {
            level: Reader::new(reader, self.grid, self.wrap),
            nearest: self.nearest,
        })
    }
}

/// Trilinear probes: bilinear on two adjacent levels, blended.
struct TwoLevels<'a> {
    grids: (&'a TexelGrid, &'a TexelGrid),
    f: f32,
    probes: Probes,
    wrap: Wrap,
}

impl TexelPairVisitor for TwoLevels<'_> {
    type Output = Vec4;

    #[inline(always)]
    fn visit<R: TexelRead>(self, a: R, b: R) -> Vec4 {
        self.probes.mean(&TwoLevelProbe {
            fine: Reader::new(a, self.grids.0, self.wrap),
            coarse: Reader::new(b, self.grids.1, self.wrap),
            f: self.f,
        })
    }
}

/// `x.ceil()` for `x ≥ 0` below 2²⁴ (exact there) without the library call, saturating for
/// larger or infinite `x`; 0 for NaN.
#[inline]
fn ceil_positive(x: f32) -> u32 {
    let t = x as u32;
    if (t as f32) < x {
        t.saturating_add(1)
    } else {
        t
    }
}

/// Probes along the major axis at the minor axis's level of detail.
fn anisotropic(mip: &MipMap, uv: Vec2, footprint: &UvFootprint) -> Vec4 {
    let base = mip.level(0);
    let (dx, dy) = footprint.in_texels(base.width, base.height);
    let (lx, ly) = (dx.length(), dy.length());
    if !(lx.is_finite() && ly.is_finite()) {
        return trilinear(mip, uv, f32::INFINITY);
    }
    let (major_uv, major, minor) = if lx >= ly {
        (footprint.duv_dx, lx, ly)
    } else {
        (footprint.duv_dy, ly, lx)
    };
    // Cap the eccentricity: widen the minor axis (blur) rather than take more probes.
    let minor = minor.max(major / MAX_ANISOTROPY);
    if major <= 1.0 || minor <= 0.0 {
        // At most one texel along the major axis: the footprint is within the reconstruction
        // filter's support, so magnification is right.
        return trilinear(mip, uv, minor.max(major).log2());
    }
    let lod = minor.log2();
    // major / minor is in [1, MAX_ANISOTROPY] up to rounding (minor ≥ major / 16 > 0), where
    // `ceil_positive` is exact.
    let probes = ceil_positive(major / minor).clamp(1, MAX_ANISOTROPY as u32);
    probe_mean(
        mip,
        Probes {
            uv,
            step: major_uv,
            count: probes,
        },
        lod,
    )
}

impl TextureFilter {
    /// Every filter, in the order the command line lists them.
    pub const ALL: [TextureFilter; 5] = [
        Self::Nearest,
        Self::Bilinear,
        Self::Bicubic,
        Self::Trilinear,
        Self::Anisotropic,
    ];
}

impl std::fmt::Display for TextureFilter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for TextureFilter {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|f| f.name() == s)
            .ok_or_else(|| {
                format!(
                    "unknown texture filter '{s}' (expected nearest, bilinear, bicubic, trilinear \
                 or anisotropic)"
                )
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn checker(n: u32) -> MipMap {
        let texels: Vec<Vec4> = (0..n * n)
            .map(|i| {
                if (i % n + i / n).is_multiple_of(2) {
                    Vec4::ZERO
                } else {
                    Vec4::ONE
                }
            })
            .collect();
        MipMap::from_grid(
            TexelGrid::new(n, n, texels).unwrap(),
            Wrap::default(),
            MagFilter::Linear,
        )
    }

    #[test]
    fn large_footprints_read_the_mean_and_nan_is_contained() {
        let mip = checker(8);
        let wide = UvFootprint {
            duv_dx: Vec2::new(4.0, 0.0),
            duv_dy: Vec2::new(0.0, 4.0),
        };
        for filter in [TextureFilter::Trilinear, TextureFilter::Anisotropic] {
            let v = lookup(&mip, Vec2::new(0.3, 0.7), &wide, filter);
            assert!(
                (v - Vec4::splat(0.5)).abs().max_element() < 1e-6,
                "{filter:?}: {v}"
            );
            let nan = UvFootprint {
                duv_dx: Vec2::NAN,
                duv_dy: Vec2::ZERO,
            };
            assert!(lookup(&mip, Vec2::new(0.3, 0.7), &nan, filter).is_finite());
        }
    }
}
