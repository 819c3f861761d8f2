//! What a glTF file holds that a user needs to write render jobs for it (`glint info FILE`):
//! its scenes, cameras, lights, animations with their time ranges, material variants, the
//! extensions it uses (read, ignored or refused by glint), and its triangle and texture
//! counts. The file is parsed and validated as a load is, but nothing is built, and a file
//! that requires an extension glint lacks is described rather than refused.

use super::LoadError;
use super::limits::{GeometryBudget, LoadOptions};
use super::source::{self, Files, Origin, SUPPORTED_EXTENSIONS};
use serde::Serialize;
use std::collections::HashSet;
use std::path::Path;

/// A description of one glTF file.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct FileInfo {
    /// The file, as given.
    pub file: String,
    /// The scene rendered without `--scene`: the file's `scene`, else 0 (`None` without scenes).
    pub default_scene: Option<usize>,
    /// Every scene, in file order (`--scene N`).
    pub scenes: Vec<SceneInfo>,
    /// The default scene's cameras, in node order (`--camera N`).
    pub cameras: Vec<CameraInfo>,
    /// The default scene's KHR_lights_punctual lights, one per light node.
    pub lights: Vec<LightInfo>,
    /// Every animation (sampled with `--time SECONDS`).
    pub animations: Vec<AnimationInfo>,
    /// KHR_materials_variants names (`--variant NAME`), in file order.
    pub variants: Vec<String>,
    /// The extensions the file uses, by what glint does with them.
    pub extensions: ExtensionInfo,
    /// Triangles the default scene draws: each node's mesh counted once per node (and per
    /// EXT_mesh_gpu_instancing copy).
    pub triangles: u64,
    /// Meshes, materials, textures and images in the file.
    pub meshes: usize,
    /// See [`FileInfo::meshes`].
    pub materials: usize,
    /// See [`FileInfo::meshes`].
    pub textures: usize,
    /// See [`FileInfo::meshes`].
    pub images: usize,
}

/// One scene.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SceneInfo {
    /// Its index (`--scene N`).
    pub index: usize,
    /// Its name, if any.
    pub name: Option<String>,
    /// How many nodes it holds, its roots' descendants included.
    pub nodes: usize,
}

/// One camera node of the default scene.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct CameraInfo {
    /// Its index among the scene's cameras (`--camera N`).
    pub index: usize,
    /// The camera node.
    pub node: usize,
    /// The camera's name, else its node's.
    pub name: Option<String>,
    /// `perspective` or `orthographic`.
    pub kind: &'static str,
    /// The vertical field of view in radians (perspective cameras).
    pub yfov: Option<f32>,
}

/// One light node of the default scene.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct LightInfo {
    /// The light's index in the file's KHR_lights_punctual list.
    pub light: usize,
    /// The light node.
    pub node: usize,
    /// The light's name, if any.
    pub name: Option<String>,
    /// `point`, `spot` or `directional`.
    pub kind: &'static str,
}

/// One animation.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct AnimationInfo {
    /// Its index.
    pub index: usize,
    /// Its name, if any.
    pub name: Option<String>,
    /// How many channels it drives.
    pub channels: usize,
    /// Its first and last key times in seconds (the `min` and `max` glTF requires on every
    /// sampler's input accessor); `None` when a sampler lacks them.
    pub start: Option<f32>,
    /// See [`AnimationInfo::start`].
    pub end: Option<f32>,
}

/// The extensions a file uses.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct ExtensionInfo {
    /// Used and read by glint.
    pub read: Vec<String>,
    /// Used but not required, and not read: their effects are missing from renders.
    pub ignored: Vec<String>,
    /// Required but not supported: glint refuses to render the file.
    pub refused: Vec<String>,
}

/// Describes the glTF or GLB file at `path` (its buffers are read as a load reads them, under
/// `options`' budgets and asset root).
pub fn inspect(path: &Path, options: &LoadOptions) -> Result<FileInfo, LoadError> {
    let bytes = super::read_scene_file(path)?;
    let origin = Origin {
        file: path,
        files: Files::Folder(super::base_dir(path)),
        options,
    };
    // The extension lists as written (a load drops the required ones it does not read).
    let extensions = ::gltf::Gltf::from_slice_without_validation(&bytes)
        .map(|g| extension_info(&g.document.into_json()))
        .unwrap_or_default();
    let mut geometry = GeometryBudget::new(options);
    let mut warnings = Vec::new();
    let parsed = source::parse_for_inspection(&bytes, origin, &mut geometry, &mut warnings)?;
    Ok(describe(
        &parsed.document,
        path.display().to_string(),
        extensions,
    ))
}

/// Sorts the root's `extensionsUsed` and `extensionsRequired` by what glint does with them.
fn extension_info(root: &::gltf::json::Root) -> ExtensionInfo {
    let supported = |e: &str| SUPPORTED_EXTENSIONS.contains(&e);
    let required: HashSet<&str> = root
        .extensions_required
        .iter()
        .map(String::as_str)
        .collect();
    let mut info = ExtensionInfo::default();
    let mut seen = HashSet::new();
    for e in root.extensions_used.iter().chain(&root.extensions_required) {
        if !seen.insert(e.as_str()) {
            continue;
        }
        let list = if supported(e) {
            &mut info.read
        } else if required.contains(e.as_str()) {
            &mut info.refused
        } else {
            &mut info.ignored
        };
        list.push(e.clone());
    }
    info
}

fn describe(document: &::gltf::Document, file: String, extensions: ExtensionInfo) -> FileInfo {
    let default_scene = document
        .default_scene()
        .map(|s| s.index())
        .or_else(|| (document.scenes().len() > 0).then_some(0));
    let scenes = document
        .scenes()
        .map(|scene| SceneInfo {
            index: scene.index(),
            name: scene.name().map(str::to_string),
            nodes: scene_nodes(document, scene.index()).len(),
        })
        .collect();
    // Nodes of the default scene (every node, in a file without scenes), in node order.
    let mut nodes: Vec<usize> = match default_scene {
        Some(index) => scene_nodes(document, index),
        None => (0..document.nodes().len()).collect(),
    };
    nodes.sort_unstable();
    let all: Vec<::gltf::Node<'_>> = document.nodes().collect();
    let in_scene = || nodes.iter().filter_map(|&i| all.get(i));
    let cameras = in_scene()
        .filter_map(|node| Some((node, node.camera()?)))
        .enumerate()
        .map(|(index, (node, camera))| {
            let (kind, yfov) = match camera.projection() {
                ::gltf::camera::Projection::Perspective(p) => ("perspective", Some(p.yfov())),
                ::gltf::camera::Projection::Orthographic(_) => ("orthographic", None),
            };
            CameraInfo {
                index,
                node: node.index(),
                name: camera.name().or(node.name()).map(str::to_string),
                kind,
                yfov,
            }
        })
        .collect();
    let lights = in_scene()
        .filter_map(|node| Some((node, node.light()?)))
        .map(|(node, light)| LightInfo {
            light: light.index(),
            node: node.index(),
            name: light.name().map(str::to_string),
            kind: match light.kind() {
                ::gltf::khr_lights_punctual::Kind::Point => "point",
                ::gltf::khr_lights_punctual::Kind::Spot { .. } => "spot",
                ::gltf::khr_lights_punctual::Kind::Directional => "directional",
            },
        })
        .collect();
    let animations = document
        .animations()
        .map(|animation| {
            let mut range: Option<(f32, f32)> = Some((f32::INFINITY, f32::NEG_INFINITY));
            for sampler in animation.samplers() {
                let input = sampler.input();
                let bound = |v: Option<::gltf::json::Value>| {
                    v.and_then(|v| v.get(0).and_then(|x| x.as_f64()))
                        .map(|x| x as f32)
                };
                range = match (range, bound(input.min()), bound(input.max())) {
                    (Some((lo, hi)), Some(a), Some(b)) => Some((lo.min(a), hi.max(b))),
                    _ => None,
                };
            }
            let range = range.filter(|(lo, hi)| lo <= hi);
            AnimationInfo {
                index: animation.index(),
                name: animation.name().map(str::to_string),
                channels: animation.channels().count(),
                start: range.map(|r| r.0),
                end: range.map(|r| r.1),
            }
        })
        .collect();
    let triangles = in_scene()
        .filter_map(|node| Some((node, node.mesh()?)))
        .map(|(node, mesh)| {
            let copies = instance_count(document, node).max(1);
            mesh.primitives()
                .map(primitive_triangles)
                .sum::<u64>()
                .saturating_mul(copies)
        })
        .fold(0u64, u64::saturating_add);
    FileInfo {
        file,
        default_scene,
        scenes,
        cameras,
        lights,
        animations,
        variants: super::variants::names(document),
        extensions,
        triangles,
        meshes: document.meshes().len(),
        materials: document.materials().len(),
        textures: document.textures().len(),
        images: document.images().len(),
    }
}

/// Every node of scene `index`: its roots and their descendants, each once (a node reached
/// twice, which glTF forbids, is counted once).
fn scene_nodes(document: &::gltf::Document, index: usize) -> Vec<usize> {
    let Some(scene) = document.scenes().nth(index) else {
        return Vec::new();
    };
    let mut seen = HashSet::new();
    let mut stack: Vec<::gltf::Node<'_>> = scene.nodes().collect();
    let mut out = Vec::new();
    while let Some(node) = stack.pop() {
        if seen.insert(node.index()) {
            out.push(node.index());
            stack.extend(node.children());
        }
    }
    out
}

/// The triangles one primitive draws, from its accessors' counts.
fn primitive_triangles(primitive: ::gltf::Primitive<'_>) -> u64 {
    use ::gltf::mesh::Mode;
    let elements = match primitive.indices() {
        Some(indices) => indices.count(),
        None => primitive
            .get(&::gltf::Semantic::Positions)
            .map_or(0, |p| p.count()),
    } as u64;
    match primitive.mode() {
        Mode::Triangles => elements / 3,
        Mode::TriangleStrip | Mode::TriangleFan => elements.saturating_sub(2),
        _ => 0,
    }
}

/// The copies EXT_mesh_gpu_instancing draws of `node` (0 without the extension): the count of
/// its first attribute's accessor.
fn instance_count(document: &::gltf::Document, node: &::gltf::Node<'_>) -> u64 {
    node.extension_value("EXT_mesh_gpu_instancing")
        .and_then(|ext| {
            let attributes = ext.get("attributes")?.as_object()?;
            let accessor = usize::try_from(attributes.values().next()?.as_u64()?).ok()?;
            document.accessors().nth(accessor).map(|a| a.count() as u64)
        })
        .unwrap_or(0)
}
