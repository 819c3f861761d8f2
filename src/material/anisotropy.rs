//! KHR_materials_anisotropy at a hit: the strength and the direction along which the
//! specular lobes are stretched.
//!
//! With the hit's tangent frame `(t, b, n)` (the TANGENT attribute or MikkTSpace's, `b =
//! w · n × t`, as for normal maps, see [`super::normal_map`]), the texel `c` of
//! `anisotropyTexture` (linear; white `(1, 0.5, 1)`-like defaults without one), the
//! extension's `anisotropyRotation` ρ and `anisotropyStrength` s:
//!
//! ```text
//! d        = normalize(2 c.rg − 1)            ((1, 0) without a texture)
//! d'       = R(ρ) d                           (counter-clockwise from t toward b)
//! strength = s · c.b                          (s without a texture)
//! T        = d'.x t + d'.y b                  (the anisotropy direction, world space)
//! αt = mix(α, 1, strength²),  αb = α          (α = roughness², see TrowbridgeReitz)
//! ```
//!
//! The BSDF's frame is then built around the shading normal with `T` as its X axis, so the
//! distribution's `αx = αt` lies along `T`. A mesh without tangents (no texture coordinates
//! to generate them from; the loader warns) shades isotropically.

use crate::scene::layers::Anisotropy;
use crate::texture::{TextureEvaluator, TexturePoint};
use glam::{Vec2, Vec3};

/// The anisotropy at one hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnisotropyAtHit {
    /// `anisotropyStrength × texture B`, in [0, 1].
    pub strength: f32,
    /// The anisotropy direction `T`: unit, world space, orthogonal to the shading normal.
    pub direction: Vec3,
}

/// The direction `d' = R(rotation) · normalize(2 rg − 1)` in the tangent frame for a texel's
/// red and green channels (`None`: no texture, the tangent `(1, 0)` rotated).
#[inline]
pub fn tangent_space_direction(rg: Option<Vec2>, rotation: f32) -> Vec2 {
    let d = rg
        .map(|c| (c * 2.0 - Vec2::ONE).normalize_or_zero())
        .filter(|d| *d != Vec2::ZERO && d.is_finite())
        .unwrap_or(Vec2::X);
    let (sin, cos) = if rotation.is_finite() {
        rotation.sin_cos()
    } else {
        (0.0, 1.0)
    };
    Vec2::new(cos * d.x - sin * d.y, sin * d.x + cos * d.y)
}

/// The anisotropy of `anisotropy` at `at`, around the shading normal `ns`; `None` when the
/// strength is 0 there or the mesh has no tangent frame.
#[inline]
pub fn at_hit(
    textures: &TextureEvaluator<'_>,
    at: &TexturePoint<'_>,
    anisotropy: &Anisotropy,
    ns: Vec3,
) -> Option<AnisotropyAtHit> {
    let si = at.si;
    let tangent = si.tangent_to_world(si.interpolate(at.mesh.tangents.as_deref()?)?);
    let texel = anisotropy.texture.as_ref().map(|t| textures.value(at, t));
    let strength = (anisotropy.strength * texel.map_or(1.0, |c| c.z)).clamp(0.0, 1.0);
    if strength.is_nan() || strength <= 0.0 {
        return None;
    }
    // The frame of the side the ray arrived on (a back face's normal is negated; so is its
    // bitangent, which keeps the direction on the surface where the texture put it).
    let side = if si.front_face { 1.0 } else { -1.0 };
    let (t, b) = super::normal_map::tangent_frame(side * ns, tangent)?;
    let d = tangent_space_direction(texel.map(|c| Vec2::new(c.x, c.y)), anisotropy.rotation);
    let direction = (t * d.x + b * d.y).normalize_or_zero();
    (direction != Vec3::ZERO && direction.is_finite()).then_some(AnisotropyAtHit {
        strength,
        direction,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_direction_and_rotation_compose() {
        let close = |a: Vec2, b: Vec2| (a - b).length() < 1e-6;
        assert!(close(tangent_space_direction(None, 0.0), Vec2::X));
        let quarter = std::f32::consts::FRAC_PI_2;
        assert!(close(tangent_space_direction(None, quarter), Vec2::Y));
        // (0.5, 1) encodes +b; rotated a quarter turn it points along −t.
        let up = Some(Vec2::new(0.5, 1.0));
        assert!(close(tangent_space_direction(up, 0.0), Vec2::Y));
        assert!(close(tangent_space_direction(up, quarter), -Vec2::X));
        // A texel with no direction (0.5, 0.5) falls back to the tangent.
        assert!(close(
            tangent_space_direction(Some(Vec2::splat(0.5)), 0.0),
            Vec2::X
        ));
    }
}
