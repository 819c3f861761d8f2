//! Partial EXRs: one part of a split render ([`crate::render::partial`]) on disk.
//!
//! Channels (32-bit float): `R`, `G`, `B` and the selected AOVs (`albedo.*`, `normal.*`,
//! `depth.Z`) as *sums* over the part's samples, plus `weight`, the summed sample weight.
//! Layer attributes `glint.spp`, `glint.seed`, `glint.samples` (`START..END`) say which render
//! and which samples the part holds, and `glint.scene` and `glint.fingerprint` what it was
//! rendered from ([`super::fingerprint`]); `glint merge` checks them before adding parts.
//! `glint.kernels` names the ray-query code that rendered the part (`embree 3.13.5 sse4.2`,
//! `embree 3.13.5 native (avx2)`, `bvh`): `glint merge` notes when parts differ in it.
//! `glint.brdf` names the metallic-roughness model (`compensated` or `spec`): `glint merge`
//! refuses parts of different models and writes it into a merged EXR.

use crate::output::fingerprint::SceneTag;
use crate::output::{OutputError, write_atomically};
use crate::render::partial::{PartialImage, parse_sample_range};
use crate::render::{Aovs, Image};
use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Encoding, FlatSamples, Layer, LayerAttributes,
    SmallVec, Text, WritableImage,
};
use glam::Vec3;
use std::path::{Path, PathBuf};

const SPP: &str = "glint.spp";
const SEED: &str = "glint.seed";
const SAMPLES: &str = "glint.samples";
const SCENE: &str = "glint.scene";
const FINGERPRINT: &str = "glint.fingerprint";
const KERNELS: &str = "glint.kernels";
const BRDF: &str = "glint.brdf";

/// Why a partial EXR cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum PartError {
    /// The file is not a readable EXR.
    #[error("cannot read {path}: {message}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The decoder's message.
        message: String,
    },
    /// The EXR is not a glint partial render.
    #[error(
        "{path} is not a partial render ({what}); write parts with glint render \
         --sample-range or --shard and an .exr output"
    )]
    NotPartial {
        /// The file.
        path: PathBuf,
        /// What is missing or wrong.
        what: String,
    },
}

/// Writes `part` to `path` atomically, without a scene tag.
pub fn write_partial_exr(path: &Path, part: &PartialImage) -> Result<(), OutputError> {
    write_partial_exr_tagged(path, part, None)
}

/// Writes `part` to `path` atomically, with the scene it was rendered from.
pub fn write_partial_exr_tagged(
    path: &Path,
    part: &PartialImage,
    tag: Option<&SceneTag>,
) -> Result<(), OutputError> {
    let mut channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::new();
    let mut add3 = |names: [&str; 3], image: &Image<Vec3>| {
        for (axis, name) in names.iter().enumerate() {
            let samples = image.pixels.iter().map(|p| p[axis]).collect();
            channels.push(AnyChannel::new(*name, FlatSamples::F32(samples)));
        }
    };
    add3(["R", "G", "B"], &part.radiance_sum);
    if let Some(albedo) = &part.aov_sums.albedo {
        add3(["albedo.R", "albedo.G", "albedo.B"], albedo);
    }
    if let Some(normal) = &part.aov_sums.normal {
        add3(["normal.X", "normal.Y", "normal.Z"], normal);
    }
    if let Some(alpha) = &part.aov_sums.alpha {
        channels.push(AnyChannel::new("A", FlatSamples::F32(alpha.pixels.clone())));
    }
    if let Some(depth) = &part.aov_sums.depth {
        channels.push(AnyChannel::new(
            "depth.Z",
            FlatSamples::F32(depth.pixels.clone()),
        ));
    }
    channels.push(AnyChannel::new(
        "weight",
        FlatSamples::F32(part.weight.pixels.clone()),
    ));
    let mut attributes = LayerAttributes::default();
    let mut text = |key: &str, value: String| {
        attributes.other.insert(
            Text::from(key),
            AttributeValue::Text(Text::from(value.as_str())),
        );
    };
    text(SPP, part.spp.to_string());
    // Text, not an EXR integer attribute: seeds are 64-bit.
    text(SEED, part.seed.to_string());
    text(
        SAMPLES,
        format!("{}..{}", part.samples.start, part.samples.end),
    );
    if let Some(tag) = tag {
        text(SCENE, tag.scene.clone());
        text(FINGERPRINT, tag.fingerprint.clone());
        if let Some(kernels) = &tag.kernels {
            text(KERNELS, kernels.clone());
        }
        if let Some(brdf) = &tag.brdf {
            text(BRDF, brdf.clone());
        }
    }
    let size = (
        part.radiance_sum.width as usize,
        part.radiance_sum.height as usize,
    );
    let layer = Layer::new(
        size,
        attributes,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels),
    );
    let image = exr::image::Image::from_layer(layer);
    write_atomically(path, |writer| {
        image
            .write()
            .to_buffered(writer)
            .map_err(|e| OutputError::Encode {
                path: path.to_path_buf(),
                format: "EXR",
                message: e.to_string(),
            })
    })
}

/// Reads a partial EXR written by [`write_partial_exr`].
pub fn read_partial_exr(path: &Path) -> Result<PartialImage, PartError> {
    read_partial_exr_tagged(path).map(|(part, _)| part)
}

/// Reads a partial EXR and its scene tag (`None` for parts written without one, e.g. by
/// glint versions before the tag).
pub fn read_partial_exr_tagged(path: &Path) -> Result<(PartialImage, Option<SceneTag>), PartError> {
    use exr::prelude::{ReadChannels, ReadLayers};
    // The header's declared size against the budgets, before any pixel is allocated.
    crate::output::budget::check_exr(
        path,
        crate::render::MAX_PIXELS,
        crate::output::budget::memory_budget(),
    )
    .map_err(|message| PartError::Read {
        path: path.to_path_buf(),
        message,
    })?;
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| PartError::Read {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
    let not_partial = |what: String| PartError::NotPartial {
        path: path.to_path_buf(),
        what,
    };
    let layer = image.layer_data;
    let text = |key: &str| match layer.attributes.other.get(&Text::from(key)) {
        Some(AttributeValue::Text(value)) => Ok(value.to_string()),
        _ => Err(not_partial(format!("no '{key}' attribute"))),
    };
    let spp: u32 = text(SPP)?
        .parse()
        .map_err(|_| not_partial(format!("'{SPP}' is not a count")))?;
    let seed: u64 = text(SEED)?
        .parse()
        .map_err(|_| not_partial(format!("'{SEED}' is not a seed")))?;
    let samples = parse_sample_range(&text(SAMPLES)?)
        .map_err(|e| not_partial(format!("'{SAMPLES}': {e}")))?;
    if samples.end > spp {
        return Err(not_partial(format!(
            "its samples {}..{} exceed its {spp} samples per pixel",
            samples.start, samples.end
        )));
    }
    let tag = match (text(SCENE), text(FINGERPRINT)) {
        (Ok(scene), Ok(fingerprint)) => Some(SceneTag {
            scene,
            fingerprint,
            kernels: text(KERNELS).ok(),
            brdf: text(BRDF).ok(),
        }),
        _ => None,
    };
    let (width, height) = (layer.size.0 as u32, layer.size.1 as u32);
    let channel = |name: &str| -> Option<Vec<f32>> {
        layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name == *name)
            .map(|c| c.sample_data.values_as_f32().collect())
    };
    let image3 = |names: [&str; 3]| -> Option<Image<Vec3>> {
        let (x, y, z) = (channel(names[0])?, channel(names[1])?, channel(names[2])?);
        Some(Image {
            width,
            height,
            pixels: x
                .iter()
                .zip(&y)
                .zip(&z)
                .map(|((&x, &y), &z)| Vec3::new(x, y, z))
                .collect(),
        })
    };
    let radiance_sum =
        image3(["R", "G", "B"]).ok_or_else(|| not_partial("no R, G, B channels".into()))?;
    let weight = channel("weight").ok_or_else(|| not_partial("no 'weight' channel".into()))?;
    check_weights(&weight, samples.len() as u64).map_err(not_partial)?;
    let part = PartialImage {
        spp,
        seed,
        samples,
        radiance_sum,
        aov_sums: Aovs {
            albedo: image3(["albedo.R", "albedo.G", "albedo.B"]),
            normal: image3(["normal.X", "normal.Y", "normal.Z"]),
            depth: channel("depth.Z").map(|pixels| Image {
                width,
                height,
                pixels,
            }),
            alpha: channel("A").map(|pixels| Image {
                width,
                height,
                pixels,
            }),
            ..Aovs::default()
        },
        weight: Image {
            width,
            height,
            pixels: weight,
        },
    };
    Ok((part, tag))
}

/// Refuses weights no render writes: each pixel's summed sample weight is a finite number, 0
/// or at least `f32::MIN_POSITIVE` in size (a subnormal weight would turn the merged mean into
/// infinity), and at most 64 per sample of the part (every filter weighs a sample at most 1
/// per pixel; 64 leaves room).
fn check_weights(weights: &[f32], samples: u64) -> Result<(), String> {
    let largest = samples as f32 * 64.0;
    match weights.iter().position(|&w| {
        !(w.is_finite() && (w == 0.0 || w.abs() >= f32::MIN_POSITIVE) && w.abs() <= largest)
    }) {
        None => Ok(()),
        Some(i) => Err(format!(
            "its 'weight' at pixel {i} is {:e}, not a summed weight of {samples} samples \
             (finite, 0 or normal, at most {largest})",
            weights[i]
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::partial::PartialImage;

    #[test]
    fn round_trips_sums_weights_and_attributes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("part.exr");
        let part = PartialImage {
            spp: 16,
            seed: u64::MAX - 3,
            samples: 4..9,
            radiance_sum: Image {
                width: 3,
                height: 2,
                pixels: (0..6).map(|i| Vec3::new(i as f32, 0.5, 1e-9)).collect(),
            },
            aov_sums: Aovs {
                depth: Some(Image::filled(3, 2, 2.5)),
                ..Aovs::default()
            },
            weight: Image::filled(3, 2, 5.0),
        };
        write_partial_exr(&path, &part).unwrap();
        assert_eq!(
            read_partial_exr_tagged(&path).unwrap(),
            (part.clone(), None)
        );
        let tag = SceneTag {
            scene: "a.glb".into(),
            fingerprint: "0123456789abcdef0123456789abcdef".into(),
            kernels: Some("embree 3.13.5 sse4.2".into()),
            brdf: Some("spec".into()),
        };
        write_partial_exr_tagged(&path, &part, Some(&tag)).unwrap();
        assert_eq!(read_partial_exr_tagged(&path).unwrap(), (part, Some(tag)));
    }

    #[test]
    fn a_plain_exr_is_not_a_part() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("plain.exr");
        let image = Image::filled(2, 2, Vec3::ONE);
        crate::output::write_exr(&path, &image, &Aovs::default()).unwrap();
        let err = read_partial_exr(&path).unwrap_err().to_string();
        assert!(
            err.contains("plain.exr") && err.contains("glint.spp"),
            "{err}"
        );
    }
}
