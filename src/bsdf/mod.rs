//! Bidirectional scattering distribution functions: what a surface does with light, as the
//! path tracer and the direct integrator ask for it.
//!
//! Every BSDF works in a local shading frame ([`Frame`]): the shading normal is +Z, `wo` and
//! `wi` are unit vectors pointing away from the surface. A BSDF answers three questions:
//! - [`Bsdf::eval`]: `f(wo, wi)` in 1/sr, without the cosine (zero for delta lobes);
//! - [`Bsdf::pdf`]: the solid-angle density with which [`Bsdf::sample`] picks `wi` through its
//!   non-delta lobes (delta lobes contribute no density, so MIS weights never see infinity);
//! - [`Bsdf::sample`]: a direction drawn from the BSDF with its weight `f·|cos θi|/pdf`.
//!
//! One BSDF per file, each with its formula in its doc block.

pub mod albedo_quadrature;
pub mod anisotropic_albedo;
pub mod clearcoat;
pub mod compensated_sampling;
pub mod dielectric;
pub mod dielectric_energy;
pub mod energy;
pub mod flags;
pub mod lambert;
pub mod layered;
pub mod metallic_roughness;
pub mod microfacet;
pub mod sheen;

pub use clearcoat::ClearcoatBsdf;
pub use dielectric::DielectricBsdf;
pub use flags::BsdfFlags;
pub use lambert::LambertBsdf;
pub use layered::LayeredBsdf;
pub use metallic_roughness::{BrdfModel, MetallicRoughnessBsdf};
pub use microfacet::TrowbridgeReitz;
pub use sheen::SheenBsdf;

use glam::{Vec2, Vec3};

/// An orthonormal shading frame: `n` is the shading normal, `t` and `b` span the tangent plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Tangent (local +X).
    pub t: Vec3,
    /// Bitangent (local +Y).
    pub b: Vec3,
    /// Normal (local +Z).
    pub n: Vec3,
}

impl Frame {
    /// A frame around the unit normal `n` with an arbitrary, continuous tangent (Duff et al.
    /// 2017, "Building an Orthonormal Basis, Revisited").
    pub fn from_normal(n: Vec3) -> Self {
        let (t, b) = n.any_orthonormal_pair();
        Self { t, b, n }
    }

    /// A frame around the unit normal `n` whose tangent is `tangent` projected onto the
    /// tangent plane (Gram-Schmidt); falls back to [`Frame::from_normal`] when the projection
    /// vanishes.
    pub fn from_normal_tangent(n: Vec3, tangent: Vec3) -> Self {
        let t = (tangent - n * n.dot(tangent)).normalize_or_zero();
        if t == Vec3::ZERO || !t.is_finite() {
            return Self::from_normal(n);
        }
        Self {
            t,
            b: n.cross(t),
            n,
        }
    }

    /// World → local.
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.t), v.dot(self.b), v.dot(self.n))
    }

    /// Local → world.
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.t * v.x + self.b * v.y + self.n * v.z
    }
}

/// A direction drawn by [`Bsdf::sample`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// The sampled incident direction, local frame, unit.
    pub wi: Vec3,
    /// `f(wo, wi) · |cos θi| / pdf` (for a delta lobe: its reflectance or transmittance
    /// divided by the probability of choosing that lobe).
    pub weight: Vec3,
    /// Solid-angle density of `wi` under [`Bsdf::pdf`]; for a delta lobe, the probability of
    /// choosing the lobe (a discrete probability, not a density).
    pub pdf: f32,
    /// Whether `wi` came from a delta lobe (mirror, smooth glass): no light sampling can
    /// reach it, so MIS gives the BSDF sample weight 1.
    pub delta: bool,
    /// Whether `wi` is on the other side of the surface from `wo` (transmission).
    pub transmission: bool,
}

/// A surface's scattering, in the local shading frame.
pub trait Bsdf {
    /// `f(wo, wi)` in 1/sr, without the cosine; zero for delta lobes.
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3;
    /// Solid-angle density of sampling `wi` given `wo` through the non-delta lobes.
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32;
    /// Draws `wi` given `wo`; `u_lobe` chooses a lobe, `u` the direction within it. `None`
    /// when no direction can be drawn (e.g. `wo` below the horizon of a reflector).
    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample>;
    /// The kinds of lobes this BSDF has ([`BsdfFlags`]).
    fn flags(&self) -> BsdfFlags;
    /// Whether every lobe is a delta lobe (then light sampling is pointless: `eval` is zero
    /// everywhere).
    #[inline]
    fn is_delta(&self) -> bool {
        self.flags().is_specular_only()
    }
}

/// cos θ of a local direction.
#[inline]
pub fn cos_theta(w: Vec3) -> f32 {
    w.z
}

/// Whether two local directions are on the same side of the surface.
#[inline]
pub fn same_hemisphere(a: Vec3, b: Vec3) -> bool {
    a.z * b.z > 0.0
}
