//! Checks on the raw JSON that the `gltf` crate's schema validation leaves out but its
//! accessors rely on (they `unwrap` them): done before the document is wrapped, so that a
//! consistent-looking but incomplete file is one error naming the item, never a panic.

use super::LoadError;
use super::source::Origin;
use ::gltf::json::validation::Checked;

/// Checks every camera, image and KHR_lights_punctual light for the members the crate's
/// accessors assume: a camera's `type` object, an image's `uri` or `bufferView` (and its
/// `mimeType` with a `bufferView`), a spot light's `spot` object.
pub fn check_unwrapped_members(
    root: &::gltf::json::Root,
    origin: Origin<'_>,
) -> Result<(), LoadError> {
    let invalid = |message: String| LoadError::Invalid {
        path: origin.file.to_path_buf(),
        message,
    };
    for (index, camera) in root.cameras.iter().enumerate() {
        let present = match camera.type_ {
            Checked::Valid(::gltf::json::camera::Type::Perspective) => camera.perspective.is_some(),
            Checked::Valid(::gltf::json::camera::Type::Orthographic) => {
                camera.orthographic.is_some()
            }
            // The schema check reports an unknown type with its JSON path.
            Checked::Invalid => true,
        };
        if !present {
            let kind = match camera.type_ {
                Checked::Valid(::gltf::json::camera::Type::Orthographic) => "orthographic",
                _ => "perspective",
            };
            return Err(invalid(format!(
                "camera {index}: its type is \"{kind}\" but it has no \"{kind}\" object \
                 (the file is corrupt; re-export the camera)"
            )));
        }
    }
    for (index, image) in root.images.iter().enumerate() {
        match (&image.uri, &image.buffer_view) {
            (None, None) => {
                return Err(invalid(format!(
                    "image {index} has neither a \"uri\" nor a \"bufferView\" (the file is corrupt; re-export it)"
                )));
            }
            (None, Some(_)) if image.mime_type.is_none() => {
                return Err(invalid(format!(
                    "image {index} is stored in a bufferView but has no \"mimeType\" \
                     (glTF requires one; re-export it or add \"mimeType\": \"image/png\")"
                )));
            }
            _ => {}
        }
    }
    let lights = root
        .extensions
        .as_ref()
        .and_then(|e| e.khr_lights_punctual.as_ref())
        .map_or(&[][..], |l| l.lights.as_slice());
    for (index, light) in lights.iter().enumerate() {
        if matches!(
            light.type_,
            Checked::Valid(::gltf::json::extensions::scene::khr_lights_punctual::Type::Spot)
        ) && light.spot.is_none()
        {
            return Err(invalid(format!(
                "KHR_lights_punctual light {index} is a spot light without its \"spot\" object \
                 (the file is corrupt; re-export it)"
            )));
        }
    }
    Ok(())
}
