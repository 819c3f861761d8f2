//! The KHR_materials layers a [`Material`](super::Material) may carry, as plain data read at
//! load: clear coat, sheen, transmission, diffuse transmission and volume. Each is `None` on a material without its
//! extension, so such materials shade exactly as before (see
//! [`crate::bsdf::layered`] for the BSDF they become).

use super::{NormalTextureRef, TextureRef};
use glam::Vec3;

/// KHR_materials_clearcoat.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clearcoat {
    /// `clearcoatFactor` in [0, 1].
    pub factor: f32,
    /// `clearcoatRoughnessFactor` in [0, 1] (perceptual; α = roughness²).
    pub roughness: f32,
    /// `clearcoatTexture` (linear): its red channel multiplies `factor`.
    pub texture: Option<TextureRef>,
    /// `clearcoatRoughnessTexture` (linear): its green channel multiplies `roughness`.
    pub roughness_texture: Option<TextureRef>,
    /// `clearcoatNormalTexture` with its `scale`: the coat's own shading normal, in the same
    /// tangent frame as the base's normal map (see [`crate::material::normal_map`]).
    pub normal_texture: Option<NormalTextureRef>,
}

/// KHR_materials_sheen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sheen {
    /// `sheenColorFactor`, linear RGB in [0, 1].
    pub color: Vec3,
    /// `sheenRoughnessFactor` in [0, 1] (perceptual; α = roughness²).
    pub roughness: f32,
    /// `sheenColorTexture` (sRGB in the file, linear here): its RGB multiplies `color`.
    pub color_texture: Option<TextureRef>,
    /// `sheenRoughnessTexture` (linear): its alpha channel multiplies `roughness`.
    pub roughness_texture: Option<TextureRef>,
}

/// KHR_materials_transmission.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transmission {
    /// `transmissionFactor` in [0, 1]: the share of the dielectric base that transmits.
    pub factor: f32,
    /// `transmissionTexture` (linear): its red channel multiplies `factor`.
    pub texture: Option<TextureRef>,
}

/// KHR_materials_diffuse_transmission: a share of the dielectric's diffuse base sent through
/// the surface as a Lambertian lobe into the other hemisphere (see
/// [`crate::bsdf::metallic_roughness`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseTransmission {
    /// `diffuseTransmissionFactor` in [0, 1]: the share of the diffuse base transmitted.
    pub factor: f32,
    /// `diffuseTransmissionTexture` (linear): its alpha channel multiplies `factor`.
    pub texture: Option<TextureRef>,
    /// `diffuseTransmissionColorFactor`, linear RGB in [0, 1]: the transmitted light's colour.
    pub color: Vec3,
    /// `diffuseTransmissionColorTexture` (sRGB in the file, linear here): its RGB multiplies
    /// `color`.
    pub color_texture: Option<TextureRef>,
}

/// KHR_materials_anisotropy: the metal's and the dielectric's specular lobes stretched along
/// a direction in the tangent plane (see [`crate::material::anisotropy`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Anisotropy {
    /// `anisotropyStrength` in [0, 1]: `αt = mix(α, 1, strength²)`, `αb = α`.
    pub strength: f32,
    /// `anisotropyRotation` (radians, counter-clockwise from the tangent toward the
    /// bitangent): rotates the direction.
    pub rotation: f32,
    /// `anisotropyTexture` (linear): red and green are the direction in the tangent frame
    /// (`2c − 1`), blue multiplies `strength`.
    pub texture: Option<TextureRef>,
}

/// KHR_materials_volume: the medium enclosed by the mesh's surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Volume {
    /// `thicknessFactor` (scene units). It only tells rasterisers how far light travels
    /// inside; a path tracer measures the real distance, so glint keeps it for reference and
    /// uses it only to decide that the surface is not thin-walled (thickness 0 means thin).
    pub thickness: f32,
    /// `attenuationColor`, linear RGB in [0, 1]: the colour white light becomes after
    /// `attenuation_distance`.
    pub attenuation_color: Vec3,
    /// `attenuationDistance` (scene units, > 0; infinite: no attenuation).
    pub attenuation_distance: f32,
}

/// Whether any of a material's layers reads a texture (the scene then needs texture lookups
/// at hits, see [`crate::scene::features`]).
pub fn any_texture(
    clearcoat: Option<&Clearcoat>,
    sheen: Option<&Sheen>,
    transmission: Option<&Transmission>,
    diffuse_transmission: Option<&DiffuseTransmission>,
) -> bool {
    clearcoat.is_some_and(|c| {
        c.texture.is_some() || c.roughness_texture.is_some() || c.normal_texture.is_some()
    }) || sheen.is_some_and(|s| s.color_texture.is_some() || s.roughness_texture.is_some())
        || transmission.is_some_and(|t| t.texture.is_some())
        || diffuse_transmission.is_some_and(|d| d.texture.is_some() || d.color_texture.is_some())
}

impl Volume {
    /// The Beer-Lambert attenuation coefficient `σ = −ln(attenuationColor) / attenuationDistance`
    /// per channel (1/scene unit): white light travelling `d` keeps `exp(−σ d)`, which is
    /// `attenuationColor` at `d = attenuationDistance`. A black channel absorbs everything
    /// (σ = +∞ is kept as a large finite value so that `0 · σ` stays 0).
    pub fn sigma(&self) -> Vec3 {
        let d = self.attenuation_distance;
        if !(d.is_finite() && d > 0.0) {
            return Vec3::ZERO;
        }
        self.attenuation_color.map(|c| {
            let c = c.clamp(0.0, 1.0);
            if c >= 1.0 {
                0.0
            } else if c <= 0.0 {
                f32::MAX.sqrt()
            } else {
                -c.ln() / d
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sigma_gives_the_attenuation_colour_at_the_attenuation_distance() {
        let v = Volume {
            thickness: 1.0,
            attenuation_color: Vec3::new(0.5, 0.9, 1.0),
            attenuation_distance: 2.0,
        };
        let t = (-v.sigma() * 2.0).exp();
        assert!((t - v.attenuation_color).abs().max_element() < 1e-6);
        let none = Volume {
            attenuation_distance: f32::INFINITY,
            ..v
        };
        assert_eq!(none.sigma(), Vec3::ZERO);
    }
}
