//! Normal maps: a tangent-space normal texture turned into the shading normal at a hit, and
//! the rule that keeps shading normals from letting light through the geometric surface.
//!
//! # The perturbed normal (glTF `normalTexture`)
//!
//! A texel `c ∈ [0, 1]³` (decoded linearly) encodes the tangent-space normal
//!
//! ```text
//! m = normalize((2c − 1) ⊙ (s, s, 1))          s = normalTexture.scale
//! ```
//!
//! in the frame of the interpolated vertex normal `n`, tangent `t` (the TANGENT attribute's
//! xyz, or MikkTSpace's, made orthogonal to `n` by Gram-Schmidt) and bitangent
//! `b = w · (n × t)`, `w = ±1` the TANGENT's handedness:
//!
//! ```text
//! n_s = normalize(m.x · t + m.y · b + m.z · n)
//! ```
//!
//! A back face of a double-sided material uses the negated frame (glTF: back-face normals
//! are reversed), which negates `n_s`: a bump seen from behind is a dent.
//!
//! # No light through the horizon
//!
//! A perturbed normal can face away from the viewer, or reflect the view direction below the
//! geometric surface: a BSDF evaluated around it would then be black, or scatter light that
//! came through the surface. glint uses two rules:
//!
//! 1. [`keep_reflection_above`]: before shading, the normal is bent toward the geometric
//!    normal `n_g` until the mirror reflection of `ωo` about it lies at least
//!    `τ = min(0.01, 0.9 · ωo·n_g)` above the geometric surface (the idea of Cycles'
//!    `ensure_valid_specular_reflection`; derived and written here independently). The bent
//!    normal is the half vector between `ωo` and the reflection direction of height `τ`
//!    in the plane of `n_s` and `n_g`, so `ωo · n_s > 0` always holds afterwards.
//! 2. In the integrators, as for interpolated normals: a light sample or a BSDF sample `ωi`
//!    is used only when it is above both the geometric and the shading horizon
//!    (`ωi·n_g > 0` and `ωi·n_s > 0`), whichever strategy drew it, so MIS weights see the
//!    same domain for both strategies and no light crosses the geometric surface.
//!
//! The functions here are plain vector maths, so other material layers (a clearcoat's own
//! normal texture) call them with their own texel.

use glam::{Vec3, Vec4};

/// The tangent-space normal a texel encodes, with glTF's `scale` applied to x and y; `None`
/// when the result has no direction (a zero texel vector, non-finite data).
#[inline]
pub fn decode(texel: Vec3, scale: f32) -> Option<Vec3> {
    let m = (texel * 2.0 - Vec3::ONE) * Vec3::new(scale, scale, 1.0);
    let m = m.normalize_or_zero();
    (m != Vec3::ZERO && m.is_finite()).then_some(m)
}

/// The unit tangent-frame vectors (t, b) around the unit normal `n` from an interpolated
/// tangent (xyz, w handedness): `t` is the tangent made orthogonal to `n`, `b = w·(n × t)`
/// with `w` taken as +1 unless negative. `None` when the tangent is parallel to `n` or zero.
#[inline]
pub fn tangent_frame(n: Vec3, tangent: Vec4) -> Option<(Vec3, Vec3)> {
    let t = tangent.truncate();
    let t = (t - n * n.dot(t)).normalize_or_zero();
    if t == Vec3::ZERO || !t.is_finite() {
        return None;
    }
    let w = if tangent.w < 0.0 { -1.0 } else { 1.0 };
    Some((t, w * n.cross(t)))
}

/// The perturbed shading normal `n_s` (module docs) for a hit's front-face interpolated
/// unit normal `n` and tangent, from the normal texture's `texel` and `scale`; also returns
/// the frame's unit tangent. `None` (leave the normal alone) when the tangent or the texel
/// gives no direction.
#[inline]
pub fn perturbed_normal(texel: Vec3, scale: f32, n: Vec3, tangent: Vec4) -> Option<(Vec3, Vec3)> {
    let m = decode(texel, scale)?;
    let (t, b) = tangent_frame(n, tangent)?;
    let ns = (t * m.x + b * m.y + n * m.z).normalize_or_zero();
    (ns != Vec3::ZERO && ns.is_finite()).then_some((ns, t))
}

/// The smallest height above the geometric surface that [`keep_reflection_above`] keeps
/// the mirror direction at: `min(0.01, 0.9 · cos θo)`, so a grazing view may reflect as
/// grazingly as it arrives, but never below.
#[inline]
pub fn reflection_floor(cos_o: f32) -> f32 {
    (0.9 * cos_o).min(0.01)
}

/// Bends the unit shading normal `ns` toward the unit geometric normal `ng` so that the
/// mirror reflection of `wo` about it is at least [`reflection_floor`] above the geometric
/// surface (rule 1 of the module docs). `wo` is unit and on `ng`'s side (`wo·ng > 0`, which
/// [`crate::geometry::SurfaceInteraction`] guarantees); `ns` is returned unchanged when it
/// already satisfies the rule and faces `wo`.
///
/// In the plane spanned by `ng` and the part `x` of `ns` orthogonal to it, `wo` has
/// components `(i_x, i_z)` of length `L`; the reflection about a normal in that plane keeps
/// `wo`'s out-of-plane part (negated) and reflects the in-plane part, so it has height `τ`
/// exactly when its in-plane part is `(√(L² − τ²), τ)`. The bent normal is the normalised sum
/// of the in-plane parts of `wo` and of that direction.
#[inline]
pub fn keep_reflection_above(ns: Vec3, ng: Vec3, wo: Vec3) -> Vec3 {
    let cos_o = wo.dot(ng);
    let tau = reflection_floor(cos_o);
    let cos_s = wo.dot(ns);
    let reflected = 2.0 * cos_s * ns - wo;
    if cos_s > 0.0 && reflected.dot(ng) >= tau {
        return ns;
    }
    let x = (ns - ng * ns.dot(ng)).normalize_or_zero();
    if x == Vec3::ZERO || !x.is_finite() || cos_o <= 0.0 {
        // ns is (anti)parallel to ng, or wo is not on ng's side: ng itself reflects wo at
        // its own height, the best any normal can do.
        return ng;
    }
    let (ix, iz) = (wo.dot(x), cos_o);
    let length_sq = ix * ix + iz * iz;
    let rx = (length_sq - tau * tau).max(0.0).sqrt();
    let bent = (x * (ix + rx) + ng * (iz + tau)).normalize_or_zero();
    if bent == Vec3::ZERO || !bent.is_finite() {
        ng
    } else {
        bent
    }
}

/// The material's normal-mapped shading normal at `at` and the tangent of its frame, bent so
/// that it reflects `si.wo` above the geometric surface; `None` when the material has no
/// normal map or the mesh no tangents.
///
/// `at.si.ns` must be the interpolated vertex normal (or `ng`) on the incoming side; the map
/// is applied in the front face's frame and negated for a back face, as glTF reverses
/// back-face normals.
#[inline]
pub fn at_hit(
    textures: &crate::texture::TextureEvaluator<'_>,
    at: &crate::texture::TexturePoint<'_>,
    material: &super::ShadingMaterial,
) -> Option<(Vec3, Vec3)> {
    let normal = material.normal_texture.as_ref()?;
    let si = at.si;
    let tangent = si.tangent_to_world(si.interpolate(at.mesh.tangents.as_deref()?)?);
    let side = if si.front_face { 1.0 } else { -1.0 };
    let texel = textures.value(at, &normal.texture).truncate();
    let (ns, t) = perturbed_normal(texel, normal.scale, side * si.ns, tangent)?;
    Some((keep_reflection_above(side * ns, si.ng, si.wo), side * t))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic spread of unit vectors (Fibonacci sphere).
    fn directions(n: usize) -> Vec<Vec3> {
        (0..n)
            .map(|i| {
                let z = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
                let phi = i as f32 * 2.399_963;
                let r = (1.0 - z * z).max(0.0).sqrt();
                Vec3::new(r * phi.cos(), r * phi.sin(), z)
            })
            .collect()
    }

    #[test]
    fn the_flat_texel_leaves_the_normal_alone() {
        let n = Vec3::new(0.3, 0.4, 0.5).normalize();
        let tangent = n.any_orthonormal_vector().extend(1.0);
        let (ns, _) = perturbed_normal(Vec3::new(0.5, 0.5, 1.0), 1.0, n, tangent).unwrap();
        assert!((ns - n).length() < 1e-6, "{ns} vs {n}");
        // Any scale: x and y are zero.
        let (ns, _) = perturbed_normal(Vec3::new(0.5, 0.5, 1.0), 7.0, n, tangent).unwrap();
        assert!((ns - n).length() < 1e-6);
    }

    #[test]
    fn red_tilts_toward_the_tangent_and_green_toward_the_bitangent() {
        let n = Vec3::Z;
        // 45° toward +x: m = (1, 0, 1)/√2, texel = (m + 1)/2.
        let m = Vec3::new(1.0, 0.0, 1.0).normalize();
        let texel = (m + Vec3::ONE) * 0.5;
        let (ns, t) = perturbed_normal(texel, 1.0, n, Vec4::new(1.0, 0.0, 0.0, 1.0)).unwrap();
        assert!((ns - m).length() < 1e-6 && (t - Vec3::X).length() < 1e-6);
        // Green with w = +1 tilts toward n × t = +y; with w = −1 toward −y.
        let m = Vec3::new(0.0, 1.0, 1.0).normalize();
        let texel = (m + Vec3::ONE) * 0.5;
        let (up, _) = perturbed_normal(texel, 1.0, n, Vec4::new(1.0, 0.0, 0.0, 1.0)).unwrap();
        let (down, _) = perturbed_normal(texel, 1.0, n, Vec4::new(1.0, 0.0, 0.0, -1.0)).unwrap();
        assert!((up - m).length() < 1e-6, "{up}");
        assert!((down - Vec3::new(0.0, -m.y, m.z)).length() < 1e-6, "{down}");
    }

    #[test]
    fn scale_multiplies_x_and_y_before_normalising() {
        let texel = Vec3::new(1.0, 0.5, 0.5 + 0.5 * 0.5); // (1, 0, 0.5)
        let m = decode(texel, 0.5).unwrap();
        let want = Vec3::new(0.5, 0.0, 0.5).normalize();
        assert!((m - want).length() < 1e-6, "{m}");
        assert_eq!(decode(Vec3::splat(0.5), 1.0), None);
        assert_eq!(decode(Vec3::new(f32::NAN, 0.5, 1.0), 1.0), None);
    }

    #[test]
    fn a_tangent_along_the_normal_gives_no_frame() {
        assert_eq!(tangent_frame(Vec3::Z, Vec4::new(0.0, 0.0, 2.0, 1.0)), None);
        assert_eq!(tangent_frame(Vec3::Z, Vec4::ZERO), None);
        // A tangent off the plane is projected onto it.
        let (t, b) = tangent_frame(Vec3::Z, Vec4::new(1.0, 0.0, 1.0, 1.0)).unwrap();
        assert!((t - Vec3::X).length() < 1e-6 && (b - Vec3::Y).length() < 1e-6);
    }

    /// Over many normals, geometric normals and view directions: the result is unit, faces
    /// wo, reflects wo at least τ above the surface (up to rounding), and is the input
    /// whenever the input already did all of that.
    #[test]
    fn bent_normals_reflect_above_the_floor_and_valid_ones_are_kept() {
        let dirs = directions(300);
        let mut bent = 0;
        for (k, &ng) in dirs.iter().enumerate().step_by(37) {
            for &wo in dirs.iter().filter(|w| w.dot(ng) > 1e-3) {
                for &ns in dirs.iter().skip(k % 5).step_by(5) {
                    let out = keep_reflection_above(ns, ng, wo);
                    let tau = reflection_floor(wo.dot(ng));
                    assert!((out.length() - 1.0).abs() < 1e-4, "{out}");
                    assert!(out.dot(wo) > 0.0, "ns {ns} ng {ng} wo {wo} → {out}");
                    let r = 2.0 * out.dot(wo) * out - wo;
                    assert!(
                        r.dot(ng) >= tau - 2e-4,
                        "reflection height {} < τ {tau} (ns {ns} ng {ng} wo {wo} → {out})",
                        r.dot(ng)
                    );
                    let valid = ns.dot(wo) > 0.0 && (2.0 * ns.dot(wo) * ns - wo).dot(ng) >= tau;
                    if valid {
                        assert_eq!(out, ns);
                    } else {
                        bent += 1;
                        // The bent normal stays in the plane of ns and ng.
                        let plane = ns.cross(ng);
                        if plane.length() > 1e-3 {
                            assert!(out.dot(plane.normalize()).abs() < 1e-3);
                        }
                    }
                }
            }
        }
        assert!(bent > 1000, "the test must exercise bending ({bent} cases)");
    }

    #[test]
    fn degenerate_inputs_fall_back_to_the_geometric_normal() {
        let ng = Vec3::Z;
        let wo = Vec3::new(0.6, 0.0, 0.8);
        assert_eq!(keep_reflection_above(-Vec3::Z, ng, wo), ng);
        // A grazing view and a normal tilted away from it.
        let wo = Vec3::new(-0.999, 0.0, (1.0f32 - 0.998).sqrt()).normalize();
        let ns = Vec3::new(0.9, 0.0, 0.436).normalize();
        let out = keep_reflection_above(ns, ng, wo);
        assert!(out.is_finite() && out.dot(wo) > 0.0);
    }
}
