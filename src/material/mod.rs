//! Materials: glTF's metallic-roughness materials (with their KHR_materials extensions)
//! prepared once per render ([`ShadingMaterial`]) and turned into what shading needs at each
//! hit by one call, [`at_hit`](fn@at_hit) (the surface front end): shading normal, normal map, colours,
//! emission, texture-driven factors, layers and the BSDF ([`SurfaceBsdf`]).
//!
//! A material's base colour ρ is `base colour × vertex colour (COLOR_0) × base colour
//! texture`, all linear RGB; emission is `emissive × emissive texture` (W/(m²·sr)). Back
//! faces of single-sided materials neither emit nor reflect (camera rays cull them). Alpha
//! coverage decides which hits count (`render::visibility`); an unlit material
//! (KHR_materials_unlit) emits ρ and scatters nothing. [`normal_map`] turns a normal
//! texture's texel into the shading normal; [`layers`] holds the KHR_materials layers.

pub mod anisotropy;
pub mod at_hit;
pub mod layers;
pub mod normal_map;
pub mod scattering;

pub use at_hit::{HitQuery, SurfaceAtHit, at_hit, emitted};
pub use scattering::SurfaceBsdf;

use crate::bsdf::BrdfModel;
use crate::scene::{Material, Scene, TextureRef};
use glam::Vec3;

/// A material prepared for shading: the weights and factors each hit needs, computed once.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadingMaterial {
    /// Linear base colour factor (RGB of the glTF factor).
    pub base_color: Vec3,
    /// Base colour texture, if it names an existing texture.
    pub base_color_texture: Option<TextureRef>,
    /// glTF metalness in [0, 1].
    pub metallic: f32,
    /// glTF perceptual roughness in [0, 1].
    pub roughness: f32,
    /// Metallic-roughness texture (B × metallic, G × roughness).
    pub metallic_roughness_texture: Option<TextureRef>,
    /// Dielectric index of refraction (KHR_materials_ior).
    pub ior: f32,
    /// KHR_materials_specular factor and colour.
    pub specular: f32,
    /// See [`ShadingMaterial::specular`].
    pub specular_color: Vec3,
    /// Specular-glossiness texture (RGB × specular colour, A × glossiness; see
    /// [`Material::specular_glossiness_texture`]).
    pub specular_glossiness_texture: Option<TextureRef>,
    /// Emitted radiance factor, W/(m²·sr).
    pub emissive: Vec3,
    /// Emissive texture, if it names an existing texture.
    pub emissive_texture: Option<TextureRef>,
    /// Whether back faces are shaded.
    pub double_sided: bool,
    /// Procedural base colour, multiplied into ρ.
    pub procedural: Option<crate::texture::ProceduralTexture>,
    /// KHR_materials_unlit: emits ρ as radiance, neither reflects nor is lit.
    pub unlit: bool,
    /// Normal map, if it names an existing texture ([`normal_map`]).
    pub normal_texture: Option<crate::scene::NormalTextureRef>,
    /// KHR_materials clear coat, sheen, transmission and volume (`None` without any).
    pub layers: Option<layers::ShadingLayers>,
    /// KHR_materials_anisotropy (`None` without it, or with strength 0).
    pub anisotropy: Option<crate::scene::layers::Anisotropy>,
    /// Energy-compensated or Appendix-B metallic-roughness model (the render's choice).
    pub brdf: BrdfModel,
}

impl ShadingMaterial {
    /// Prepares `material`; texture references to textures the scene lacks are dropped (the
    /// loader reports those; the renderer must not index out of bounds).
    pub fn new(material: &Material, texture_count: usize) -> Self {
        let valid = |t: &Option<TextureRef>| t.filter(|r| r.texture < texture_count);
        if material.anisotropy.is_some() {
            // Its energy table, built once per process before any tile needs it.
            crate::bsdf::anisotropic_albedo::prepare();
        }
        Self {
            base_color: material.base_color.truncate(),
            base_color_texture: valid(&material.base_color_texture),
            metallic: material.metallic,
            roughness: material.roughness,
            metallic_roughness_texture: valid(&material.metallic_roughness_texture),
            ior: material.ior,
            specular: material.specular,
            specular_color: material.specular_color,
            specular_glossiness_texture: valid(&material.specular_glossiness_texture),
            emissive: material.emissive,
            emissive_texture: valid(&material.emissive_texture),
            double_sided: material.double_sided,
            procedural: material.procedural.clone(),
            unlit: material.unlit,
            normal_texture: material
                .normal_texture
                .filter(|n| n.texture.texture < texture_count),
            layers: layers::ShadingLayers::of(material)
                .map(|l| l.with_valid_textures(texture_count)),
            anisotropy: material
                .anisotropy
                .map(|a| crate::scene::layers::Anisotropy {
                    texture: valid(&a.texture),
                    ..a
                }),
            brdf: BrdfModel::default(),
        }
    }

    /// Whether light may pass through the surface (KHR_materials_transmission or
    /// KHR_materials_diffuse_transmission): back faces
    /// are then shaded whatever `doubleSided` says (a ray leaving glass meets them inside).
    #[inline]
    pub fn may_transmit(&self) -> bool {
        self.layers.is_some_and(|l| l.transmits())
    }

    /// Whether the material reads any texture at a hit (then a ray's differential is worth
    /// turning into a footprint).
    #[inline]
    pub fn textured(&self) -> bool {
        self.base_color_texture.is_some()
            || self.metallic_roughness_texture.is_some()
            || self.specular_glossiness_texture.is_some()
            || self.emissive_texture.is_some()
            || self.normal_texture.is_some()
            || self.procedural.is_some()
            || self.layers.is_some_and(|l| l.has_textures())
            || self.anisotropy.is_some_and(|a| a.texture.is_some())
    }

    /// The materials of `scene`, plus glTF's default material at the end for meshes whose
    /// material index is out of range (see [`material_index`]), each under the metallic-roughness
    /// model `brdf`.
    pub fn table(scene: &Scene, brdf: BrdfModel) -> Vec<ShadingMaterial> {
        scene
            .materials
            .iter()
            .chain(std::iter::once(&Material::default()))
            .map(|m| Self {
                brdf,
                ..Self::new(m, scene.textures.len())
            })
            .collect()
    }
}

/// The index into [`ShadingMaterial::table`] for a mesh's material index: itself, or the
/// default material at the end when out of range.
#[inline]
pub fn material_index(mesh_material: usize, table_len: usize) -> usize {
    mesh_material.min(table_len.saturating_sub(1))
}
