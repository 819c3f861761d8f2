//! KHR_materials_clearcoat, _sheen, _transmission and _volume → the layer fields of a
//! [`Material`](crate::scene::Material).
//!
//! Factors are read from the material's extension objects and clamped to their ranges (with
//! the usual clamping warning). Textures of these extensions are not applied yet: each
//! material with one gets one warning naming the texture, and the factor alone is used.
//! Absent or empty extensions leave the fields `None`, so materials without them are
//! untouched.

use super::limits;
use super::source::Origin;
use crate::scene::layers::{Clearcoat, Sheen, Transmission, Volume};
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
    /// KHR_materials_volume.
    pub volume: Option<Volume>,
}

/// Reads the layer extensions of `material` (`label` names it in warnings).
pub fn read(
    material: &::gltf::Material<'_>,
    label: &str,
    origin: Origin<'_>,
    warnings: &mut Vec<String>,
) -> Layers {
    let mut reader = Reader {
        label,
        origin,
        warnings,
    };
    let mut layers = Layers::default();
    if let Some(ext) = material.extension_value("KHR_materials_clearcoat") {
        let ext_name = "KHR_materials_clearcoat";
        reader.unapplied_textures(
            ext,
            ext_name,
            &[
                "clearcoatTexture",
                "clearcoatRoughnessTexture",
                "clearcoatNormalTexture",
            ],
        );
        let factor = reader.number(ext, ext_name, "clearcoatFactor", 0.0, 0.0, 1.0);
        let roughness = reader.number(ext, ext_name, "clearcoatRoughnessFactor", 0.0, 0.0, 1.0);
        layers.clearcoat = (factor > 0.0).then_some(Clearcoat { factor, roughness });
    }
    if let Some(ext) = material.extension_value("KHR_materials_sheen") {
        let ext_name = "KHR_materials_sheen";
        reader.unapplied_textures(
            ext,
            ext_name,
            &["sheenColorTexture", "sheenRoughnessTexture"],
        );
        let color = reader.color(ext, ext_name, "sheenColorFactor", Vec3::ZERO);
        let roughness = reader.number(ext, ext_name, "sheenRoughnessFactor", 0.0, 0.0, 1.0);
        layers.sheen = (color != Vec3::ZERO).then_some(Sheen { color, roughness });
    }
    if let Some(ext) = material.extension_value("KHR_materials_transmission") {
        let ext_name = "KHR_materials_transmission";
        reader.unapplied_textures(ext, ext_name, &["transmissionTexture"]);
        let factor = reader.number(ext, ext_name, "transmissionFactor", 0.0, 0.0, 1.0);
        layers.transmission = (factor > 0.0).then_some(Transmission { factor });
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

    /// One warning naming the textures of `fields` the extension object has: glint uses
    /// their factors only, for now.
    fn unapplied_textures(&mut self, ext: &Value, ext_name: &str, fields: &[&str]) {
        let present: Vec<&str> = fields
            .iter()
            .copied()
            .filter(|f| ext.get(*f).is_some())
            .collect();
        if present.is_empty() {
            return;
        }
        let coat_normal = if present.contains(&"clearcoatNormalTexture") {
            "; the coat uses the surface's shading normal"
        } else {
            ""
        };
        self.warnings.push(format!(
            "{}: {}: {ext_name}'s {} not yet applied (glint uses the factors alone{coat_normal})",
            self.origin.file.display(),
            self.label,
            match present.as_slice() {
                [one] => format!("{one} is"),
                many => format!("{} are", many.join(", ")),
            }
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::super::source::SUPPORTED_EXTENSIONS;

    #[test]
    fn the_layer_extensions_are_declared_supported() {
        for e in [
            "KHR_materials_clearcoat",
            "KHR_materials_sheen",
            "KHR_materials_transmission",
            "KHR_materials_volume",
        ] {
            assert!(SUPPORTED_EXTENSIONS.contains(&e), "{e}");
        }
    }
}
