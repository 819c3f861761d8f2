//! OpenEXR output: linear radiance as 32-bit floats, one part, ZIP-compressed scan lines.
//!
//! Channels: `R`, `G`, `B` (radiance, W/(m²·sr)), plus for each selected AOV
//! `albedo.R/G/B`, `normal.X/Y/Z` (world space) and `depth.Z` (scene units), and for a denoised
//! render the radiance before denoising as `noisy.R/G/B` (`R`, `G`, `B` are then denoised), named with the
//! layer-prefix convention OpenEXR readers group into layers; `A`, the coverage (the
//! filter-weighted fraction of camera samples that hit the scene: with the environment
//! hidden, `--env-hidden`, the colour is premultiplied by it, as OpenEXR's compositing
//! convention expects; with it visible, uncovered samples carry the environment instead);
//! the ID AOVs ([`crate::render::ids`]) as 32-bit unsigned integers `instance_id` and
//! `material_id`, and the coverage layers as `coverage.id0` … `coverage.id3` (uint32) with
//! `coverage.fraction0` … `coverage.fraction3` (float); `samples` (uint32), each pixel's sample
//! count, when adaptive sampling ran; the geometric ground truth
//! ([`crate::render::ground_truth`]) as floats `z`, `position.X/Y/Z`, `uv.U/V`, `flow.X/Y` and
//! `flow_backward.X/Y`, NaN where invalid. Exposure is not applied.

use super::{OutputError, write_atomically};
use crate::render::ids::COVERAGE_LAYERS;
use crate::render::{Aovs, Image};
use exr::meta::attribute::{AttributeValue, Text};
use exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, Layer, LayerAttributes, SmallVec, WritableImage,
};
use glam::{Vec2, Vec3};

/// Writes `image` and the AOVs present in `aovs` to `path`, atomically.
pub fn write_exr(
    path: &std::path::Path,
    image: &Image<Vec3>,
    aovs: &Aovs,
) -> Result<(), OutputError> {
    write_exr_annotated(path, image, aovs, &[])
}

/// [`write_exr`] with text attributes in the header, `(name, value)`: `glint render` names the
/// metallic-roughness model that rendered as `glint.brdf` (`compensated` or `spec`). Names and
/// values must be ASCII; others are left out.
pub fn write_exr_annotated(
    path: &std::path::Path,
    image: &Image<Vec3>,
    aovs: &Aovs,
    attributes: &[(&str, &str)],
) -> Result<(), OutputError> {
    write_exr_layers(path, image, aovs, &[], attributes)
}

/// [`write_exr_annotated`] with further RGB layers, `(name, image)`, written as `name.R`,
/// `name.G`, `name.B` (a denoised render keeps its noisy radiance as the layer `noisy`).
pub fn write_exr_layers(
    path: &std::path::Path,
    image: &Image<Vec3>,
    aovs: &Aovs,
    layers: &[(&str, &Image<Vec3>)],
    attributes: &[(&str, &str)],
) -> Result<(), OutputError> {
    let encode_error = |message: String| OutputError::Encode {
        path: path.to_path_buf(),
        format: "EXR",
        message,
    };
    let pixel_count = image.width as usize * image.height as usize;
    let mut channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::new();
    let mut add_vec3 = |names: [&str; 3], source: &Image<Vec3>| -> Result<(), OutputError> {
        if source.pixels.len() != pixel_count {
            return Err(encode_error(format!(
                "channel {} has {} pixels, expected {pixel_count}",
                names[0],
                source.pixels.len()
            )));
        }
        for (axis, name) in names.iter().enumerate() {
            let samples = source.pixels.iter().map(|p| p[axis]).collect();
            channels.push(AnyChannel::new(*name, FlatSamples::F32(samples)));
        }
        Ok(())
    };
    add_vec3(["R", "G", "B"], image)?;
    for (name, layer) in layers {
        let names = ["R", "G", "B"].map(|c| format!("{name}.{c}"));
        add_vec3([&names[0], &names[1], &names[2]], layer)?;
    }
    if let Some(albedo) = &aovs.albedo {
        add_vec3(["albedo.R", "albedo.G", "albedo.B"], albedo)?;
    }
    if let Some(normal) = &aovs.normal {
        add_vec3(["normal.X", "normal.Y", "normal.Z"], normal)?;
    }
    if let Some(depth) = &aovs.depth {
        if depth.pixels.len() != pixel_count {
            return Err(encode_error("depth AOV has the wrong size".into()));
        }
        channels.push(AnyChannel::new(
            "depth.Z",
            FlatSamples::F32(depth.pixels.clone()),
        ));
    }
    if let Some(alpha) = &aovs.alpha {
        if alpha.pixels.len() != pixel_count {
            return Err(encode_error("alpha has the wrong size".into()));
        }
        channels.push(AnyChannel::new("A", FlatSamples::F32(alpha.pixels.clone())));
    }
    let mut add_f32 = |name: &str, pixels: Vec<f32>| -> Result<(), OutputError> {
        if pixels.len() != pixel_count {
            return Err(encode_error(format!("channel {name} has the wrong size")));
        }
        channels.push(AnyChannel::new(name, FlatSamples::F32(pixels)));
        Ok(())
    };
    if let Some(z) = &aovs.z {
        add_f32("z", z.pixels.clone())?;
    }
    if let Some(position) = &aovs.position {
        for (axis, name) in ["position.X", "position.Y", "position.Z"]
            .iter()
            .enumerate()
        {
            add_f32(name, position.pixels.iter().map(|p| p[axis]).collect())?;
        }
    }
    let pairs: [(&Option<Image<Vec2>>, [&str; 2]); 3] = [
        (&aovs.uv, ["uv.U", "uv.V"]),
        (&aovs.flow, ["flow.X", "flow.Y"]),
        (&aovs.flow_backward, ["flow_backward.X", "flow_backward.Y"]),
    ];
    for (image, names) in pairs {
        if let Some(image) = image {
            for (axis, name) in names.iter().enumerate() {
                add_f32(name, image.pixels.iter().map(|p| p[axis]).collect())?;
            }
        }
    }
    let mut add_u32 = |name: String, pixels: Vec<u32>| -> Result<(), OutputError> {
        if pixels.len() != pixel_count {
            return Err(encode_error(format!("{name} AOV has the wrong size")));
        }
        channels.push(AnyChannel::new(name.as_str(), FlatSamples::U32(pixels)));
        Ok(())
    };
    if let Some(ids) = &aovs.instance_id {
        add_u32("instance_id".into(), ids.pixels.clone())?;
    }
    if let Some(ids) = &aovs.material_id {
        add_u32("material_id".into(), ids.pixels.clone())?;
    }
    if let Some(samples) = &aovs.samples {
        add_u32("samples".into(), samples.pixels.clone())?;
    }
    if let Some(coverage) = &aovs.coverage {
        for layer in 0..COVERAGE_LAYERS {
            let ids = coverage.ids.pixels.iter().map(|p| p[layer]).collect();
            add_u32(format!("coverage.id{layer}"), ids)?;
        }
        for layer in 0..COVERAGE_LAYERS {
            let fractions: Vec<f32> = coverage.fractions.pixels.iter().map(|p| p[layer]).collect();
            if fractions.len() != pixel_count {
                return Err(encode_error("coverage AOV has the wrong size".into()));
            }
            channels.push(AnyChannel::new(
                format!("coverage.fraction{layer}").as_str(),
                FlatSamples::F32(fractions),
            ));
        }
    }
    let mut layer_attributes = LayerAttributes::default();
    for (name, value) in attributes {
        if let (Some(name), Some(value)) = (Text::new_or_none(name), Text::new_or_none(value)) {
            layer_attributes
                .other
                .insert(name, AttributeValue::Text(value));
        }
    }
    let layer = Layer::new(
        (image.width as usize, image.height as usize),
        layer_attributes,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels),
    );
    let exr_image = exr::image::Image::from_layer(layer);
    write_atomically(path, |writer| {
        exr_image
            .write()
            .to_buffered(writer)
            .map_err(|e| encode_error(e.to_string()))
    })
}
