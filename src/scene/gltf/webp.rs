//! EXT_texture_webp: a texture whose image is a WebP file.
//!
//! The extension names the WebP image in `textures[i].extensions.EXT_texture_webp.source`;
//! the core `source` is then absent, or a PNG / JPEG fallback for viewers without WebP.
//! glint decodes WebP (the `image` crate's decoder), so it points every such texture's
//! `source` at the WebP image before the document is validated, and the rest of the loader
//! sees an ordinary texture. A texture whose WebP index is out of range keeps its `source`
//! (and fails validation if it has none, naming the texture).

const EXTENSION: &str = "EXT_texture_webp";

/// Points each EXT_texture_webp texture's `source` at its WebP image.
pub fn use_webp_sources(root: &mut ::gltf::json::Root) {
    let images = root.images.len();
    for texture in &mut root.textures {
        let webp = texture
            .extensions
            .as_ref()
            .and_then(|e| e.others.get(EXTENSION))
            .and_then(|v| v.get("source"))
            .and_then(serde_json::Value::as_u64)
            .and_then(|i| u32::try_from(i).ok())
            .filter(|&i| (i as usize) < images);
        if let Some(index) = webp {
            texture.source = ::gltf::json::Index::new(index);
        }
    }
}
