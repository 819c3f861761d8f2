//! The default environment of a path-traced scene without lights: the CC0 studio HDRI bundled
//! as `scenes/demo-env.hdr` (256×128, Poly Haven's studio, see `scenes/demo-env-LICENSE.txt`),
//! compiled into glint so that it needs no file at run time. It is what the Khronos viewers,
//! model-viewer and Blender show a file in before it is given lights: a soft studio with a
//! bright window, instead of a flat uniform white (still a flag away: `--background 1,1,1`).

use crate::light::environment::{EnvImage, EnvOptions, EnvironmentError, EnvironmentLight};
use glam::Vec3;
use std::sync::{Arc, OnceLock};

/// The bundled image's bytes (Radiance HDR).
const STUDIO_HDR: &[u8] = include_bytes!("../../scenes/demo-env.hdr");

/// Where the bundled image comes from, for notes.
pub const STUDIO_NAME: &str = "the bundled CC0 studio HDRI (scenes/demo-env.hdr)";

/// The studio environment at strength 1, unrotated; decoded once per process.
pub fn studio_environment() -> Result<Arc<EnvironmentLight>, EnvironmentError> {
    static STUDIO: OnceLock<Arc<EnvironmentLight>> = OnceLock::new();
    if let Some(light) = STUDIO.get() {
        return Ok(Arc::clone(light));
    }
    let light = Arc::new(EnvironmentLight::from_image(
        decode()?,
        &EnvOptions::default(),
    )?);
    Ok(Arc::clone(STUDIO.get_or_init(|| light)))
}

fn decode() -> Result<EnvImage, EnvironmentError> {
    use image::ImageDecoder;
    let decode_error = |e: image::ImageError| EnvironmentError::Decode {
        path: "scenes/demo-env.hdr (bundled)".into(),
        format: "Radiance HDR",
        message: e.to_string(),
    };
    let decoder = image::codecs::hdr::HdrDecoder::new(std::io::Cursor::new(STUDIO_HDR))
        .map_err(decode_error)?;
    let (width, height) = decoder.dimensions();
    let rgb = image::DynamicImage::from_decoder(decoder)
        .map_err(decode_error)?
        .into_rgb32f();
    Ok(EnvImage {
        width: width as usize,
        height: height as usize,
        texels: rgb
            .as_raw()
            .chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bundled_studio_is_the_file_in_scenes() {
        let bundled = studio_environment().unwrap();
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/demo-env.hdr");
        let file = EnvironmentLight::from_file(&path, 1.0, 0.0).unwrap();
        assert_eq!(bundled.size(), Some((256, 128)));
        assert_eq!(bundled.average_radiance(), file.average_radiance());
        let d = Vec3::new(0.3, 0.5, -0.8).normalize();
        assert_eq!(bundled.radiance(d), file.radiance(d));
    }
}
