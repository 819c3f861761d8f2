//! The Trowbridge-Reitz (GGX) microfacet distribution with Smith height-correlated
//! masking-shadowing and visible-normal sampling.
//!
//! For a unit microfacet normal `m` in the local frame (+Z the macro normal) and roughnesses
//! `αx`, `αy` (glTF: `α = roughness²`, isotropic):
//!
//! ```text
//! D(m)  = 1 / (π αx αy (mx²/αx² + my²/αy² + mz²)²)          for mz > 0, else 0
//!       = α² / (π ((n·m)² (α² − 1) + 1)²)                    (isotropic, glTF Appendix B)
//! Λ(w)  = (√(1 + (αx² wx² + αy² wy²)/wz²) − 1) / 2
//! G1(w) = 1 / (1 + Λ(w))
//! G2(wo, wi) = 1 / (1 + Λ(wo) + Λ(wi))                       (height-correlated Smith)
//! Dv(w, m) = G1(w) · max(0, w·m) · D(m) / |wz|               (visible normals, ∫ Dv dm = 1)
//! ```
//!
//! `D` is normalised over projected area, `∫ D(m) (n·m) dm = 1`. Visible normals are sampled
//! with the spherical-cap method of Dupuy & Benyoub (2023, "Sampling Visible GGX Normals with
//! Spherical Caps"), which draws the same distribution as Heitz (2018): stretch `w` to the
//! configuration of `α = 1`, where visible normals are `normalize(wh + c)` for `c` uniform on
//! the spherical cap `c.z > −wh.z`, and unstretch.
//! The pdf of the reflected direction `wi = reflect(wo, m)` is `Dv(wo, m) / (4 |wo·m|)`.
//!
//! Below [`SMOOTH_ALPHA`] the distribution is treated as a delta (a smooth interface): `D`
//! overflows single precision long before α reaches 0, and such surfaces are mirrors in all
//! but name.

use glam::{Vec2, Vec3};
use std::f32::consts::{PI, TAU};

/// Roughness α below which a surface is perfectly smooth (handled as a delta lobe). α = 10⁻³
/// is perceptual roughness ≈ 0.032; the highlight of such a surface is narrower than a pixel
/// of any practical camera, and `D` would peak at 1/(πα²) ≈ 3·10⁵.
pub const SMOOTH_ALPHA: f32 = 1e-3;

/// The GGX distribution with roughnesses `alpha_x`, `alpha_y` along the local X and Y axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrowbridgeReitz {
    /// α along local X.
    pub alpha_x: f32,
    /// α along local Y.
    pub alpha_y: f32,
}

impl TrowbridgeReitz {
    /// An anisotropic distribution; non-finite or negative α are taken as 0 (smooth).
    pub fn new(alpha_x: f32, alpha_y: f32) -> Self {
        let clean = |a: f32| if a.is_finite() { a.max(0.0) } else { 0.0 };
        Self {
            alpha_x: clean(alpha_x),
            alpha_y: clean(alpha_y),
        }
    }

    /// An isotropic distribution of roughness α.
    pub fn isotropic(alpha: f32) -> Self {
        Self::new(alpha, alpha)
    }

    /// glTF's mapping from perceptual roughness (clamped to [0, 1]) to α = roughness².
    pub fn from_roughness(roughness: f32) -> Self {
        let r = if roughness.is_finite() {
            roughness.clamp(0.0, 1.0)
        } else {
            1.0
        };
        Self::isotropic(r * r)
    }

    /// KHR_materials_anisotropy's distribution for perceptual `roughness` and
    /// `anisotropyStrength` `strength` (both clamped to [0, 1]): `αx = αt = mix(α, 1,
    /// strength²)` along the anisotropy direction (local X), `αy = αb = α`, with `α =
    /// roughness²`. Strength 0 is exactly [`from_roughness`](Self::from_roughness). When
    /// `αt` is rough, `αb` is kept at least [`SMOOTH_ALPHA`] (a lobe smooth along one axis
    /// only is a line no sampler or density resolves in single precision; the Khronos sample
    /// viewer clamps it the same way).
    pub fn from_roughness_anisotropy(roughness: f32, strength: f32) -> Self {
        let iso = Self::from_roughness(roughness);
        let s = if strength.is_finite() {
            strength.clamp(0.0, 1.0)
        } else {
            0.0
        };
        if s <= 0.0 {
            return iso;
        }
        let a = iso.alpha_x;
        let at = a + (1.0 - a) * s * s;
        let ab = if at >= SMOOTH_ALPHA {
            a.max(SMOOTH_ALPHA)
        } else {
            a
        };
        Self::new(at, ab)
    }

    /// Whether the surface is handled as a delta (smooth) interface: both α below
    /// [`SMOOTH_ALPHA`].
    #[inline]
    pub fn is_smooth(&self) -> bool {
        self.alpha_x.max(self.alpha_y) < SMOOTH_ALPHA
    }

    /// The microfacet density `D(m)` per unit projected area, for a unit `m`.
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let (x, y) = (m.x / self.alpha_x, m.y / self.alpha_y);
        let s = x * x + y * y + m.z * m.z;
        let d = 1.0 / (PI * self.alpha_x * self.alpha_y * s * s);
        if d.is_finite() { d } else { 0.0 }
    }

    /// Smith's Λ(w) (infinite at grazing `w`).
    #[inline]
    pub fn lambda(&self, w: Vec3) -> f32 {
        if w.z == 0.0 {
            return f32::INFINITY;
        }
        let ax = self.alpha_x * w.x;
        let ay = self.alpha_y * w.y;
        let a2t2 = (ax * ax + ay * ay) / (w.z * w.z);
        if !a2t2.is_finite() {
            return f32::INFINITY;
        }
        // (√(1+x) − 1)/2 written without the cancellation at small x.
        a2t2 / (2.0 * (1.0 + (1.0 + a2t2).sqrt()))
    }

    /// Smith's masking `G1(w) = 1/(1 + Λ(w))`.
    #[inline]
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking-shadowing `G2(wo, wi) = 1/(1 + Λ(wo) + Λ(wi))`.
    #[inline]
    pub fn g2(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// The density of visible normals `Dv(w, m) = G1(w) max(0, w·m) D(m) / |w_z|` (per solid
    /// angle of `m`; integrates to 1 over the hemisphere).
    #[inline]
    pub fn visible_d(&self, w: Vec3, m: Vec3) -> f32 {
        let cos = w.z.abs();
        if cos == 0.0 {
            return 0.0;
        }
        self.g1(w) * w.dot(m).max(0.0) * self.d(m) / cos
    }

    /// Draws a microfacet normal from [`visible_d`](Self::visible_d) for a `w` in the upper
    /// hemisphere (callers flip `w` into it). Returns a unit `m` with `m.z ≥ 0`.
    pub fn sample_visible(&self, w: Vec3, u: Vec2) -> Vec3 {
        // Stretch to the α = 1 configuration, where visible normals are uniform over the
        // spherical cap {c : c.z > −wh.z} offset by wh.
        let wh = Vec3::new(self.alpha_x * w.x, self.alpha_y * w.y, w.z).normalize_or(Vec3::Z);
        let phi = TAU * u.x;
        let z = (1.0 - u.y) * (1.0 + wh.z) - wh.z;
        let sin = (1.0 - z * z).max(0.0).sqrt();
        let c = Vec3::new(sin * phi.cos(), sin * phi.sin(), z);
        let h = c + wh;
        Vec3::new(self.alpha_x * h.x, self.alpha_y * h.y, h.z.max(0.0)).normalize_or(Vec3::Z)
    }

    /// Solid-angle pdf of `wi = reflect(wo, m)` when `m` is drawn by
    /// [`sample_visible`](Self::sample_visible): `Dv(wo, m) / (4 |wo·m|)`.
    #[inline]
    pub fn reflection_pdf(&self, wo: Vec3, m: Vec3) -> f32 {
        let om = wo.dot(m).abs();
        if om == 0.0 {
            return 0.0;
        }
        self.visible_d(wo, m) / (4.0 * om)
    }
}

impl TrowbridgeReitz {
    /// Draws a reflected direction for `wo` (upper hemisphere) by the **folded** visible-normal
    /// sampler: `wi = reflect(wo, m)` with `m ~ Dv(wo, ·)`, and a `wi` below the surface
    /// mirrored through the tangent plane, `(x, y, z) → (x, y, −z)`, instead of being lost.
    /// Its density ([`folded_reflection_pdf`](Self::folded_reflection_pdf)) is the sum of the
    /// plain reflection density at `wi` and at its mirror image, exact and in closed form, so
    /// the draw is as unbiased as the plain one; but no draw is wasted, which halves the
    /// second moment of a compensated rough lobe's weights at normal incidence (at α = 1 the
    /// plain sampler sends half its draws below the horizon). The returned `wi` has `z ≥ 0`
    /// (`z = 0` only for grazing draws, which callers reject).
    #[inline]
    pub fn sample_folded_reflection(&self, wo: Vec3, u: Vec2) -> Vec3 {
        let wi = reflect(wo, self.sample_visible(wo, u));
        Vec3::new(wi.x, wi.y, wi.z.abs())
    }

    /// The solid-angle density of [`sample_folded_reflection`](Self::sample_folded_reflection)
    /// at `wi` (upper hemisphere): `p(wi) + p(wi')`, with `p(w) = Dv(wo, h)/(4 |wo·h|)`,
    /// `h = normalize(wo + w)`, the plain reflection density, and `wi' = (x, y, −z)`.
    #[inline]
    pub fn folded_reflection_pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let plain = |w: Vec3| {
            let h = (wo + w).normalize_or_zero();
            if h == Vec3::ZERO {
                0.0
            } else {
                self.reflection_pdf(wo, h)
            }
        };
        plain(wi) + plain(Vec3::new(wi.x, wi.y, -wi.z))
    }
}

/// Reflects the local direction `w` about the unit normal `m`.
#[inline]
pub fn reflect(w: Vec3, m: Vec3) -> Vec3 {
    2.0 * w.dot(m) * m - w
}

/// Schlick's Fresnel approximation `F = f0 + (f90 − f0)(1 − cos)⁵` per channel.
#[inline]
pub fn schlick(f0: Vec3, f90: Vec3, cos: f32) -> Vec3 {
    let w = (1.0 - cos.abs()).clamp(0.0, 1.0);
    let w2 = w * w;
    f0 + (f90 - f0) * (w2 * w2 * w)
}

/// `∫ g(m) dωm` over the upper hemisphere of microfacet normals by the midpoint rule on
/// `nv × nphi` cells in `(v, φ)`, `θ = atan(a tan v)`: the substitution packs cells where GGX
/// of roughness `a` has its mass. The tests' independent quadrature (of the distribution, and
/// of the albedo tables in `energy` and `dielectric_energy`).
#[cfg(test)]
pub(crate) fn integrate_over_normals(
    a: f64,
    (nv, nphi): (usize, usize),
    g: impl Fn(Vec3) -> f64,
) -> f64 {
    let (dv, dphi) = (
        std::f64::consts::FRAC_PI_2 / nv as f64,
        std::f64::consts::TAU / nphi as f64,
    );
    let mut sum = 0.0;
    for i in 0..nv {
        let v = (i as f64 + 0.5) * dv;
        let t = v.tan();
        let theta = (a * t).atan();
        let dtheta_dv = a * (1.0 + t * t) / (1.0 + a * a * t * t);
        for j in 0..nphi {
            let phi = (j as f64 + 0.5) * dphi;
            let m = Vec3::new(
                (theta.sin() * phi.cos()) as f32,
                (theta.sin() * phi.sin()) as f32,
                theta.cos() as f32,
            );
            sum += g(m) * theta.sin() * dtheta_dv * dv * dphi;
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(theta: f64, phi: f64) -> Vec3 {
        Vec3::new(
            (theta.sin() * phi.cos()) as f32,
            (theta.sin() * phi.sin()) as f32,
            theta.cos() as f32,
        )
    }

    #[test]
    fn d_integrates_to_one_over_projected_area() {
        for &(ax, ay) in &[
            (1.0, 1.0),
            (0.5, 0.5),
            (0.1, 0.1),
            (0.02, 0.02),
            (0.3, 0.05),
        ] {
            let tr = TrowbridgeReitz::new(ax, ay);
            let a = (ax as f64 * ay as f64).sqrt();
            let i = integrate_over_normals(a, (1500, 192), |m| tr.d(m) as f64 * m.z as f64);
            assert!((i - 1.0).abs() < 2e-3, "α = ({ax}, {ay}): ∫ D cos = {i}");
        }
    }

    #[test]
    fn visible_normals_integrate_to_one() {
        // Checks Λ against D: ∫ Dv(w, m) dm = 1 holds only for the matching Λ.
        for &(ax, ay) in &[(0.8, 0.8), (0.2, 0.2), (0.05, 0.05), (0.4, 0.1)] {
            let tr = TrowbridgeReitz::new(ax, ay);
            let a = (ax as f64 * ay as f64).sqrt();
            for &(theta, phi) in &[(0.0, 0.0), (0.7, 0.3), (1.3, 2.0), (1.52, 4.0)] {
                let w = dir(theta, phi);
                let i = integrate_over_normals(a, (1500, 192), |m| tr.visible_d(w, m) as f64);
                assert!(
                    (i - 1.0).abs() < 3e-3,
                    "α = ({ax}, {ay}), θ = {theta}: ∫ Dv = {i}"
                );
            }
        }
    }

    #[test]
    fn lambda_matches_the_isotropic_closed_form() {
        let tr = TrowbridgeReitz::isotropic(0.3);
        for &theta in &[0.1f64, 0.8, 1.4] {
            let a2t2 = 0.09 * theta.tan().powi(2);
            let expect = ((1.0 + a2t2).sqrt() - 1.0) / 2.0;
            let got = tr.lambda(dir(theta, 1.1)) as f64;
            assert!(
                (got - expect).abs() < 1e-5 * (1.0 + expect),
                "{got} vs {expect}"
            );
        }
        assert_eq!(tr.g1(Vec3::X), 0.0);
        assert!((tr.g1(Vec3::Z) - 1.0).abs() < 1e-7);
    }

    #[test]
    fn sampled_normals_are_unit_and_upper() {
        let tr = TrowbridgeReitz::new(0.6, 0.2);
        for i in 0..64 {
            for j in 0..16 {
                let u = Vec2::new((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 16.0);
                let w = dir(0.05 + 1.5 * j as f64 / 16.0, i as f64);
                let m = tr.sample_visible(w, u);
                assert!((m.length() - 1.0).abs() < 1e-5 && m.z >= 0.0, "{m}");
                assert!(w.dot(m) >= -1e-5, "back-facing visible normal {m} for {w}");
            }
        }
    }

    #[test]
    fn smoothness_threshold_and_bad_input() {
        assert!(TrowbridgeReitz::from_roughness(0.0).is_smooth());
        assert!(TrowbridgeReitz::from_roughness(0.03).is_smooth());
        assert!(!TrowbridgeReitz::from_roughness(0.04).is_smooth());
        assert!(TrowbridgeReitz::new(f32::NAN, -1.0).is_smooth());
        assert_eq!(TrowbridgeReitz::from_roughness(f32::NAN).alpha_x, 1.0);
    }
}
