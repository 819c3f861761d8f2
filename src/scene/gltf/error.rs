//! The loader's error type: one line per problem, naming the file, the thing in it and a fix.

use std::path::{Path, PathBuf};

/// Why a scene could not be loaded. Every variant names the file and the thing in it.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// A problem that fits no other variant.
    #[error("{}: {message}", path.display())]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// What is wrong, naming the node / mesh / accessor.
        message: String,
    },
    /// The scene file itself cannot be read.
    #[error("{}: cannot read the scene file: {source} (check the path)", path.display())]
    Read {
        /// The scene file.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// The file is not well-formed glTF JSON or GLB (truncated, corrupt, not glTF at all).
    #[error("{}: {message}", path.display())]
    Syntax {
        /// The scene file.
        path: PathBuf,
        /// What is malformed and where.
        message: String,
    },
    /// The JSON is well-formed but breaks the glTF schema (e.g. a reference to an accessor
    /// that does not exist).
    #[error("{}: invalid glTF: {problems} (the exporter wrote a broken file; re-export it)", path.display())]
    Schema {
        /// The scene file.
        path: PathBuf,
        /// The problems, each with its JSON path (e.g. `meshes[0].primitives[0].indices`).
        problems: String,
    },
    /// A buffer or image the file refers to cannot be read.
    #[error(
        "{}: {what} refers to \"{uri}\", which cannot be read as {}: {source} \
         (put the file next to the scene or fix the URI)",
        path.display(),
        resolved.display()
    )]
    MissingFile {
        /// The scene file.
        path: PathBuf,
        /// Which buffer or image refers to it (e.g. `buffer 0`).
        what: String,
        /// The URI as written in the file.
        uri: String,
        /// Where glint looked for it.
        resolved: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// A buffer's or image's data cannot be obtained (bad data URI, missing GLB chunk, a
    /// buffer shorter than declared).
    #[error("{}: {what}: {problem}", path.display())]
    Data {
        /// The scene file.
        path: PathBuf,
        /// Which buffer, buffer view or image.
        what: String,
        /// What is wrong and how to fix it.
        problem: String,
    },
    /// `--variant NAME` names no KHR_materials_variants variant of the file.
    #[error("{}: no material variant \"{name}\" ({available})", path.display())]
    UnknownVariant {
        /// The scene file.
        path: PathBuf,
        /// The name asked for.
        name: String,
        /// `its variants are "a", "b"`, or that it has none.
        available: String,
    },
    /// The file requires extensions glint cannot honour (all of them named at once).
    #[error(
        "{}: the file requires {extension}, which glint does not support \
         (supported: {supported}); {advice}",
        path.display()
    )]
    UnsupportedExtension {
        /// `extension NAME`, or `extensions A, B and C` when several are missing.
        extension: String,
        /// The scene file.
        path: PathBuf,
        /// The extensions glint supports, comma-separated.
        supported: String,
        /// How to convert the file into something glint reads.
        advice: String,
    },
    /// A primitive's data is unusable: a bad accessor, an index past the vertex count, a NaN
    /// position.
    #[error("{}: {primitive}: {problem}", path.display())]
    Primitive {
        /// The scene file.
        path: PathBuf,
        /// Which primitive (`node "X" / mesh 3 / primitive 0`).
        primitive: String,
        /// What is wrong, naming the accessor.
        problem: String,
    },
    /// A node, camera or light has values glint cannot use.
    #[error("{}: {what}: {problem}", path.display())]
    Node {
        /// The scene file.
        path: PathBuf,
        /// Which node, camera or light.
        what: String,
        /// What is wrong.
        problem: String,
    },
    /// A texture image does not decode.
    #[error("{}: {image}: cannot decode the image: {message} (re-save it as PNG or JPEG)", path.display())]
    Texture {
        /// The scene file.
        path: PathBuf,
        /// Which image (index and URI or name).
        image: String,
        /// The decoder's message.
        message: String,
    },
    /// A KHR_texture_basisu texture's KTX2 image cannot be used (not a Basis Universal
    /// payload, truncated, over the texel budget, does not transcode).
    #[error("{}: {texture}: {image} (KHR_texture_basisu): {problem}", path.display())]
    Basisu {
        /// The scene file.
        path: PathBuf,
        /// Which texture (`texture 3`).
        texture: String,
        /// Which image (index and URI or name).
        image: String,
        /// What is wrong and how to fix it.
        problem: String,
    },
}

impl LoadError {
    /// The scene file (or in-memory label) the error is about.
    pub fn path(&self) -> &Path {
        match self {
            LoadError::Invalid { path, .. }
            | LoadError::Read { path, .. }
            | LoadError::Syntax { path, .. }
            | LoadError::Schema { path, .. }
            | LoadError::MissingFile { path, .. }
            | LoadError::Data { path, .. }
            | LoadError::UnsupportedExtension { path, .. }
            | LoadError::UnknownVariant { path, .. }
            | LoadError::Primitive { path, .. }
            | LoadError::Node { path, .. }
            | LoadError::Texture { path, .. }
            | LoadError::Basisu { path, .. } => path,
        }
    }
}

/// A third-party library's message on one line: its line breaks and the indentation after
/// them become single spaces (glint's errors are one line each; some decoders wrap theirs).
pub fn one_line(message: &str) -> String {
    message.split_whitespace().collect::<Vec<_>>().join(" ")
}
