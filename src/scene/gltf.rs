//! Loading glTF 2.0 (`.gltf` and `.glb`) into a [`Scene`](super::Scene).
//!
//! # Supported
//! - `.gltf` with external files or base64 data URIs, and `.glb` (binary chunk); URIs are
//!   relative paths (percent-escapes decoded) or data URIs.
//! - The default scene, or the one [`SceneSelection::scene`] names (else scene 0; a file
//!   without scenes renders its root nodes). The node
//!   hierarchy is flattened: matrix or translation · rotation · scale composed down the tree;
//!   one world-space [`Mesh`](super::Mesh) per (node, primitive), named
//!   `node "X" / mesh 3 / primitive 0`, unless the mesh is shared (below).
//!   Positions go through the world matrix, normals through its inverse transpose
//!   (renormalised), tangents through its linear part; a mirroring node (negative
//!   determinant) has its triangles' winding flipped so that front faces stay
//!   counter-clockwise, and its tangents' handedness flipped.
//! - Modes TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN (strips and fans become triangles as
//!   the glTF spec defines them), indexed or not.
//! - Attributes POSITION, NORMAL, TANGENT, TEXCOORD_0, TEXCOORD_1 (float or normalized
//!   integers), COLOR_0 (RGB or RGBA, float or normalized integers; linear). Sparse
//!   accessors. KHR_mesh_quantization's integer layouts (`quantization`),
//!   EXT_meshopt_compression's compressed buffer views (`meshopt`) and
//!   KHR_draco_mesh_compression's compressed primitives (`draco`), decoded at load under the
//!   geometry budget ([`LoadOptions::max_geometry_bytes`]).
//! - Morph targets with the node's or mesh's default weights (`morph`); skins posed by their
//!   joints (`skin`); animations sampled at [`SceneSelection::time`] (`animation`).
//! - EXT_mesh_gpu_instancing, and meshes several nodes share (same mesh, same morph weights,
//!   not skinned): one object-space [`Mesh`](super::Mesh) per primitive with a placement per
//!   copy (`instancing`, `sharing`), traced as instances of one structure by both backends.
//! - Materials: baseColorFactor and baseColorTexture, metallicFactor, roughnessFactor,
//!   emissiveFactor × KHR_materials_emissive_strength, emissiveTexture, doubleSided, name;
//!   metallicRoughnessTexture; normalTexture with scale (`normal_texture`; MikkTSpace
//!   tangents generated for its meshes when the file has no TANGENT, see
//!   [`crate::scene::tangents`]); KHR_texture_transform on every texture (with its texCoord
//!   override). A primitive
//!   without a material gets glTF's default (white, metallic 1, roughness 1, single-sided).
//!   KHR_materials_pbrSpecularGlossiness is converted to that model (`specular_glossiness`);
//!   KHR_materials_variants' mappings replace a primitive's material for the variant
//!   [`SceneSelection::variant`] names (`variants`).
//! - Textures: PNG, JPEG, (EXT_texture_webp) WebP and (KHR_texture_basisu, `basisu`) KTX2
//!   with Basis Universal ETC1S or UASTC payloads, from files, data URIs or buffer views; a
//!   texture with a KTX2 image and a fallback `source` reads the KTX2 when its header is
//!   usable; base colour and emissive decoded from sRGB to linear with the exact sRGB
//!   curve; sampler wrap modes and the magnification filter.
//! - Cameras (perspective and orthographic) of every camera node, in node order, with the
//!   node's scale removed.
//! - KHR_lights_punctual point, spot and directional lights, in radiometric units (see
//!   [`Light`](super::Light)): glTF's `intensity × color` is carried as is, no 683 lm/W.
//!
//! # Ignored
//! - Animations when no time is given (one warning; the rest pose renders).
//! - occlusionTexture, alphaMode / alphaCutoff,
//!   texture minification filters, the camera's znear / zfar.
//! - KHR_materials_* extensions other than emissive_strength, and every other extension:
//!   a file that lists some as *required* is refused naming all of them (with advice where
//!   a converter exists); one that merely uses them loads with a warning.
//! - POINTS, LINES, LINE_LOOP and LINE_STRIP primitives: skipped with a warning (one line
//!   primitive should not make a whole scene unloadable).
//! - TEXCOORD_2 and above, COLOR_1 and above.
//!
//! # Errors
//! Every bad input is a [`LoadError`] naming the file and the thing in it, never a panic: a
//! missing, truncated or invalid file, a missing `.bin` or image file, an accessor reference
//! or byte range out of bounds, indices past the vertex count, NaN or infinite positions, an
//! unsupported required extension, an image that does not decode.

mod accessors;
mod alpha;
mod animation;
mod basisu;
mod draco;
mod error;
pub mod info;
mod instancing;
mod limits;
mod material_layers;
mod materials;
#[cfg(feature = "meshopt")]
mod meshopt;
#[cfg(not(feature = "meshopt"))]
#[path = "gltf/meshopt_off.rs"]
mod meshopt;
mod morph;
mod nodes;
mod normal_texture;
mod objects;
mod primitives;
mod procedural;
mod quantization;
mod sharing;
mod skin;
mod source;
mod specular_glossiness;
mod unsupported;
mod validate;
mod variants;
mod webp;

pub use error::{LoadError, one_line};
pub use limits::{
    DEFAULT_MAX_GEOMETRY_BYTES, DEFAULT_MAX_TEXTURE_PIXELS, GEOMETRY_BYTES_PER_INDEX,
    GEOMETRY_BYTES_PER_VERTEX, LoadOptions, MAX_COORDINATE, MAX_EMISSION,
};
pub use materials::uv_transform;
pub use primitives::{assemble_triangles, normal_transform};
pub use source::{MemoryFiles, SUPPORTED_EXTENSIONS, external_path};

/// The folder the relative URIs of the scene file at `path` resolve against: its own folder.
pub fn base_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

use super::{Material, Scene};
use glam::Mat4;
use source::{Files, Origin};
use std::path::Path;

/// Which scene of the file to load, and at what animation time.
///
/// The default is what `load` does: the file's default scene (else scene 0) in its rest
/// pose, animations not applied.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneSelection {
    /// The index of the scene to render (`--scene N`); `None`: the file's default scene.
    pub scene: Option<usize>,
    /// The time in seconds at which every animation is sampled (`--time SECONDS`); `None`:
    /// the rest pose (the file's node transforms and default morph weights).
    pub time: Option<f32>,
    /// The KHR_materials_variants variant whose materials to render (`--variant NAME`);
    /// `None`: every primitive's default material. A name the file lacks is
    /// [`LoadError::UnknownVariant`], which lists the file's variants.
    pub variant: Option<String>,
}

/// A loaded scene and the warnings the loader gave (skipped primitives, ignored extensions).
#[derive(Debug)]
pub struct Loaded {
    /// The scene.
    pub scene: Scene,
    /// One line each, already naming the file; for stderr.
    pub warnings: Vec<String>,
}

/// Loads a `.gltf` or `.glb` file, resolving external buffers and images next to it.
/// Warnings go to stderr; use [`load_with_warnings`] to handle them yourself.
pub fn load(path: &Path) -> Result<Scene, LoadError> {
    load_with_warnings(path).map(print_warnings)
}

/// Like [`load`], for the scene and animation time `selection` names; warnings go to stderr.
pub fn load_with(path: &Path, selection: &SceneSelection) -> Result<Scene, LoadError> {
    load_selected(path, selection).map(print_warnings)
}

/// Loads a glTF or GLB held in memory (the embedded demo scene); `label` names it in errors and
/// `base_dir` resolves relative URIs (None: only embedded data is allowed).
/// Warnings go to stderr; use [`load_slice_with_warnings`] to handle them yourself.
pub fn load_slice(bytes: &[u8], label: &str, base_dir: Option<&Path>) -> Result<Scene, LoadError> {
    load_slice_with_warnings(bytes, label, base_dir).map(print_warnings)
}

/// Like [`load`], returning the warnings instead of printing them.
pub fn load_with_warnings(path: &Path) -> Result<Loaded, LoadError> {
    load_with_options(path, &LoadOptions::default())
}

/// Like [`load_with_warnings`], with an asset root and size budgets.
pub fn load_with_options(path: &Path, options: &LoadOptions) -> Result<Loaded, LoadError> {
    load_full(path, &SceneSelection::default(), options)
}

/// Like [`load_with_warnings`], for the scene and animation time `selection` names.
pub fn load_selected(path: &Path, selection: &SceneSelection) -> Result<Loaded, LoadError> {
    load_full(path, selection, &LoadOptions::default())
}

/// The bytes of the glTF or GLB file at `path`, which must be a regular file (a FIFO or a
/// device is refused at once instead of blocking).
pub(crate) fn read_scene_file(path: &Path) -> Result<Vec<u8>, LoadError> {
    source::read_regular_file(path).map_err(|err| LoadError::Read {
        path: path.to_path_buf(),
        source: match err {
            source::FileError::Io(err) => err,
            source::FileError::NotRegular(kind) => {
                std::io::Error::other(format!("it is {kind}, not a regular file"))
            }
        },
    })
}

/// Loads the scene and time `selection` names under `options` (asset root, size budgets),
/// returning the warnings.
pub fn load_full(
    path: &Path,
    selection: &SceneSelection,
    options: &LoadOptions,
) -> Result<Loaded, LoadError> {
    let bytes = read_scene_file(path)?;
    load_bytes(
        &bytes,
        Origin {
            file: path,
            files: Files::Folder(base_dir(path)),
            options,
        },
        selection,
    )
}

/// Like [`load_slice`], returning the warnings instead of printing them.
pub fn load_slice_with_warnings(
    bytes: &[u8],
    label: &str,
    base_dir: Option<&Path>,
) -> Result<Loaded, LoadError> {
    load_bytes(
        bytes,
        Origin {
            file: Path::new(label),
            files: base_dir.map_or(Files::None, Files::Folder),
            options: &LoadOptions::default(),
        },
        &SceneSelection::default(),
    )
}

/// Loads a glTF or GLB held in memory whose external buffers and images are held in memory
/// too: each relative URI is looked up in `files` (see [`MemoryFiles`]); nothing is read from
/// disk. `label` names the scene in errors. The scene, time and budgets are those of
/// `selection` and `options` (`options.asset_root` does not apply: no file is read).
///
/// This is the entry point for scenes that arrive over a network or from an archive, and for
/// the in-process fuzz targets (`examples/fuzz/`).
pub fn load_from_memory(
    bytes: &[u8],
    label: &str,
    files: &MemoryFiles,
    selection: &SceneSelection,
    options: &LoadOptions,
) -> Result<Loaded, LoadError> {
    load_bytes(
        bytes,
        Origin {
            file: Path::new(label),
            files: Files::Memory(files),
            options,
        },
        selection,
    )
}

/// Prints a load's warnings to stderr and returns its scene.
pub fn print_warnings(loaded: Loaded) -> Scene {
    for warning in &loaded.warnings {
        eprintln!("glint: warning: {warning}");
    }
    loaded.scene
}

fn load_bytes(
    bytes: &[u8],
    origin: Origin<'_>,
    selection: &SceneSelection,
) -> Result<Loaded, LoadError> {
    let mut warnings = Vec::new();
    let mut geometry = limits::GeometryBudget::new(origin.options);
    let source = source::parse(bytes, origin, &mut geometry, &mut warnings)?;
    let document = &source.document;
    let variant = variants::select(document, selection.variant.as_deref(), origin)?;
    let materials::Materials {
        mut materials,
        textures,
    } = materials::load(document, &source.buffers, origin, &mut warnings)?;
    // glTF's default material goes last, added only if some primitive needs it.
    let default_material = materials.len();
    let mut uses_default = false;

    let pose = match selection.time {
        Some(time) if time.is_finite() => {
            animation::sample(document, &source.buffers, time, origin)?
        }
        Some(time) => {
            return Err(LoadError::Invalid {
                path: origin.file.to_path_buf(),
                message: format!("animation time {time} is not a finite number of seconds"),
            });
        }
        None => {
            let count = document.animations().len();
            if count > 0 {
                warnings.push(format!(
                    "{}: {count} animation(s) not applied (rest pose); pass --time SECONDS to sample them",
                    origin.file.display()
                ));
            }
            animation::Pose::rest()
        }
    };
    let quantized = quantization::enabled(document);
    let placed = nodes::flatten(document, selection.scene, &pose, origin, &mut warnings)?;
    // Joint transforms need every node's world matrix, not only the scene's.
    let all_world = if document.skins().len() > 0 {
        skin::world_matrices(document, &pose, origin)?
    } else {
        Vec::new()
    };
    let mut scene = Scene {
        textures,
        ..Scene::default()
    };
    // Per node: its morph weights, its skin's joint matrices and its copies (node-local
    // transforms; one identity copy without EXT_mesh_gpu_instancing).
    let mut drawn = Vec::with_capacity(placed.len());
    for node in &placed {
        let Some(mesh) = node.node.mesh() else {
            drawn.push(None);
            continue;
        };
        let weights = pose
            .node(node.node.index())
            .and_then(|p| p.weights.clone())
            .unwrap_or_else(|| morph::default_weights(&node.node));
        let joints = match node.node.skin() {
            Some(skin) => Some(skin::joint_matrices(
                &node.node,
                &skin,
                &all_world,
                &source.buffers,
                origin,
            )?),
            None => None,
        };
        let gpu_instances = instancing::transforms(&node.node, document, &source.buffers, origin)?;
        // A skinned mesh is placed by its joints, so instancing it would be meaningless.
        let copies = match (&joints, gpu_instances) {
            (None, Some(copies)) => copies,
            (Some(_), Some(_)) => {
                warnings.push(format!(
                    "{}: {}: EXT_mesh_gpu_instancing on a skinned node is ignored (the joints place the mesh)",
                    origin.file.display(),
                    nodes::node_label(&node.node)
                ));
                vec![Mat4::IDENTITY]
            }
            (_, None) => vec![Mat4::IDENTITY],
        };
        drawn.push(Some(sharing::NodeMesh {
            mesh,
            weights,
            joints,
            copies,
            instanced: node
                .node
                .extension_value("EXT_mesh_gpu_instancing")
                .is_some(),
        }));
    }
    scene.nodes = node_infos(&placed, document.nodes().len());
    let shares = sharing::plan(&placed, &drawn);
    for (index, node) in placed.iter().enumerate() {
        if let Some(Some(drawn)) = drawn.get(index) {
            let mesh = &drawn.mesh;
            let share = shares.of(index);
            if share.is_some_and(|s| !s.first) {
                // Drawn as a placement of the meshes its group's first node built.
                continue;
            }
            // A shared mesh is built once in object space and placed at every copy of
            // every node of its group; any other is baked into world space per copy.
            let placements = share.map(|s| s.placements.as_slice());
            let copies: &[Mat4] = match placements {
                Some(_) => &[Mat4::IDENTITY],
                None => &drawn.copies,
            };
            for (instance, local) in copies.iter().enumerate() {
                for primitive in mesh.primitives() {
                    let mapped = variants::material(&primitive, mesh.index(), variant, origin)?;
                    let material = match mapped.or(primitive.material().index()) {
                        Some(index) => index,
                        None => {
                            uses_default = true;
                            default_material
                        }
                    };
                    let copy_label = match placements {
                        Some(p) => format!(" / {} copies", p.len()),
                        None if drawn.instanced => format!(" / instance {instance}"),
                        None => String::new(),
                    };
                    let ctx = primitives::PrimitiveContext {
                        origin,
                        buffers: &source.buffers,
                        label: format!(
                            "{} / mesh {} / primitive {}{copy_label}",
                            nodes::node_label(&node.node),
                            mesh.index(),
                            primitive.index()
                        ),
                        world_from_object: match placements {
                            Some(_) => Mat4::IDENTITY,
                            None => node.world_from_node * *local,
                        },
                        material,
                        quantized,
                        morph_weights: &drawn.weights,
                        skin: drawn.joints.as_deref(),
                    };
                    let (bytes, declared) = primitive_geometry_bytes(&primitive);
                    geometry.charge(bytes, &format!("{} ({declared})", ctx.label), origin)?;
                    if let Some(mut built) = primitives::build(&primitive, &ctx, &mut warnings)? {
                        built.node = u32::try_from(node.node.index()).ok();
                        normal_texture::ensure_tangents(
                            &mut built,
                            &materials,
                            origin,
                            &mut warnings,
                        );
                        if let Some(placements) = placements {
                            built.instances = placements.to_vec();
                            if built.instances.is_empty() {
                                continue;
                            }
                        }
                        scene.meshes.push(built);
                    }
                }
            }
        }
        if let Some(light) = objects::light(node, origin)? {
            scene.lights.push(light);
        }
    }
    // Cameras in node order, whatever the traversal order.
    let mut camera_nodes: Vec<&nodes::PlacedNode<'_>> = placed
        .iter()
        .filter(|p| p.node.camera().is_some())
        .collect();
    camera_nodes.sort_by_key(|p| p.node.index());
    for node in camera_nodes {
        if let Some(camera) = objects::camera(node, origin)? {
            scene.cameras.push(camera);
        }
    }
    if uses_default {
        materials.push(Material::default());
    }
    scene.materials = materials;
    limits::check_scene(&scene, origin)?;
    Ok(Loaded { scene, warnings })
}

/// What building `primitive` may allocate, from its accessors' declared counts: every vertex
/// at [`GEOMETRY_BYTES_PER_VERTEX`], and its indices (three per strip or fan element); and
/// which accessors declared them, for the message.
fn primitive_geometry_bytes(primitive: &::gltf::Primitive<'_>) -> (u64, String) {
    use ::gltf::mesh::Mode;
    let positions = primitive.get(&::gltf::Semantic::Positions);
    let vertices = positions.as_ref().map_or(0, |a| a.count() as u64);
    let mut from = match &positions {
        Some(a) => format!(
            "POSITION accessor {} declares {vertices} vertices",
            a.index()
        ),
        None => "no POSITION".to_string(),
    };
    let elements = match primitive.indices() {
        Some(a) => {
            from.push_str(&format!(
                ", indices accessor {} {} indices",
                a.index(),
                a.count()
            ));
            a.count() as u64
        }
        None => vertices,
    };
    let indices = match primitive.mode() {
        Mode::TriangleStrip | Mode::TriangleFan => elements.saturating_mul(3),
        _ => elements,
    };
    let bytes = vertices
        .saturating_mul(GEOMETRY_BYTES_PER_VERTEX)
        .saturating_add(indices.saturating_mul(GEOMETRY_BYTES_PER_INDEX));
    (bytes, from)
}

/// The [`super::NodeInfo`] of every placed node that draws a mesh, by node index.
fn node_infos(placed: &[nodes::PlacedNode<'_>], count: usize) -> Vec<Option<super::NodeInfo>> {
    let mut infos = vec![None; count];
    for node in placed {
        let Some(mesh) = node.node.mesh() else {
            continue;
        };
        let category = node
            .node
            .extras()
            .as_ref()
            .and_then(|raw| serde_json::from_str::<serde_json::Value>(raw.get()).ok())
            .and_then(|extras| {
                extras
                    .get("category")
                    .and_then(|c| c.as_str())
                    .map(str::to_string)
            });
        if let Some(slot) = infos.get_mut(node.node.index()) {
            *slot = Some(super::NodeInfo {
                name: node.node.name().map(str::to_string),
                mesh: mesh.index() as u32,
                mesh_name: mesh.name().map(str::to_string),
                category,
                world_from_node: node.world_from_node,
            });
        }
    }
    infos
}
