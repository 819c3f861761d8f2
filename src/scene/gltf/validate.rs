//! Checks on the raw JSON that the `gltf` crate's schema validation leaves out but its
//! accessors rely on (they `unwrap` them): done before the document is wrapped, so that a
//! consistent-looking but incomplete file is one error naming the item, never a panic.

use super::LoadError;
use super::source::Origin;
use ::gltf::json::validation::Checked;

/// Checks every camera, image and KHR_lights_punctual light for the members the crate's
/// accessors assume: a camera's `type` object, exactly one of an image's `uri` and
/// `bufferView` (and its `mimeType` with a `bufferView`), a spot light's `spot` object.
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
        check_image_source(index, image).map_err(invalid)?;
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

/// glTF's rules on where an image's bytes come from: exactly one of `uri` and `bufferView`,
/// and a `mimeType` with a `bufferView`. The crate's `Image::source` unwraps on both.
fn check_image_source(index: usize, image: &::gltf::json::Image) -> Result<(), String> {
    match (&image.uri, &image.buffer_view) {
        (None, None) => Err(format!(
            "image {index} has neither a \"uri\" nor a \"bufferView\" (the file is corrupt; re-export it)"
        )),
        (Some(_), Some(_)) => Err(format!(
            "image {index} has both a \"uri\" and a \"bufferView\", but glTF allows exactly one \
             (the file is corrupt; remove one of them or re-export it)"
        )),
        (None, Some(_)) if image.mime_type.is_none() => Err(format!(
            "image {index} is stored in a bufferView but has no \"mimeType\" \
             (glTF requires one; re-export it or add \"mimeType\": \"image/png\")"
        )),
        _ => Ok(()),
    }
}

/// Drops every animation channel the crate would panic on when it is sampled, with a warning
/// naming the animation and the channel: a target `path` that is not one of glTF's four
/// (`translation`, `rotation`, `scale`, `weights`; e.g. KHR_animation_pointer's `pointer`), or
/// a target `node` past the file's nodes (the crate's schema check leaves channel targets
/// out). The rest of the file, and its other channels, still load.
pub fn drop_unusable_channels(
    root: &mut ::gltf::json::Root,
    origin: Origin<'_>,
    warnings: &mut Vec<String>,
) {
    let nodes = root.nodes.len();
    for (animation_index, animation) in root.animations.iter_mut().enumerate() {
        let mut channel_index = 0;
        animation.channels.retain(|channel| {
            let problem = channel_problem(&channel.target, nodes);
            if let Some(problem) = &problem {
                warnings.push(format!(
                    "{}: animation {animation_index} / channel {channel_index}: {problem}; \
                     the channel is ignored",
                    origin.file.display()
                ));
            }
            channel_index += 1;
            problem.is_none()
        });
    }
}

/// Why a channel's target cannot be sampled, if it cannot.
fn channel_problem(target: &::gltf::json::animation::Target, nodes: usize) -> Option<String> {
    if matches!(target.path, Checked::Invalid) {
        return Some(
            "its target path is not translation, rotation, scale or weights \
             (glint animates only glTF's four node properties)"
                .to_string(),
        );
    }
    let node = target.node.value();
    (node >= nodes).then(|| {
        format!("it targets node {node}, but the file has only {nodes} nodes (the file is corrupt)")
    })
}
