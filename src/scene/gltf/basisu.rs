//! KHR_texture_basisu: a texture whose image is a KTX2 file with a Basis Universal payload.
//!
//! The extension names the KTX2 image in `textures[i].extensions.KHR_texture_basisu.source`;
//! the core `source` is then absent, or a PNG / JPEG fallback for viewers without KTX2.
//! glint transcodes KTX2 ([`crate::scene::ktx2_decode`]), so the KTX2 image is preferred:
//! [`basisu_image`] names it for the texture decoder, and the core `source` is used only when
//! the KTX2 image cannot be used (its header is unreadable or not a Basis payload), with a
//! warning. A texture without a core `source` gets the KTX2 image as its `source` before the
//! document is validated ([`use_basisu_sources`]), so the rest of the loader sees an ordinary
//! texture. A KTX2 index out of range is ignored (the texture then fails validation if it has
//! no `source`, naming the texture).

/// The extension's name.
pub const EXTENSION: &str = "KHR_texture_basisu";

/// The image index the extension names, if any (not range-checked).
fn extension_source(
    extensions: Option<&serde_json::Map<String, serde_json::Value>>,
) -> Option<usize> {
    extensions?
        .get(EXTENSION)?
        .get("source")?
        .as_u64()
        .and_then(|i| usize::try_from(i).ok())
}

/// Gives each KHR_texture_basisu texture that has no core `source` (or an out-of-range one)
/// its KTX2 image as `source`; a texture with a valid fallback keeps it.
pub fn use_basisu_sources(root: &mut ::gltf::json::Root) {
    let images = root.images.len();
    for texture in &mut root.textures {
        let ktx2 = extension_source(texture.extensions.as_ref().map(|e| &e.others))
            .filter(|&i| i < images)
            .and_then(|i| u32::try_from(i).ok());
        let fallback_valid = texture.source.value() < images;
        if let (Some(index), false) = (ktx2, fallback_valid) {
            texture.source = ::gltf::json::Index::new(index);
        }
    }
}

/// The KTX2 image of a KHR_texture_basisu texture, when the extension names an existing one.
pub fn basisu_image(texture: &::gltf::Texture<'_>, image_count: usize) -> Option<usize> {
    extension_source(texture.extensions()).filter(|&i| i < image_count)
}
