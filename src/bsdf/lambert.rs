//! The Lambertian BRDF.
//!
//! `f(wo, wi) = ρ/π` when `wo` and `wi` lie on the same side (above the surface for `wo`);
//! sampled by the cosine-weighted hemisphere, `pdf = cos θi / π`, so the sample weight is ρ.
//! Its directional-hemispherical reflectance is ρ at every angle.

use super::{Bsdf, BsdfFlags, BsdfSample, same_hemisphere};
use crate::sampling::warp::{cosine_hemisphere, cosine_hemisphere_pdf};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// Ideal diffuse reflection with albedo ρ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LambertBsdf {
    /// Albedo ρ per channel.
    pub albedo: Vec3,
}

impl Bsdf for LambertBsdf {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::REFLECTION | BsdfFlags::DIFFUSE
    }

    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z > 0.0 && same_hemisphere(wo, wi) {
            self.albedo * FRAC_1_PI
        } else {
            Vec3::ZERO
        }
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z > 0.0 && same_hemisphere(wo, wi) {
            cosine_hemisphere_pdf(wi.z)
        } else {
            0.0
        }
    }

    #[inline]
    fn sample(&self, wo: Vec3, _u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = cosine_hemisphere(u);
        let pdf = cosine_hemisphere_pdf(wi.z);
        if pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.albedo,
            pdf,
            delta: false,
            transmission: false,
        })
    }
}
