//! The average emission of a textured emitter over one triangle, for choosing area lights.
//!
//! An area light's selection probability follows its power `Φ_k = π A_k Y(Le_k)`, where
//! `Le_k` is the emission averaged over triangle `k` ([`super::area`]). For an untextured
//! emitter that is the emissive factor. For a textured one, the texture's average over the
//! whole image would give every triangle the same weight, so triangles mapped onto the dark
//! parts of an emissive texture would be sampled as often as the bright ones: still unbiased,
//! but noisy. Here the average is estimated over the triangle's own uv footprint:
//!
//! ```text
//! Le_k ≈ emissive · (1/N) Σ_j T(uv(b_j)),   N = GRID² barycentric points b_j
//! ```
//!
//! The points are the centres of a `GRID × GRID` stratification of the unit square mapped
//! onto the triangle (area-preserving), and each lookup is prefiltered (trilinear) over a
//! footprint of `1/GRID` of the triangle's uv extent, so together they cover the triangle's
//! texels at a level of detail where a lookup averages its share. The estimate only steers
//! sampling: the integrator evaluates the true emission at the sampled point, and a triangle
//! estimated at 0 is never chosen by light sampling but is still found by BSDF sampling,
//! whose MIS weight is then 1 — so the estimator stays unbiased whatever the estimate.

use crate::sampling::warp::uniform_triangle;
use crate::scene::{Mesh, TextureRef};
use crate::texture::MipMap;
use crate::texture::filter::{TextureFilter, UvFootprint, lookup};
use glam::{Vec2, Vec3};

/// Strata per axis of the unit square mapped onto the triangle.
pub const GRID: u32 = 4;

/// The mean of `texture` (its RGB) over triangle `triangle` of `mesh`, or the texture's
/// mean over the whole image when the mesh lacks the texture's uv set (the shading then
/// reads uv (0, 0) everywhere, but the whole-image mean is the better guess for a file
/// that is inconsistent anyway). `None` when the triangle index is out of range.
pub fn triangle_mean(
    mesh: &Mesh,
    triangle: usize,
    texture: &TextureRef,
    mip: &MipMap,
) -> Option<Vec3> {
    let tri = mesh.indices.get(triangle)?;
    let Some(uvs) = mesh
        .texcoords
        .get(texture.texcoord)
        .and_then(Option::as_ref)
    else {
        return Some(image_mean(mip));
    };
    let corner = |i: u32| {
        uvs.get(i as usize)
            .map(|&uv| texture.transform.transform_point2(uv))
    };
    let (uv0, uv1, uv2) = (corner(tri[0])?, corner(tri[1])?, corner(tri[2])?);
    let (e1, e2) = (uv1 - uv0, uv2 - uv0);
    // Each lookup covers 1/GRID of the triangle's extent along both uv edges.
    let footprint = UvFootprint {
        duv_dx: e1 / GRID as f32,
        duv_dy: e2 / GRID as f32,
    };
    let mut sum = Vec3::ZERO;
    for j in 0..GRID {
        for i in 0..GRID {
            let u = Vec2::new(
                (i as f32 + 0.5) / GRID as f32,
                (j as f32 + 0.5) / GRID as f32,
            );
            let b = uniform_triangle(u);
            let uv = uv0 * b.x + uv1 * b.y + uv2 * b.z;
            sum += lookup(mip, uv, &footprint, TextureFilter::Trilinear).truncate();
        }
    }
    let mean = sum / (GRID * GRID) as f32;
    Some(if mean.is_finite() {
        mean.max(Vec3::ZERO)
    } else {
        Vec3::ZERO
    })
}

/// The mean of the coarsest MIP level (a 1 × 1 box-filtered average of the whole image).
pub fn image_mean(mip: &MipMap) -> Vec3 {
    let top = mip.level(mip.level_count().saturating_sub(1));
    top.nearest(Vec2::splat(0.5), mip.wrap).truncate()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Texture, WrapMode};
    use glam::{Affine2, Vec4};

    /// A 2 × 1 texture, black on the left half and white on the right.
    fn half_white() -> MipMap {
        let texture = Texture {
            name: "half".into(),
            width: 2,
            height: 1,
            texels: vec![Vec4::new(0.0, 0.0, 0.0, 1.0), Vec4::ONE].into(),
            wrap_s: WrapMode::ClampToEdge,
            wrap_t: WrapMode::ClampToEdge,
            mag_filter: Default::default(),
        };
        MipMap::new(&texture)
    }

    fn mesh_with_uvs(uvs: Vec<Vec2>) -> Mesh {
        Mesh {
            positions: vec![Vec3::ZERO; uvs.len()],
            indices: vec![[0, 1, 2], [3, 4, 5]],
            texcoords: [Some(uvs), None],
            ..Mesh::default()
        }
    }

    #[test]
    fn triangles_on_dark_and_bright_halves_get_their_own_means() {
        let mip = half_white();
        // Triangle 0 lies inside the left (black) texel, triangle 1 inside the right one.
        let mesh = mesh_with_uvs(vec![
            Vec2::new(0.05, 0.1),
            Vec2::new(0.45, 0.1),
            Vec2::new(0.05, 0.9),
            Vec2::new(0.55, 0.1),
            Vec2::new(0.95, 0.1),
            Vec2::new(0.55, 0.9),
        ]);
        let texture = TextureRef {
            texture: 0,
            texcoord: 0,
            transform: Affine2::IDENTITY,
        };
        let dark = triangle_mean(&mesh, 0, &texture, &mip).unwrap();
        let bright = triangle_mean(&mesh, 1, &texture, &mip).unwrap();
        assert!(dark.max_element() < 0.2, "dark triangle mean {dark}");
        assert!(bright.min_element() > 0.8, "bright triangle mean {bright}");
        assert!((image_mean(&mip) - Vec3::splat(0.5)).abs().max_element() < 1e-6);
    }

    #[test]
    fn missing_uv_set_falls_back_to_the_image_mean_and_bad_indices_to_none() {
        let mip = half_white();
        let mesh = mesh_with_uvs(vec![Vec2::ZERO; 6]);
        let second_set = TextureRef {
            texture: 0,
            texcoord: 1,
            transform: Affine2::IDENTITY,
        };
        let mean = triangle_mean(&mesh, 0, &second_set, &mip).unwrap();
        assert!((mean - Vec3::splat(0.5)).abs().max_element() < 1e-6);
        assert!(triangle_mean(&mesh, 2, &second_set, &mip).is_none());
    }
}
