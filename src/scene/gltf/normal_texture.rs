//! A material's `normalTexture` (with `scale` and KHR_texture_transform) → a
//! [`NormalTextureRef`], and [`TextureSlot`], the one description of "which texture, which
//! texture coordinates, which transform" that every texture channel goes through.
//!
//! The gltf crate gives a `textureInfo` ([`::gltf::texture::Info`]) for most channels but a
//! separate type for `normalTextureInfo`, without an accessor for its KHR_texture_transform;
//! both become a [`TextureSlot`] here, so the material loader requests every texture the same
//! way.

use super::source::Origin;
use crate::scene::texture_decode::ColorSpace;
use crate::scene::{NormalTextureRef, TextureRef};

/// KHR_texture_transform's values as the file gives them (checked by the loader).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RawTransform {
    /// `offset`.
    pub offset: [f32; 2],
    /// `rotation`, radians.
    pub rotation: f32,
    /// `scale`.
    pub scale: [f32; 2],
    /// `texCoord`, which overrides the texture info's own.
    pub tex_coord: Option<u32>,
}

/// One texture reference of a material, whatever glTF type it came in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureSlot {
    /// Index of the glTF texture.
    pub texture: usize,
    /// The texture info's `texCoord`.
    pub tex_coord: u32,
    /// Its KHR_texture_transform, if any.
    pub transform: Option<RawTransform>,
}

impl From<::gltf::texture::Info<'_>> for TextureSlot {
    fn from(info: ::gltf::texture::Info<'_>) -> Self {
        Self {
            texture: info.texture().index(),
            tex_coord: info.tex_coord(),
            transform: info.texture_transform().map(|t| RawTransform {
                offset: t.offset(),
                rotation: t.rotation(),
                scale: t.scale(),
                tex_coord: t.tex_coord(),
            }),
        }
    }
}

/// A KHR_texture_transform object kept as raw JSON (the gltf crate parses it only on core
/// textureInfos), parsed with the crate's own schema; `None` when absent or malformed (the
/// crate ignores a malformed one on core textures too).
pub(super) fn raw_transform(value: Option<&serde_json::Value>) -> Option<RawTransform> {
    let t = serde_json::from_value::<::gltf::json::extensions::texture::TextureTransform>(
        value?.clone(),
    )
    .ok()?;
    Some(RawTransform {
        offset: t.offset.0,
        rotation: t.rotation.0,
        scale: t.scale.0,
        tex_coord: t.tex_coord,
    })
}

impl From<::gltf::material::NormalTexture<'_>> for TextureSlot {
    fn from(normal: ::gltf::material::NormalTexture<'_>) -> Self {
        // The crate keeps this extension of a normalTextureInfo as raw JSON; it has the same
        // schema as on any textureInfo. A malformed one is ignored like a missing one (the
        // crate does the same for textureInfo).
        let transform = raw_transform(normal.extension_value("KHR_texture_transform"));
        Self {
            texture: normal.texture().index(),
            tex_coord: normal.tex_coord(),
            transform,
        }
    }
}

/// The material's normal map, requested through the loader's `request` (which dedups and
/// decodes textures; normal maps are decoded linearly). A non-finite `scale` is replaced by
/// glTF's default 1, with a warning.
pub fn read<R>(
    material: &::gltf::Material<'_>,
    request: &mut R,
    label: &str,
    origin: Origin<'_>,
    warnings: &mut Vec<String>,
) -> Option<NormalTextureRef>
where
    R: FnMut(Option<TextureSlot>, ColorSpace, &str, &str) -> Option<TextureRef>,
{
    let normal = material.normal_texture()?;
    let mut scale = normal.scale();
    if !scale.is_finite() {
        warnings.push(format!(
            "{}: {label}: normalTexture.scale is {scale}, not a finite number; using 1",
            origin.file.display()
        ));
        scale = 1.0;
    }
    let texture = request(
        Some(TextureSlot::from(normal)),
        ColorSpace::Linear,
        "normal",
        label,
    )?;
    Some(NormalTextureRef { texture, scale })
}

/// Generates MikkTSpace tangents for `mesh` when its material has a normal map and the file
/// supplied no TANGENT (only then: meshes without normal maps get no tangent frames). A mesh
/// that cannot have them (no texture coordinates for the normal map) keeps none, with a
/// warning; its normal map is then not applied.
pub fn ensure_tangents(
    mesh: &mut crate::scene::Mesh,
    materials: &[crate::scene::Material],
    origin: Origin<'_>,
    warnings: &mut Vec<String>,
) {
    // The base's normal map, else the clear coat's (both share the mesh's tangent frame),
    // else the anisotropy's texture set (TEXCOORD_0 without a texture): KHR_materials_anisotropy
    // directions live in the same frame.
    let Some(texcoord) = materials.get(mesh.material).and_then(|m| {
        m.normal_texture
            .or(m.clearcoat.and_then(|c| c.normal_texture))
            .map(|n| n.texture.texcoord)
            .or(m.anisotropy.map(|a| a.texture.map_or(0, |t| t.texcoord)))
    }) else {
        return;
    };
    if mesh.tangents.is_some() {
        return;
    }
    if let Err(err) = crate::scene::tangents::generate(mesh, texcoord) {
        warnings.push(format!("{}: {}: {err}", origin.file.display(), mesh.name));
    }
}
