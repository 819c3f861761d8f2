//! A material's coverage and shading model: glTF `alphaMode` / `alphaCutoff` and
//! KHR_materials_unlit, read into [`AlphaMode`] and [`Material::unlit`].
//!
//! [`Material::unlit`]: crate::scene::Material::unlit

use super::source::Origin;
use crate::scene::AlphaMode;

/// glTF's `alphaCutoff` when a MASK material gives none.
pub const DEFAULT_ALPHA_CUTOFF: f32 = 0.5;

/// The alpha mode and the unlit flag of one glTF material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// `alphaMode`, with `alphaCutoff` inside MASK.
    pub alpha: AlphaMode,
    /// Whether the material carries KHR_materials_unlit.
    pub unlit: bool,
}

/// Reads `material`'s alpha mode and unlit flag. A MASK cutoff that is not a finite number
/// ≥ 0 (the schema's bound) is replaced, with a warning naming the material: NaN by glTF's
/// default 0.5, a negative one by 0 (which keeps every point, as any negative cutoff would).
pub fn read(
    material: &::gltf::Material<'_>,
    label: &str,
    origin: Origin<'_>,
    warnings: &mut Vec<String>,
) -> Surface {
    let alpha = match material.alpha_mode() {
        ::gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
        ::gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        ::gltf::material::AlphaMode::Mask => {
            let given = material.alpha_cutoff().unwrap_or(DEFAULT_ALPHA_CUTOFF);
            let cutoff = if given.is_nan() {
                DEFAULT_ALPHA_CUTOFF
            } else {
                given.max(0.0)
            };
            if cutoff != given {
                warnings.push(format!(
                    "{}: {label}: alphaCutoff {given} is not a number ≥ 0; using {cutoff} \
                     (fix the material's alphaCutoff)",
                    origin.file.display()
                ));
            }
            AlphaMode::Mask { cutoff }
        }
    };
    // Read from the raw extension map: the extension has no properties, its presence is the
    // whole message.
    let unlit = material.extension_value("KHR_materials_unlit").is_some();
    Surface { alpha, unlit }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn reads_alpha_modes_cutoffs_and_unlit() {
        let json = br#"{
            "asset": {"version": "2.0"},
            "extensionsUsed": ["KHR_materials_unlit"],
            "materials": [
                {"alphaMode": "MASK", "alphaCutoff": 0.25},
                {"alphaMode": "MASK"},
                {"alphaMode": "BLEND", "alphaCutoff": 0.9},
                {"alphaCutoff": 0.3},
                {"extensions": {"KHR_materials_unlit": {}}, "alphaMode": "BLEND"}
            ]
        }"#;
        let gltf = ::gltf::Gltf::from_slice(json).expect("valid glTF");
        let options = crate::scene::gltf::LoadOptions::default();
        let origin = Origin {
            file: Path::new("x.gltf"),
            files: crate::scene::gltf::source::Files::None,
            options: &options,
        };
        let mut warnings = Vec::new();
        let got: Vec<Surface> = gltf
            .document
            .materials()
            .map(|m| read(&m, "m", origin, &mut warnings))
            .collect();
        let surface = |alpha, unlit| Surface { alpha, unlit };
        assert_eq!(
            got,
            [
                surface(AlphaMode::Mask { cutoff: 0.25 }, false),
                surface(
                    AlphaMode::Mask {
                        cutoff: DEFAULT_ALPHA_CUTOFF
                    },
                    false
                ),
                // The cutoff matters in MASK mode only.
                surface(AlphaMode::Blend, false),
                surface(AlphaMode::Opaque, false),
                surface(AlphaMode::Blend, true),
            ]
        );
        assert!(warnings.is_empty(), "{warnings:?}");

        // Below the schema's minimum: kept as 0, with a warning naming the material.
        let json = br#"{"asset": {"version": "2.0"},
            "materials": [{"alphaMode": "MASK", "alphaCutoff": -0.5}]}"#;
        let gltf = ::gltf::Gltf::from_slice(json).expect("parses");
        let material = gltf.document.materials().next().expect("one material");
        let got = read(&material, "material 0", origin, &mut warnings);
        assert_eq!(got.alpha, AlphaMode::Mask { cutoff: 0.0 });
        assert!(
            warnings.len() == 1 && warnings[0].contains("material 0: alphaCutoff -0.5"),
            "{warnings:?}"
        );
    }
}
