//! Procedural textures: value noise, Perlin gradient noise, mixed octaves and a checkerboard,
//! deterministic by seed and band-limited by the pixel's footprint so that they do not alias.
//!
//! A pattern is evaluated at a point of its domain (texture coordinates `(u, v, 0)` or the
//! world-space position), scaled by `frequency`, and mapped to a colour between `colors[0]`
//! (pattern value 0) and `colors[1]` (value 1).
//!
//! Band-limiting, given the footprint (the domain-space derivatives ∂p/∂x, ∂p/∂y of the
//! pixel):
//! - checkerboard: exact box filtering. The checkerboard is `(1 − s(x)·s(y)[·s(z)]) / 2` with
//!   `s` the ±1 square wave of period 2; a box filter of a product of functions of separate
//!   axes is the product of their 1-D box filters, and the box filter of `s` over a width `w`
//!   is a difference of its integral (a triangle wave) divided by `w`. The box's side along
//!   each axis is the footprint parallelogram's extent on that axis, `|∂p/∂x|ₖ + |∂p/∂y|ₖ`
//!   (`Anisotropic`), or the largest of them on every axis (`Trilinear`, isotropic).
//! - noise: each octave of frequency f has its energy below about one cycle per lattice
//!   cell; over a footprint of width w it is kept whole while `f·w ≤ ½`, faded linearly to
//!   its mean (0) by `f·w = 1` and dropped beyond ("clamping", as pbrt's FBm does).
//!
//! Lattice values and gradients come from an integer hash of the cell and the seed, so a
//! seed gives the same pattern on every machine and every run.

use glam::{IVec3, Vec3};

// The texture's description is scene data (read by the loader); its evaluation is here.
pub use crate::scene::procedural_texture::{Domain, Octave, Pattern, ProceduralTexture};

/// How a procedural texture is band-limited.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Band {
    /// Point-sampled: aliases under minification.
    Point,
    /// One footprint width for every axis (the longer one).
    Isotropic,
    /// The footprint's extent per axis.
    Anisotropic,
}

impl ProceduralTexture {
    /// The colour at domain point `p` over a footprint `(dp_dx, dp_dy)` (domain units).
    pub fn color(&self, p: Vec3, dp_dx: Vec3, dp_dy: Vec3, band: Band) -> Vec3 {
        let t = self.value(p, dp_dx, dp_dy, band).clamp(0.0, 1.0);
        self.colors[0].lerp(self.colors[1], t)
    }

    /// The pattern's value (in [0, 1] for checker and single noises) at `p`.
    pub fn value(&self, p: Vec3, dp_dx: Vec3, dp_dy: Vec3, band: Band) -> f32 {
        let f = self.frequency;
        let q = p * f;
        // Footprint in pattern units; non-finite footprints count as infinitely wide.
        let sanitize = |v: Vec3| {
            if v.is_finite() {
                v * f
            } else {
                Vec3::splat(f32::MAX)
            }
        };
        let (dx, dy) = (sanitize(dp_dx), sanitize(dp_dy));
        let width = match band {
            Band::Point => Vec3::ZERO,
            Band::Anisotropic => dx.abs() + dy.abs(),
            Band::Isotropic => Vec3::splat((dx.abs() + dy.abs()).max_element()),
        };
        let three_d = self.domain == Domain::World;
        match &self.pattern {
            Pattern::Checker => checker(q, width, three_d),
            Pattern::Value => 0.5 + 0.5 * band_limited(value_noise, q, 1.0, width, self.seed),
            Pattern::Perlin => 0.5 + 0.5 * band_limited(perlin, q, 1.0, width, self.seed),
            Pattern::Mixed(octaves) => {
                let sum: f32 = octaves
                    .iter()
                    .enumerate()
                    .map(|(i, o)| {
                        // Each octave gets its own lattice, so octaves do not correlate.
                        let seed = self.seed.wrapping_add(i as u64 * 0x9E37_79B9);
                        o.amplitude * band_limited(perlin, q, o.frequency, width, seed)
                    })
                    .sum();
                0.5 + 0.5 * sum
            }
        }
    }
}

/// The box-filtered checkerboard at `q` over a box of sides `width` (pattern units).
fn checker(q: Vec3, width: Vec3, three_d: bool) -> f32 {
    let s = filtered_square(q.x, width.x) * filtered_square(q.y, width.y);
    let s = if three_d {
        s * filtered_square(q.z, width.z)
    } else {
        s
    };
    0.5 * (1.0 - s)
}

/// The ±1 square wave (+1 on [0, 1), −1 on [1, 2), period 2) averaged over `[x − w/2, x + w/2]`.
fn filtered_square(x: f32, w: f32) -> f32 {
    // Work relative to a period boundary near x, so that large x keeps its precision.
    let x = f64::from(x).rem_euclid(2.0);
    let w = f64::from(w);
    if w.is_nan() || w <= 1e-6 {
        return if x < 1.0 { 1.0 } else { -1.0 };
    }
    if w >= 2.0 * 1e6 {
        return 0.0;
    }
    let integral = |t: f64| {
        // ∫₀ᵗ s: a triangle wave rising on [0, 1) and falling on [1, 2), zero every period.
        let m = t.rem_euclid(2.0);
        if m < 1.0 { m } else { 2.0 - m }
    };
    ((integral(x + 0.5 * w) - integral(x - 0.5 * w)) / w) as f32
}

/// One noise octave at relative frequency `f`, faded to its mean as the footprint (width
/// vector `width`, in base pattern units) approaches its wavelength.
fn band_limited(noise: fn(Vec3, u64) -> f32, q: Vec3, f: f32, width: Vec3, seed: u64) -> f32 {
    // Isotropic noise: its bandwidth is limited by the widest axis of the footprint.
    let cycles = f * width.max_element();
    let fade = (2.0 - 2.0 * cycles).clamp(0.0, 1.0);
    if fade == 0.0 || !cycles.is_finite() {
        return 0.0;
    }
    fade * noise(q * f, seed)
}

/// Quintic fade 6t⁵ − 15t⁴ + 10t³ (C² continuous, zero first and second derivatives at the
/// lattice points).
#[inline]
fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// A 64-bit integer hash of a lattice cell and a seed (SplitMix64's finaliser over a mix of
/// the coordinates).
#[inline]
fn hash(cell: IVec3, seed: u64) -> u64 {
    let mut h = seed ^ 0x9E37_79B9_7F4A_7C15;
    for c in cell.to_array() {
        h = (h ^ (c as u32 as u64)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        h ^= h >> 31;
    }
    h = h.wrapping_mul(0x94D0_49BB_1331_11EB);
    h ^ (h >> 29)
}

/// Splits `q` into its lattice cell and the fraction within it.
#[inline]
fn cell_of(q: Vec3) -> (IVec3, Vec3) {
    let floor = q.floor();
    (floor.as_ivec3(), q - floor)
}

/// Trilinear interpolation of 8 corner values with faded weights.
#[inline]
fn blend(corner: impl Fn(IVec3) -> f32, frac: Vec3) -> f32 {
    let (u, v, w) = (fade(frac.x), fade(frac.y), fade(frac.z));
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    let c = |x, y, z| corner(IVec3::new(x, y, z));
    lerp(
        lerp(
            lerp(c(0, 0, 0), c(1, 0, 0), u),
            lerp(c(0, 1, 0), c(1, 1, 0), u),
            v,
        ),
        lerp(
            lerp(c(0, 0, 1), c(1, 0, 1), u),
            lerp(c(0, 1, 1), c(1, 1, 1), u),
            v,
        ),
        w,
    )
}

/// Value noise in [−1, 1]: random values at lattice points, interpolated with the quintic
/// fade.
pub fn value_noise(q: Vec3, seed: u64) -> f32 {
    if !q.is_finite() {
        return 0.0;
    }
    let (cell, frac) = cell_of(q);
    blend(
        |o| {
            // The top 24 bits as a uniform value in [−1, 1].
            (hash(cell + o, seed) >> 40) as f32 / (1u64 << 23) as f32 - 1.0
        },
        frac,
    )
}

/// Perlin gradient noise (Perlin 2002: the 12 cube-edge gradients and the quintic fade),
/// about [−1, 1]; zero at every lattice point.
pub fn perlin(q: Vec3, seed: u64) -> f32 {
    if !q.is_finite() {
        return 0.0;
    }
    let (cell, frac) = cell_of(q);
    blend(
        |o| {
            let d = frac - o.as_vec3();
            let (a, b) = match hash(cell + o, seed) % 12 {
                0 => (d.x, d.y),
                1 => (-d.x, d.y),
                2 => (d.x, -d.y),
                3 => (-d.x, -d.y),
                4 => (d.x, d.z),
                5 => (-d.x, d.z),
                6 => (d.x, -d.z),
                7 => (-d.x, -d.z),
                8 => (d.y, d.z),
                9 => (-d.y, d.z),
                10 => (d.y, -d.z),
                _ => (-d.y, -d.z),
            };
            a + b
        },
        frac,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The filtered square wave matches a brute-force average over its box.
    #[test]
    fn filtered_square_matches_numerical_average() {
        for &(x, w) in &[
            (0.3f32, 0.5f32),
            (0.9, 0.4),
            (1.7, 3.3),
            (-5.2, 0.01),
            (10.5, 2.0),
        ] {
            let n = 20_000;
            let avg: f64 = (0..n)
                .map(|i| {
                    let t = f64::from(x) + (f64::from(w)) * ((i as f64 + 0.5) / n as f64 - 0.5);
                    if t.rem_euclid(2.0) < 1.0 { 1.0 } else { -1.0 }
                })
                .sum::<f64>()
                / n as f64;
            let got = filtered_square(x, w);
            assert!(
                (f64::from(got) - avg).abs() < 1e-3,
                "x {x} w {w}: {got} vs {avg}"
            );
        }
    }

    #[test]
    fn perlin_vanishes_on_the_lattice_and_noises_are_bounded() {
        assert_eq!(perlin(Vec3::new(3.0, -2.0, 7.0), 5), 0.0);
        for i in 0..1000 {
            let q = Vec3::new(i as f32 * 0.37, i as f32 * 0.11, i as f32 * 0.053);
            assert!(perlin(q, 1).abs() <= 1.0 + 1e-5);
            assert!(value_noise(q, 1).abs() <= 1.0 + 1e-5);
        }
    }
}
