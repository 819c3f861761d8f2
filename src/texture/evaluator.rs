//! Texture evaluation at a surface hit: the hit's footprint from its ray differential, the
//! texture coordinates and their derivatives, the texture transform, then a filtered lookup
//! in the texture's MIP chain; and procedural textures, band-limited as the filter asks.
//!
//! The material front end ([`crate::material::at_hit`](fn@crate::material::at_hit)) and alpha testing
//! (`render::visibility`) read every texture through one [`TextureEvaluator`]; nothing else
//! interpolates texture coordinates.

use super::differentials::{
    self, SurfaceDifferentials, attribute_derivative, barycentric_derivatives,
};
use super::image::{TexelGrid, Wrap};
use super::noise::{Band, Domain};
use super::{MipMap, ProceduralTexture, RayDifferential, TextureFilter, UvFootprint};
use crate::geometry::SurfaceInteraction;
use crate::scene::{MagFilter, Mesh, Texture, TextureRef};
use glam::{Vec2, Vec3, Vec4};

/// Reads a scene's textures at hits: its textures, their MIP chains (index-aligned; may be
/// empty when nothing is textured) and the filter.
#[derive(Clone, Copy, Debug)]
pub struct TextureEvaluator<'a> {
    /// The scene's textures (read at the base level when a MIP chain is missing).
    pub textures: &'a [Texture],
    /// MIP chains of `textures`, index-aligned.
    pub mipmaps: &'a [MipMap],
    /// How lookups filter.
    pub filter: TextureFilter,
}

/// A hit's footprint from its ray differential: how the surface point and the barycentrics
/// change from one film sample to the next.
#[derive(Clone, Copy, Debug)]
pub struct Footprint {
    /// ∂p/∂x and ∂p/∂y on the tangent plane.
    pub surface: SurfaceDifferentials,
    /// Barycentric derivatives (∂b₁, ∂b₂) along film x.
    db_dx: Vec2,
    /// Along film y.
    db_dy: Vec2,
}

impl Footprint {
    /// The footprint of `rd` at the hit; `None` if the triangle's vertices are out of range
    /// (the hit is then read unfiltered).
    #[inline]
    pub fn at(mesh: &Mesh, si: &SurfaceInteraction, rd: &RayDifferential) -> Option<Self> {
        let triangle = si.world_triangle(mesh)?;
        let surface = differentials::at_surface(rd, si.p, si.ng);
        Some(Self {
            db_dx: barycentric_derivatives(triangle, surface.dp_dx),
            db_dy: barycentric_derivatives(triangle, surface.dp_dy),
            surface,
        })
    }

    /// The derivatives of a per-vertex attribute along film x and y.
    #[inline]
    pub fn of<T>(&self, values: &[T], si: &SurfaceInteraction) -> Option<(T, T)>
    where
        T: Copy
            + std::ops::Sub<Output = T>
            + std::ops::Mul<f32, Output = T>
            + std::ops::Add<Output = T>,
    {
        Some((
            attribute_derivative(values, si.vertices, self.db_dx)?,
            attribute_derivative(values, si.vertices, self.db_dy)?,
        ))
    }
}

/// Where a texture is read: the mesh, the hit on it and the hit's footprint (`None`: read at
/// the finest level).
#[derive(Clone, Copy)]
pub struct TexturePoint<'a> {
    /// The mesh hit.
    pub mesh: &'a Mesh,
    /// The hit.
    pub si: &'a SurfaceInteraction,
    /// The hit's footprint.
    pub footprint: Option<&'a Footprint>,
}

impl TexturePoint<'_> {
    /// Texture coordinates of set `set` and their footprint (zero without a footprint). A mesh
    /// without the set reads at (0, 0).
    #[inline]
    pub fn texcoords(&self, set: usize) -> (Vec2, UvFootprint) {
        let Some(uvs) = self.mesh.texcoords.get(set).and_then(|s| s.as_deref()) else {
            return (Vec2::ZERO, UvFootprint::default());
        };
        let uv = self.si.interpolate(uvs).unwrap_or(Vec2::ZERO);
        let duv = self
            .footprint
            .and_then(|f| f.of(uvs, self.si))
            .map(|(duv_dx, duv_dy)| UvFootprint { duv_dx, duv_dy })
            .unwrap_or_default();
        (uv, duv)
    }
}

impl TextureEvaluator<'_> {
    /// The texture's value at `at`: interpolated texture coordinates and their footprint, the
    /// texture transform applied to both, then a filtered lookup.
    #[inline]
    pub fn value(&self, at: &TexturePoint<'_>, t: &TextureRef) -> Vec4 {
        let (uv, duv) = at.texcoords(t.texcoord);
        let m = t.transform.matrix2;
        let duv = UvFootprint {
            duv_dx: m * duv.duv_dx,
            duv_dy: m * duv.duv_dy,
        };
        let uv = t.transform.transform_point2(uv);
        match self.mipmaps.get(t.texture) {
            Some(mip) => super::lookup(mip, uv, &duv, self.filter),
            // No MIP chain (a caller built the evaluator without one): the base level.
            None => match self.textures.get(t.texture) {
                Some(texture) => base_level(texture, uv),
                None => Vec4::ONE,
            },
        }
    }

    /// A procedural texture's colour at `at`, band-limited as the filter asks.
    #[inline]
    pub fn procedural(&self, at: &TexturePoint<'_>, procedural: &ProceduralTexture) -> Vec3 {
        let band = match self.filter {
            TextureFilter::Nearest | TextureFilter::Bilinear | TextureFilter::Bicubic => {
                Band::Point
            }
            TextureFilter::Trilinear => Band::Isotropic,
            TextureFilter::Anisotropic => Band::Anisotropic,
        };
        let (p, dx, dy) = match procedural.domain {
            Domain::Uv(set) => {
                let (uv, duv) = at.texcoords(set);
                (
                    uv.extend(0.0),
                    duv.duv_dx.extend(0.0),
                    duv.duv_dy.extend(0.0),
                )
            }
            Domain::World => match at.footprint {
                Some(f) => (at.si.p, f.surface.dp_dx, f.surface.dp_dy),
                None => (at.si.p, Vec3::ZERO, Vec3::ZERO),
            },
        };
        procedural.color(p, dx, dy, band)
    }
}

/// `texture` at `uv` with its sampler's magnification filter on the base level (no
/// footprint). A texture whose texel count disagrees with its size reads white.
fn base_level(texture: &Texture, uv: Vec2) -> Vec4 {
    let Some(grid) = TexelGrid::new(texture.width, texture.height, texture.texels.clone()) else {
        return Vec4::ONE;
    };
    let wrap = Wrap {
        s: texture.wrap_s,
        t: texture.wrap_t,
    };
    match texture.mag_filter {
        MagFilter::Nearest => grid.nearest(uv, wrap),
        MagFilter::Linear => grid.bilinear(uv, wrap),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::WrapMode;

    fn checker() -> Texture {
        Texture {
            name: "2x2".into(),
            width: 2,
            height: 2,
            texels: vec![Vec4::ZERO, Vec4::ONE, Vec4::ONE, Vec4::ZERO].into(),
            wrap_s: WrapMode::Repeat,
            wrap_t: WrapMode::Repeat,
            mag_filter: MagFilter::Linear,
        }
    }

    #[test]
    fn the_base_level_fallback_is_exact_at_texel_centres_and_wraps() {
        let t = checker();
        assert_eq!(base_level(&t, Vec2::new(0.25, 0.25)), Vec4::ZERO);
        assert_eq!(base_level(&t, Vec2::new(0.75, 0.25)), Vec4::ONE);
        assert_eq!(base_level(&t, Vec2::new(0.5, 0.25)), Vec4::splat(0.5));
        assert_eq!(base_level(&t, Vec2::new(1.25, -0.75)), Vec4::ZERO);
        for bad in [
            Vec2::new(f32::NAN, 0.0),
            Vec2::new(0.75, f32::INFINITY),
            Vec2::new(f32::NEG_INFINITY, 0.25),
        ] {
            assert_eq!(base_level(&t, bad), base_level(&t, Vec2::ZERO), "{bad}");
        }
    }
}
