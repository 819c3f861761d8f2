//! From bytes to a validated glTF document with its buffers in memory.
//!
//! The `gltf` crate parses and validates the JSON; glint resolves buffers and image URIs
//! itself so that every failure names the URI and where it was looked for, and checks the GLB
//! header before the crate sees it (the crate underflows on a header length below 12).

use super::LoadError;
use base64::Engine as _;
use std::borrow::Cow;
use std::path::{Path, PathBuf};

/// Extensions glint honours when a file lists them as required.
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_pbrSpecularGlossiness",
    "KHR_materials_specular",
    "KHR_materials_unlit",
    "KHR_materials_clearcoat",
    "KHR_materials_sheen",
    "KHR_materials_transmission",
    "KHR_materials_diffuse_transmission",
    "KHR_materials_volume",
    "KHR_materials_variants",
    "KHR_materials_anisotropy",
    "KHR_texture_transform",
    "KHR_mesh_quantization",
    #[cfg(feature = "meshopt")]
    "EXT_meshopt_compression",
    "EXT_mesh_gpu_instancing",
    "EXT_texture_webp",
    "KHR_texture_basisu",
    "KHR_draco_mesh_compression",
];

/// Size of the GLB header: magic, version, total length (3 × u32).
const GLB_HEADER_BYTES: usize = 12;

/// A parsed, validated document and the bytes of its buffers (index-aligned).
pub struct Source {
    /// The validated document.
    pub document: ::gltf::Document,
    /// Each buffer's bytes, at least as long as the buffer's declared `byteLength`.
    pub buffers: Vec<Vec<u8>>,
}

/// Where a scene's relative URIs (external buffers and images) are read from.
#[derive(Clone, Copy)]
pub enum Files<'a> {
    /// Nowhere: only embedded data (GLB chunks, data URIs) is allowed.
    None,
    /// Files relative to this folder (the scene file's own).
    Folder(&'a Path),
    /// Files held in memory, looked up by their relative path.
    Memory(&'a MemoryFiles),
}

/// External files of a scene held in memory, by relative path: what
/// [`load_from_memory`](super::load_from_memory) resolves a URI against instead of a folder.
///
/// A URI is looked up after its percent-escapes are decoded and a leading `./` removed, so
/// `tex%20a.png` finds the file inserted as `tex a.png`.
#[derive(Clone, Debug, Default)]
pub struct MemoryFiles {
    files: std::collections::HashMap<String, Vec<u8>>,
}

impl MemoryFiles {
    /// No files.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds (or replaces) the file at `relative_path` (`textures/a.png`, `scene.bin`).
    pub fn insert(&mut self, relative_path: impl Into<String>, bytes: Vec<u8>) {
        let path: String = relative_path.into();
        self.files.insert(normalise(&path).to_string(), bytes);
    }

    /// The file at `relative_path`, if present.
    pub fn get(&self, relative_path: &str) -> Option<&[u8]> {
        self.files.get(normalise(relative_path)).map(Vec::as_slice)
    }

    /// How many files there are.
    pub fn len(&self) -> usize {
        self.files.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
    }
}

/// A relative path without its leading `./` segments.
fn normalise(path: &str) -> &str {
    let mut path = path;
    while let Some(rest) = path.strip_prefix("./") {
        path = rest;
    }
    path
}

/// Where the loader reads from, for messages and relative URIs.
#[derive(Clone, Copy)]
pub struct Origin<'a> {
    /// The scene file (or the in-memory label) named in messages.
    pub file: &'a Path,
    /// Where relative URIs resolve: a folder, in-memory files, or nowhere.
    pub files: Files<'a>,
    /// The asset root and size budgets.
    pub options: &'a super::LoadOptions,
}

impl Origin<'_> {
    fn syntax(&self, message: impl Into<String>) -> LoadError {
        LoadError::Syntax {
            path: self.file.to_path_buf(),
            message: message.into(),
        }
    }

    fn data(&self, what: impl Into<String>, problem: impl Into<String>) -> LoadError {
        LoadError::Data {
            path: self.file.to_path_buf(),
            what: what.into(),
            problem: problem.into(),
        }
    }
}

/// Parses `bytes` (JSON or GLB), checks required extensions, validates the document and
/// loads its buffers. Unsupported extensions that are merely used are reported in `warnings`.
pub fn parse(
    bytes: &[u8],
    origin: Origin<'_>,
    geometry: &mut super::limits::GeometryBudget,
    warnings: &mut Vec<String>,
) -> Result<Source, LoadError> {
    parse_inner(bytes, origin, geometry, warnings, true)
}

/// Like [`parse`], without refusing the required extensions glint does not support (they are
/// dropped, unread): for `glint info`, which lists them.
pub fn parse_for_inspection(
    bytes: &[u8],
    origin: Origin<'_>,
    geometry: &mut super::limits::GeometryBudget,
    warnings: &mut Vec<String>,
) -> Result<Source, LoadError> {
    parse_inner(bytes, origin, geometry, warnings, false)
}

fn parse_inner(
    bytes: &[u8],
    origin: Origin<'_>,
    geometry: &mut super::limits::GeometryBudget,
    warnings: &mut Vec<String>,
    refuse_unsupported: bool,
) -> Result<Source, LoadError> {
    if bytes.is_empty() {
        return Err(origin.syntax("the file is empty (re-export or re-download it)"));
    }
    if bytes.starts_with(b"glTF") {
        check_glb_header(bytes, origin)?;
    }
    let ::gltf::Gltf { document, mut blob } = ::gltf::Gltf::from_slice_without_validation(bytes)
        .map_err(|err| match err {
            ::gltf::Error::Binary(err) => origin.syntax(describe_glb_error(&err)),
            ::gltf::Error::Deserialize(err) => origin.syntax(format!(
                "not valid glTF JSON: {err} (the file is truncated or not a glTF file)"
            )),
            other => origin.syntax(other.to_string()),
        })?;
    let mut root = document.into_json();
    if refuse_unsupported {
        check_extensions(&root, origin, warnings)?;
    }
    super::validate::check_unwrapped_members(&root, origin)?;
    super::validate::drop_unusable_channels(&mut root, origin, warnings);
    super::webp::use_webp_sources(&mut root);
    super::basisu::use_basisu_sources(&mut root);
    // glint decodes these itself; the `gltf` crate's validator would refuse them as
    // required extensions it does not know.
    root.extensions_required
        .retain(|e| ::gltf::json::extensions::ENABLED_EXTENSIONS.contains(&e.as_str()));
    check_mesh_accessor_references(&root, origin)?;
    // With Draco primitives, buffers are read before validation so that they can be decoded
    // into plain accessors first (the validator refuses their view-less accessors until then).
    let mut early_buffers = None;
    if super::draco::any_compressed(&root) {
        let unvalidated = ::gltf::Document::from_json_without_validation(root);
        let mut buffers = load_buffers(&unvalidated, blob.take(), origin)?;
        root = unvalidated.into_json();
        super::draco::decode_primitives(&mut root, &mut buffers, origin, geometry)?;
        early_buffers = Some(buffers);
    }
    let document = ::gltf::Document::from_json(root).map_err(|err| match err {
        ::gltf::Error::Validation(problems) => LoadError::Schema {
            path: origin.file.to_path_buf(),
            problems: describe_validation(&problems),
        },
        other => origin.syntax(other.to_string()),
    })?;
    let mut buffers = match early_buffers {
        Some(buffers) => buffers,
        None => load_buffers(&document, blob, origin)?,
    };
    let document = super::meshopt::decode_views(document, &mut buffers, origin, geometry)?;
    Ok(Source { document, buffers })
}

/// Checks what the GLB header promises against the bytes present, with messages that say
/// "truncated" when the file was cut short.
fn check_glb_header(bytes: &[u8], origin: Origin<'_>) -> Result<(), LoadError> {
    let Some(header) = bytes.get(..GLB_HEADER_BYTES) else {
        return Err(origin.syntax(format!(
            "truncated GLB: {} bytes, shorter than the 12-byte header (re-export or re-download it)",
            bytes.len()
        )));
    };
    let word =
        |i: usize| u32::from_le_bytes([header[i], header[i + 1], header[i + 2], header[i + 3]]);
    let (version, length) = (word(4), word(8));
    if version != 2 {
        return Err(origin.syntax(format!(
            "GLB version {version} is not supported; glint reads glTF 2.0 (re-export as glTF 2.0)"
        )));
    }
    let length = usize::try_from(length).unwrap_or(usize::MAX);
    if length < GLB_HEADER_BYTES {
        return Err(origin.syntax(format!(
            "invalid GLB: the header gives a total length of {length} bytes, less than the header itself"
        )));
    }
    if length > bytes.len() {
        return Err(origin.syntax(format!(
            "truncated GLB: the header says {length} bytes but the file has {} (re-export or re-download it)",
            bytes.len()
        )));
    }
    Ok(())
}

fn describe_glb_error(err: &::gltf::binary::Error) -> String {
    use ::gltf::binary::{ChunkType, Error};
    let chunk = |ty: &ChunkType| match ty {
        ChunkType::Json => "JSON",
        ChunkType::Bin => "BIN",
    };
    match err {
        Error::Io(err) => format!("truncated GLB: {err} (re-export or re-download it)"),
        Error::Version(v) => format!("GLB version {v} is not supported; glint reads glTF 2.0"),
        Error::Magic(m) => format!("not a GLB file (magic {m:?})"),
        Error::Length {
            length,
            length_read,
        } => format!(
            "truncated GLB: {length} bytes of content declared, {length_read} present (re-export or re-download it)"
        ),
        Error::ChunkLength {
            ty,
            length,
            length_read,
        } => format!(
            "truncated GLB: the {} chunk declares {length} bytes but only {length_read} follow (re-export or re-download it)",
            chunk(ty)
        ),
        Error::ChunkType(ty) => format!("invalid GLB: unexpected {} chunk", chunk(ty)),
        Error::UnknownChunkType(ty) => format!("invalid GLB: unknown chunk type {ty:?}"),
    }
}

/// Refuses required extensions glint cannot honour; warns about used ones it ignores.
fn check_extensions(
    root: &::gltf::json::Root,
    origin: Origin<'_>,
    warnings: &mut Vec<String>,
) -> Result<(), LoadError> {
    let missing: Vec<&str> = root
        .extensions_required
        .iter()
        .map(String::as_str)
        .filter(|e| !SUPPORTED_EXTENSIONS.contains(e))
        .collect();
    if !missing.is_empty() {
        return Err(super::unsupported::error(&missing, origin));
    }
    for extension in &root.extensions_used {
        if !SUPPORTED_EXTENSIONS.contains(&extension.as_str()) {
            warnings.push(format!(
                "{}: extension {extension} is used but not supported; its effects are ignored",
                origin.file.display()
            ));
        }
    }
    Ok(())
}

/// Names the primitive and the attribute when a mesh refers to an accessor that does not
/// exist (the schema check would only give the JSON path).
fn check_mesh_accessor_references(
    root: &::gltf::json::Root,
    origin: Origin<'_>,
) -> Result<(), LoadError> {
    let count = root.accessors.len();
    for (mesh_index, mesh) in root.meshes.iter().enumerate() {
        for (primitive_index, primitive) in mesh.primitives.iter().enumerate() {
            let attributes = primitive.attributes.iter().map(|(semantic, index)| {
                let name = match semantic {
                    ::gltf::json::validation::Checked::Valid(s) => s.to_string(),
                    ::gltf::json::validation::Checked::Invalid => {
                        "an unknown attribute".to_string()
                    }
                };
                (name, index.value())
            });
            let indices = primitive
                .indices
                .map(|i| ("indices".to_string(), i.value()));
            for (what, accessor) in attributes.chain(indices) {
                if accessor >= count {
                    return Err(LoadError::Primitive {
                        path: origin.file.to_path_buf(),
                        primitive: format!("mesh {mesh_index} / primitive {primitive_index}"),
                        problem: format!(
                            "{what} refers to accessor {accessor}, but the file has only {count} accessors \
                             (the file is corrupt; re-export it)"
                        ),
                    });
                }
            }
        }
    }
    Ok(())
}

fn describe_validation(
    problems: &[(::gltf::json::Path, ::gltf::json::validation::Error)],
) -> String {
    /// Enough to locate the first problems without flooding the terminal.
    const SHOWN: usize = 3;
    let mut text = problems
        .iter()
        .take(SHOWN)
        .map(|(path, error)| format!("{path}: {error}"))
        .collect::<Vec<_>>()
        .join("; ");
    if problems.len() > SHOWN {
        text.push_str(&format!("; and {} more", problems.len() - SHOWN));
    }
    text
}

/// Reads every buffer: the GLB's BIN chunk, a data URI or a file next to the scene.
fn load_buffers(
    document: &::gltf::Document,
    mut blob: Option<Vec<u8>>,
    origin: Origin<'_>,
) -> Result<Vec<Vec<u8>>, LoadError> {
    let mut buffers = Vec::with_capacity(document.buffers().len());
    for buffer in document.buffers() {
        let what = format!("buffer {}", buffer.index());
        if super::meshopt::is_fallback(&buffer) {
            // EXT_meshopt_compression's placeholder: its bytes exist only compressed, and
            // `decode_views` points every view that used it at decoded data.
            buffers.push(Vec::new());
            continue;
        }
        let data = match buffer.source() {
            ::gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                origin.data(
                    &what,
                    "refers to the GLB binary chunk, but the file has none (or it is used twice); re-export the scene",
                )
            })?,
            ::gltf::buffer::Source::Uri(uri) => read_uri(uri, &what, origin)?.into_owned(),
        };
        if data.len() < buffer.length() {
            return Err(origin.data(
                &what,
                format!(
                    "declares {} bytes but only {} are present (the data is truncated; re-export it)",
                    buffer.length(),
                    data.len()
                ),
            ));
        }
        buffers.push(data);
    }
    Ok(buffers)
}

/// The file [`read_uri`] reads for `uri` of a scene whose relative URIs resolve against
/// `base_dir`: the percent-decoded relative path joined to the folder. `None` where
/// `read_uri` reads no file: a data URI (its bytes are in the JSON), another URI scheme, an
/// undecodable or absolute path (all three refused at load). The asset root is not checked
/// here: a scene that loaded passed it.
pub fn external_path(uri: &str, base_dir: &Path) -> Option<PathBuf> {
    if uri.starts_with("data:")
        || uri
            .split_once(':')
            .is_some_and(|(scheme, _)| !scheme.contains('/'))
    {
        return None;
    }
    let relative = urlencoding::decode(uri).ok()?;
    let relative = Path::new(relative.as_ref());
    (!relative.is_absolute()).then(|| base_dir.join(relative))
}

/// The bytes a URI names: decoded from a base64 data URI, or read from a file relative to
/// the scene's folder (percent-escapes such as `%20` decoded first; [`external_path`] names
/// the same file).
pub fn read_uri<'u>(
    uri: &'u str,
    what: &str,
    origin: Origin<'_>,
) -> Result<Cow<'u, [u8]>, LoadError> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let Some((_media_type, payload)) = rest.split_once(";base64,") else {
            return Err(origin.data(
                what,
                "has a data URI that is not base64-encoded; only `data:<type>;base64,<data>` is supported",
            ));
        };
        return base64::engine::general_purpose::STANDARD
            .decode(payload)
            .map(Cow::Owned)
            .map_err(|err| {
                origin.data(
                    what,
                    format!("has a data URI with invalid base64 ({err}); re-export the scene"),
                )
            });
    }
    if let Some((scheme, _)) = uri.split_once(':')
        && !scheme.contains('/')
    {
        return Err(origin.data(
            what,
            format!("refers to \"{uri}\": URI scheme \"{scheme}:\" is not supported; use a relative path or embed the data"),
        ));
    }
    let relative = urlencoding::decode(uri).map_err(|_| {
        origin.data(
            what,
            format!("refers to \"{uri}\", whose %-escapes are not UTF-8; fix the URI"),
        )
    })?;
    let base_dir = match origin.files {
        Files::Folder(dir) => dir,
        Files::None => {
            return Err(origin.data(
                what,
                format!("refers to the external file \"{uri}\", but this scene is loaded from memory; embed the data (GLB)"),
            ));
        }
        Files::Memory(files) => {
            return files
                .get(relative.as_ref())
                .map(|bytes| Cow::Owned(bytes.to_vec()))
                .ok_or_else(|| LoadError::MissingFile {
                    path: origin.file.to_path_buf(),
                    what: what.to_string(),
                    uri: uri.to_string(),
                    resolved: PathBuf::from(relative.as_ref()),
                    source: std::io::Error::new(
                        std::io::ErrorKind::NotFound,
                        "not among the scene's in-memory files",
                    ),
                });
        }
    };
    let refuse = |problem: String| origin.data(what, format!("refers to \"{uri}\": {problem}"));
    if Path::new(relative.as_ref()).is_absolute() {
        return Err(refuse(
            "absolute paths are refused; make the URI relative to the scene's folder".into(),
        ));
    }
    let resolved: PathBuf = base_dir.join(relative.as_ref());
    let missing = |source: std::io::Error| LoadError::MissingFile {
        path: origin.file.to_path_buf(),
        what: what.to_string(),
        uri: uri.to_string(),
        resolved: resolved.clone(),
        source,
    };
    if let Some(root) = &origin.options.asset_root {
        let root = root.canonicalize().map_err(|err| {
            refuse(format!(
                "the asset root {} cannot be resolved: {err}",
                root.display()
            ))
        })?;
        let real = resolved.canonicalize().map_err(missing)?;
        if !real.starts_with(&root) {
            return Err(refuse(format!(
                "it resolves to {}, outside the asset root {} (move the file under the root or \
                 widen --asset-root)",
                real.display(),
                root.display()
            )));
        }
    }
    read_regular_file(&resolved)
        .map_err(|err| match err {
            FileError::Io(source) => missing(source),
            FileError::NotRegular(kind) => refuse(format!(
                "{} is {kind}, not a regular file; only regular files are read",
                resolved.display()
            )),
        })
        .map(Cow::Owned)
}

/// Why [`read_regular_file`] failed.
pub enum FileError {
    /// The operating system's error.
    Io(std::io::Error),
    /// The path names a device, FIFO, socket or folder (described).
    NotRegular(&'static str),
}

/// Reads a regular file whole, refusing anything else without blocking: the type is checked
/// with `stat` before opening (opening a FIFO would block until a writer appears, and a
/// device such as /dev/zero never ends), and again on the opened handle, whose length then
/// bounds the read.
pub fn read_regular_file(path: &Path) -> Result<Vec<u8>, FileError> {
    use std::io::Read as _;
    let kind = |meta: &std::fs::Metadata| {
        let ty = meta.file_type();
        if ty.is_file() {
            None
        } else if ty.is_dir() {
            Some("a folder")
        } else {
            Some("a device, FIFO or socket")
        }
    };
    let meta = std::fs::metadata(path).map_err(FileError::Io)?;
    if let Some(kind) = kind(&meta) {
        return Err(FileError::NotRegular(kind));
    }
    let file = std::fs::File::open(path).map_err(FileError::Io)?;
    let meta = file.metadata().map_err(FileError::Io)?;
    if let Some(kind) = kind(&meta) {
        return Err(FileError::NotRegular(kind));
    }
    // The length of a regular file bounds the allocation; `take` bounds the read should the
    // file grow meanwhile.
    let length = meta.len();
    let mut bytes = Vec::new();
    file.take(length)
        .read_to_end(&mut bytes)
        .map_err(FileError::Io)?;
    Ok(bytes)
}

/// The bytes of a buffer view, checked against its buffer.
pub fn view_bytes<'b>(
    view: &::gltf::buffer::View<'_>,
    buffers: &'b [Vec<u8>],
    what: &str,
    origin: Origin<'_>,
) -> Result<&'b [u8], LoadError> {
    let buffer: &[u8] = buffers
        .get(view.buffer().index())
        .map_or(&[], Vec::as_slice);
    view.offset()
        .checked_add(view.length())
        .and_then(|end| buffer.get(view.offset()..end))
        .ok_or_else(|| {
            origin.data(
                format!("{what}: buffer view {}", view.index()),
                format!(
                    "bytes {}..+{} lie outside buffer {} ({} bytes); the file is corrupt, re-export it",
                    view.offset(),
                    view.length(),
                    view.buffer().index(),
                    buffer.len()
                ),
            )
        })
}
