//! KHR_materials_clearcoat, _sheen, _transmission, _diffuse_transmission, _volume and
//! _anisotropy → the layer fields of a [`Material`](crate::scene::Material).
//!
//! Factors are read from the material's extension objects and clamped to their ranges (with
//! the usual clamping warning). Their textures (`clearcoatTexture` R, `clearcoatRoughnessTexture`
//! G, `sheenColorTexture` RGB, `sheenRoughnessTexture` A, `transmissionTexture` R,
//! `diffuseTransmissionTexture` A, `diffuseTransmissionColorTexture` RGB, sRGB) are
//! requested like the core ones and multiply the factors at each hit
//! (`render::layer_textures`). `clearcoatNormalTexture` (with its `scale`) gives the coat its own shading normal.
//! Absent or empty extensions leave the fields `None`, so materials without them are
//! untouched.

use super::limits;
use super::normal_texture::TextureSlot;
use super::source::Origin;
use crate::scene::layers::{
    Anisotropy, Clearcoat, DiffuseTransmission, Sheen, Transmission, Volume,
};
use crate::scene::texture_decode::ColorSpace;
use crate::scene::{NormalTextureRef, TextureRef};
use ::gltf::json::Value;
use glam::Vec3;

/// The layers of one material.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Layers {
    /// KHR_materials_clearcoat.
    pub clearcoat: Option<Clearcoat>,
    /// KHR_materials_sheen.
    pub sheen: Option<Sheen>,
    /// KHR_materials_transmission.
    pub transmission: Option<Transmission>,
    /// KHR_materials_diffuse_transmission.
    pub diffuse_transmission: Option<DiffuseTransmission>,
    /// KHR_materials_volume.
    pub volume: Option<Volume>,
    /// KHR_materials_anisotropy.
    pub anisotropy: Option<Anisotropy>,
}

/// Reads the layer extensions of `material` (`label` names it in warnings). Their textures
/// go through the loader's `request` (as every material texture does); `texture_count` is the
/// document's number of textures, against which the extension JSON's indices are checked
/// (the gltf crate validates only the core schema's).
pub fn read<R>(
    material: &::gltf::Material<'_>,
    label: &str,
    origin: Origin<'_>,
    warnings: &mut Vec<String>,
    request: &mut R,
    texture_count: usize,
) -> Layers
where
    R: FnMut(Option<TextureSlot>, ColorSpace, &str, &str) -> Option<TextureRef>,
{
    let mut reader = Reader {
        label,
        origin,
        warnings,
    };
    let mut texture = |reader: &mut Reader<'_, '_>,
                       ext: &Value,
                       ext_name: &str,
                       field: &str,
                       space: ColorSpace| {
        let slot = reader.texture_slot(ext, ext_name, field, texture_count)?;
        request(Some(slot), space, &format!("{ext_name}.{field}"), label)
    };
    let mut layers = Layers::default();
    if let Some(ext) = material.extension_value("KHR_materials_clearcoat") {
        let ext_name = "KHR_materials_clearcoat";
        let factor = reader.number(ext, ext_name, "clearcoatFactor", 0.0, 0.0, 1.0);
        let roughness = reader.number(ext, ext_name, "clearcoatRoughnessFactor", 0.0, 0.0, 1.0);
        if factor > 0.0 {
            layers.clearcoat = Some(Clearcoat {
                factor,
                roughness,
                texture: texture(
                    &mut reader,
                    ext,
                    ext_name,
                    "clearcoatTexture",
                    ColorSpace::Linear,
                ),
                roughness_texture: texture(
                    &mut reader,
                    ext,
                    ext_name,
                    "clearcoatRoughnessTexture",
                    ColorSpace::Linear,
                ),
                normal_texture: texture(
                    &mut reader,
                    ext,
                    ext_name,
                    "clearcoatNormalTexture",
                    ColorSpace::Linear,
                )
                .map(|texture| NormalTextureRef {
                    texture,
                    scale: reader.coat_normal_scale(ext),
                }),
            });
        }
    }
    if let Some(ext) = material.extension_value("KHR_materials_sheen") {
        let ext_name = "KHR_materials_sheen";
        let color = reader.color(ext, ext_name, "sheenColorFactor", Vec3::ZERO);
        let roughness = reader.number(ext, ext_name, "sheenRoughnessFactor", 0.0, 0.0, 1.0);
        if color != Vec3::ZERO {
            layers.sheen = Some(Sheen {
                color,
                roughness,
                color_texture: texture(
                    &mut reader,
                    ext,
                    ext_name,
                    "sheenColorTexture",
                    ColorSpace::Srgb,
                ),
                roughness_texture: texture(
                    &mut reader,
                    ext,
                    ext_name,
                    "sheenRoughnessTexture",
                    ColorSpace::Linear,
                ),
            });
        }
    }
    if let Some(ext) = material.extension_value("KHR_materials_transmission") {
        let ext_name = "KHR_materials_transmission";
        let factor = reader.number(ext, ext_name, "transmissionFactor", 0.0, 0.0, 1.0);
        if factor > 0.0 {
            layers.transmission = Some(Transmission {
                factor,
                texture: texture(
                    &mut reader,
                    ext,
                    ext_name,
                    "transmissionTexture",
                    ColorSpace::Linear,
                ),
            });
        }
    }
    if let Some(ext) = material.extension_value("KHR_materials_diffuse_transmission") {
        let ext_name = "KHR_materials_diffuse_transmission";
        let factor = reader.number(ext, ext_name, "diffuseTransmissionFactor", 0.0, 0.0, 1.0);
        let color = reader.color(ext, ext_name, "diffuseTransmissionColorFactor", Vec3::ONE);
        // Factor 0 transmits nothing whatever the texture says (it only multiplies).
        if factor > 0.0 {
            layers.diffuse_transmission = Some(DiffuseTransmission {
                factor,
                texture: texture(
                    &mut reader,
                    ext,
                    ext_name,
                    "diffuseTransmissionTexture",
                    ColorSpace::Linear,
                ),
                color,
                color_texture: texture(
                    &mut reader,
                    ext,
                    ext_name,
                    "diffuseTransmissionColorTexture",
                    ColorSpace::Srgb,
                ),
            });
        }
    }
    if let Some(ext) = material.extension_value("KHR_materials_volume") {
        let ext_name = "KHR_materials_volume";
        // The thickness texture, like the factor, is for rasterisers (see `Volume`).
        let thickness = reader.number(ext, ext_name, "thicknessFactor", 0.0, 0.0, f32::MAX);
        let attenuation_color = reader.color(ext, ext_name, "attenuationColor", Vec3::ONE);
        let attenuation_distance = reader.number(
            ext,
            ext_name,
            "attenuationDistance",
            f32::INFINITY,
            f32::MIN_POSITIVE,
            f32::INFINITY,
        );
        // The spec: thickness 0 makes the material thin-walled (no volume).
        layers.volume = (thickness > 0.0).then_some(Volume {
            thickness,
            attenuation_color,
            attenuation_distance,
        });
    }
    if let Some(ext) = material.extension_value("KHR_materials_anisotropy") {
        let ext_name = "KHR_materials_anisotropy";
        let strength = reader.number(ext, ext_name, "anisotropyStrength", 0.0, 0.0, 1.0);
        let rotation = reader.number(ext, ext_name, "anisotropyRotation", 0.0, f32::MIN, f32::MAX);
        // Strength 0 is isotropic whatever the texture says (it only multiplies).
        if strength > 0.0 {
            layers.anisotropy = Some(Anisotropy {
                strength,
                rotation,
                texture: texture(
                    &mut reader,
                    ext,
                    ext_name,
                    "anisotropyTexture",
                    ColorSpace::Linear,
                ),
            });
        }
    }
    layers
}

/// Reads fields of one material's extension objects, warning about what it cannot use.
struct Reader<'a, 'w> {
    label: &'a str,
    origin: Origin<'a>,
    warnings: &'w mut Vec<String>,
}

impl Reader<'_, '_> {
    /// A number field, `default` when absent; a non-number is warned about and replaced by
    /// `default`; out-of-range values are clamped with a warning.
    fn number(
        &mut self,
        ext: &Value,
        ext_name: &str,
        field: &str,
        default: f32,
        lo: f32,
        hi: f32,
    ) -> f32 {
        let value = match ext.get(field) {
            None => return default,
            Some(v) => v.as_f64(),
        };
        let Some(v) = value else {
            self.warnings.push(format!(
                "{}: {}: {ext_name}.{field} is not a number; using the default {default}",
                self.origin.file.display(),
                self.label
            ));
            return default;
        };
        limits::clamp_factor(
            v as f32,
            lo,
            hi,
            &format!("{}: {ext_name}.{field}", self.label),
            self.origin,
            self.warnings,
        )
    }

    /// An RGB field in [0, 1], `default` when absent or malformed (with a warning).
    fn color(&mut self, ext: &Value, ext_name: &str, field: &str, default: Vec3) -> Vec3 {
        let Some(v) = ext.get(field) else {
            return default;
        };
        let parts: Option<Vec<f64>> = v
            .as_array()
            .filter(|a| a.len() == 3)
            .and_then(|a| a.iter().map(Value::as_f64).collect());
        let Some(parts) = parts else {
            self.warnings.push(format!(
                "{}: {}: {ext_name}.{field} is not an array of three numbers; using the default {default}",
                self.origin.file.display(),
                self.label
            ));
            return default;
        };
        let mut c = [0.0f32; 3];
        for (k, (out, &p)) in c.iter_mut().zip(&parts).enumerate() {
            *out = limits::clamp_factor(
                p as f32,
                0.0,
                1.0,
                &format!("{}: {ext_name}.{field}[{k}]", self.label),
                self.origin,
                self.warnings,
            );
        }
        Vec3::from(c)
    }

    /// The textureInfo object `field` of `ext` as a [`TextureSlot`]: `None` when absent, or
    /// (with a warning) when malformed or naming a texture the file does not have.
    fn texture_slot(
        &mut self,
        ext: &Value,
        ext_name: &str,
        field: &str,
        texture_count: usize,
    ) -> Option<TextureSlot> {
        let info = ext.get(field)?;
        let index = info.get("index").and_then(Value::as_u64);
        let tex_coord = match info.get("texCoord") {
            None => Some(0),
            Some(v) => v.as_u64().and_then(|t| u32::try_from(t).ok()),
        };
        let (Some(index), Some(tex_coord)) = (index, tex_coord) else {
            self.warnings.push(format!(
                "{}: {}: {ext_name}.{field} is not a textureInfo (an object with an integer \
                 \"index\" and optional \"texCoord\"); the texture is ignored and the factor used alone",
                self.origin.file.display(),
                self.label
            ));
            return None;
        };
        let Some(texture) = usize::try_from(index).ok().filter(|&i| i < texture_count) else {
            self.warnings.push(format!(
                "{}: {}: {ext_name}.{field} names texture {index}, but the file has {texture_count}; \
                 the texture is ignored and the factor used alone (fix the index)",
                self.origin.file.display(),
                self.label
            ));
            return None;
        };
        // Same schema as on a core textureInfo; a malformed transform is ignored, as the
        // gltf crate does for core textures.
        let transform = super::normal_texture::raw_transform(
            info.get("extensions")
                .and_then(|e| e.get("KHR_texture_transform")),
        );
        Some(TextureSlot {
            texture,
            tex_coord,
            transform,
        })
    }

    /// `clearcoatNormalTexture.scale`: 1 when absent; a non-finite or non-number one is
    /// replaced by 1 with a warning (as for `normalTexture.scale`).
    fn coat_normal_scale(&mut self, ext: &Value) -> f32 {
        let Some(v) = ext
            .get("clearcoatNormalTexture")
            .and_then(|t| t.get("scale"))
        else {
            return 1.0;
        };
        match v.as_f64().map(|s| s as f32).filter(|s| s.is_finite()) {
            Some(s) => s,
            None => {
                self.warnings.push(format!(
                    "{}: {}: KHR_materials_clearcoat.clearcoatNormalTexture.scale is {v}, not a finite number; using 1",
                    self.origin.file.display(),
                    self.label
                ));
                1.0
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::source::SUPPORTED_EXTENSIONS;
    use super::*;
    use std::path::Path;

    /// The layers of the first material of `json`, with the texture requests it made
    /// (texture index, texCoord, colour space) and the warnings.
    fn read_first(json: &[u8]) -> (Layers, Vec<(usize, u32, ColorSpace)>, Vec<String>) {
        let gltf = ::gltf::Gltf::from_slice(json).expect("valid glTF");
        let options = crate::scene::gltf::LoadOptions::default();
        let origin = Origin {
            file: Path::new("x.gltf"),
            files: crate::scene::gltf::source::Files::None,
            options: &options,
        };
        let mut warnings = Vec::new();
        let mut requests = Vec::new();
        let mut request = |slot: Option<TextureSlot>, space, _: &str, _: &str| {
            let slot = slot?;
            requests.push((slot.texture, slot.tex_coord, space));
            Some(TextureRef {
                texture: slot.texture,
                texcoord: slot.tex_coord as usize,
                transform: glam::Affine2::IDENTITY,
            })
        };
        let material = gltf.document.materials().next().expect("one material");
        let count = gltf.document.textures().len();
        let layers = read(&material, "m", origin, &mut warnings, &mut request, count);
        (layers, requests, warnings)
    }

    const TEXTURES: &str = r#""images": [{"uri": "a.png"}],
        "textures": [{"source": 0}, {"source": 0}, {"source": 0}]"#;

    #[test]
    fn layer_textures_are_requested_in_their_colour_spaces() {
        let json = format!(
            r#"{{"asset": {{"version": "2.0"}}, {TEXTURES},
            "extensionsUsed": ["KHR_materials_clearcoat", "KHR_materials_sheen", "KHR_materials_transmission"],
            "materials": [{{"extensions": {{
                "KHR_materials_clearcoat": {{"clearcoatFactor": 1, "clearcoatTexture": {{"index": 0}},
                    "clearcoatRoughnessTexture": {{"index": 1, "texCoord": 1}},
                "clearcoatNormalTexture": {{"index": 2, "scale": 0.5}}}},
                "KHR_materials_sheen": {{"sheenColorFactor": [1, 1, 1], "sheenColorTexture": {{"index": 2}},
                    "sheenRoughnessTexture": {{"index": 2}}}},
                "KHR_materials_transmission": {{"transmissionFactor": 0.5, "transmissionTexture": {{"index": 1}}}}
            }}}}]}}"#
        );
        let (layers, requests, warnings) = read_first(json.as_bytes());
        assert!(warnings.is_empty(), "{warnings:?}");
        use ColorSpace::{Linear, Srgb};
        assert_eq!(
            requests,
            [
                (0, 0, Linear),
                (1, 1, Linear),
                (2, 0, Linear),
                (2, 0, Srgb),
                (2, 0, Linear),
                (1, 0, Linear)
            ]
        );
        let coat = layers.clearcoat.expect("coat");
        assert_eq!(coat.texture.map(|t| t.texture), Some(0));
        assert_eq!(
            coat.roughness_texture.map(|t| (t.texture, t.texcoord)),
            Some((1, 1))
        );
        let normal = coat.normal_texture.expect("coat normal");
        assert_eq!((normal.texture.texture, normal.scale), (2, 0.5));
        let sheen = layers.sheen.expect("sheen");
        assert_eq!(sheen.color_texture.map(|t| t.texture), Some(2));
        assert_eq!(sheen.roughness_texture.map(|t| t.texture), Some(2));
        let tr = layers.transmission.expect("transmission");
        assert_eq!((tr.factor, tr.texture.map(|t| t.texture)), (0.5, Some(1)));
    }

    #[test]
    fn bad_layer_textures_are_ignored_with_a_warning() {
        let json = format!(
            r#"{{"asset": {{"version": "2.0"}}, {TEXTURES},
            "extensionsUsed": ["KHR_materials_clearcoat"],
            "materials": [{{"extensions": {{"KHR_materials_clearcoat": {{"clearcoatFactor": 1,
                "clearcoatTexture": {{"index": 7}},
                "clearcoatRoughnessTexture": {{"texCoord": 0}},
                "clearcoatNormalTexture": {{"index": 0, "scale": "big"}}}}}}}}]}}"#
        );
        let (layers, requests, warnings) = read_first(json.as_bytes());
        assert_eq!(requests, [(0, 0, ColorSpace::Linear)]);
        let coat = layers.clearcoat.expect("coat");
        assert_eq!((coat.texture, coat.roughness_texture), (None, None));
        assert_eq!(coat.normal_texture.map(|n| n.scale), Some(1.0));
        assert_eq!(warnings.len(), 3, "{warnings:?}");
        assert!(
            warnings
                .iter()
                .any(|w| w.contains("clearcoatTexture names texture 7"))
        );
        assert!(
            warnings
                .iter()
                .any(|w| w.contains("clearcoatRoughnessTexture is not a textureInfo"))
        );
        assert!(
            warnings
                .iter()
                .any(|w| w.contains("clearcoatNormalTexture.scale is"))
        );
    }

    #[test]
    fn anisotropy_is_read_with_its_texture_and_strength_zero_is_none() {
        let json = format!(
            r#"{{"asset": {{"version": "2.0"}}, {TEXTURES},
            "extensionsUsed": ["KHR_materials_anisotropy"],
            "materials": [{{"extensions": {{"KHR_materials_anisotropy": {{
                "anisotropyStrength": 0.6, "anisotropyRotation": 1.57,
                "anisotropyTexture": {{"index": 2, "texCoord": 1}}}}}}}}]}}"#
        );
        let (layers, requests, warnings) = read_first(json.as_bytes());
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(requests, [(2, 1, ColorSpace::Linear)]);
        let a = layers.anisotropy.expect("anisotropy");
        assert_eq!((a.strength, a.rotation), (0.6, 1.57));
        assert_eq!(a.texture.map(|t| (t.texture, t.texcoord)), Some((2, 1)));
        let zero = br#"{"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_anisotropy"],
            "materials": [{"extensions": {"KHR_materials_anisotropy": {"anisotropyRotation": 1}}}]}"#;
        let (layers, _, _) = read_first(zero);
        assert_eq!(layers.anisotropy, None);
        let clamped = br#"{"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_anisotropy"],
            "materials": [{"extensions": {"KHR_materials_anisotropy": {"anisotropyStrength": 3}}}]}"#;
        let (layers, _, warnings) = read_first(clamped);
        assert_eq!(layers.anisotropy.map(|a| a.strength), Some(1.0));
        assert_eq!(warnings.len(), 1, "{warnings:?}");
    }

    #[test]
    fn diffuse_transmission_is_read_with_its_textures_and_factor_zero_is_none() {
        let json = format!(
            r#"{{"asset": {{"version": "2.0"}}, {TEXTURES},
            "extensionsUsed": ["KHR_materials_diffuse_transmission"],
            "materials": [{{"extensions": {{"KHR_materials_diffuse_transmission": {{
                "diffuseTransmissionFactor": 0.25,
                "diffuseTransmissionTexture": {{"index": 1}},
                "diffuseTransmissionColorFactor": [1.0, 0.9, 0.85],
                "diffuseTransmissionColorTexture": {{"index": 2, "texCoord": 1}}}}}}}}]}}"#
        );
        let (layers, requests, warnings) = read_first(json.as_bytes());
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(
            requests,
            [(1, 0, ColorSpace::Linear), (2, 1, ColorSpace::Srgb)]
        );
        let d = layers.diffuse_transmission.expect("diffuse transmission");
        assert_eq!((d.factor, d.color), (0.25, Vec3::new(1.0, 0.9, 0.85)));
        assert_eq!(d.texture.map(|t| t.texture), Some(1));
        assert_eq!(
            d.color_texture.map(|t| (t.texture, t.texcoord)),
            Some((2, 1))
        );
        // Defaults: factor 0 is no extension at all; the colour defaults to white.
        let zero = br#"{"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_diffuse_transmission"],
            "materials": [{"extensions": {"KHR_materials_diffuse_transmission": {"diffuseTransmissionColorFactor": [1, 0, 0]}}}]}"#;
        assert_eq!(read_first(zero).0.diffuse_transmission, None);
        let white = br#"{"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_diffuse_transmission"],
            "materials": [{"extensions": {"KHR_materials_diffuse_transmission": {"diffuseTransmissionFactor": 2}}}]}"#;
        let (layers, _, warnings) = read_first(white);
        let d = layers.diffuse_transmission.expect("clamped to 1");
        assert_eq!((d.factor, d.color), (1.0, Vec3::ONE));
        assert_eq!(warnings.len(), 1, "{warnings:?}");
    }

    #[test]
    fn the_layer_extensions_are_declared_supported() {
        for e in [
            "KHR_materials_clearcoat",
            "KHR_materials_sheen",
            "KHR_materials_transmission",
            "KHR_materials_diffuse_transmission",
            "KHR_materials_volume",
            "KHR_materials_anisotropy",
        ] {
            assert!(SUPPORTED_EXTENSIONS.contains(&e), "{e}");
        }
    }
}
