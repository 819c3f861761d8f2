//! KHR_materials_pbrSpecularGlossiness (archived, superseded by KHR_materials_specular),
//! converted at load to the model glint renders: glTF's metallic-roughness BRDF with
//! KHR_materials_ior and KHR_materials_specular.
//!
//! | specular-glossiness | becomes |
//! |---|---|
//! | `diffuseFactor`, `diffuseTexture` (sRGB RGB, linear A) | base colour factor and texture (α included) |
//! | `specularFactor` (F0, linear RGB) | `specularColorFactor`, with `ior = 0` so that `f0 = min(1 · specularColor, 1)` is the F0 itself |
//! | `glossinessFactor` | roughness `1 − glossiness` |
//! | `specularGlossinessTexture` RGB (sRGB) and A (linear) | multiply the specular colour, and the glossiness: roughness `1 − glossiness · A` at each hit |
//! | — | metallic 0, `specular = 1` (so f90 = 1) |
//!
//! `ior = 0` is KHR_materials_ior's own compatibility value for this workflow. A metal written
//! as specular-glossiness (black diffuse, F0 = its colour) then has the Fresnel of the
//! metallic-roughness metal of that base colour, `F0 + (1 − F0)(1 − cos)⁵`. The extension's
//! `c_diff = diffuse · (1 − max F0)` is the energy the specular lobe takes from the diffuse;
//! the model glint converts to already weights its diffuse by what the specular lobe does not
//! reflect (`1 − F`, or `1 − E_spec` compensated), so the diffuse colour is taken as is, as
//! KHR_materials_specular's base colour (the extension's `c_diff` would count that loss twice).
//! A material with both workflows renders the specular-glossiness one, as the extension says.

use super::limits;
use super::normal_texture::TextureSlot;
use super::source::Origin;
use glam::{Vec3, Vec4};

/// A specular-glossiness material's parameters in glint's model (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Converted {
    /// Base colour factor: `diffuseFactor`.
    pub base_color: Vec4,
    /// Roughness: `1 − glossinessFactor`.
    pub roughness: f32,
    /// KHR_materials_specular's specular colour: `specularFactor` (F0, with `ior = 0`).
    pub specular_color: Vec3,
    /// The base colour texture: `diffuseTexture`.
    pub diffuse_texture: Option<TextureSlot>,
    /// `specularGlossinessTexture`.
    pub specular_glossiness_texture: Option<TextureSlot>,
}

/// The ior that makes KHR_materials_specular's `f0 = min(f0(ior) · specularColor, 1)` equal
/// the specular colour: KHR_materials_ior's compatibility value 0, for which `f0(ior) = 1`.
pub const IOR: f32 = 0.0;

/// Reads `extension` of the material `label` names, clamping its factors to the ranges the
/// extension gives them ([0, 1]) with the usual warning.
pub fn read(
    extension: &::gltf::material::PbrSpecularGlossiness<'_>,
    label: &str,
    origin: Origin<'_>,
    warnings: &mut Vec<String>,
) -> Converted {
    let mut unit = |value: f32, name: &str| {
        limits::clamp_factor(
            value,
            0.0,
            1.0,
            &format!("{label}: KHR_materials_pbrSpecularGlossiness.{name}"),
            origin,
            warnings,
        )
    };
    let d = extension.diffuse_factor();
    let base_color = Vec4::new(
        unit(d[0], "diffuseFactor[0]"),
        unit(d[1], "diffuseFactor[1]"),
        unit(d[2], "diffuseFactor[2]"),
        unit(d[3], "diffuseFactor[3]"),
    );
    let s = extension.specular_factor();
    let specular_color = Vec3::new(
        unit(s[0], "specularFactor[0]"),
        unit(s[1], "specularFactor[1]"),
        unit(s[2], "specularFactor[2]"),
    );
    let glossiness = unit(extension.glossiness_factor(), "glossinessFactor");
    Converted {
        base_color,
        roughness: 1.0 - glossiness,
        specular_color,
        diffuse_texture: extension.diffuse_texture().map(Into::into),
        specular_glossiness_texture: extension.specular_glossiness_texture().map(Into::into),
    }
}
