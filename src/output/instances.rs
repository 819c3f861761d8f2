//! Per-instance annotations of a render, as the camera sidecar ([`super::sidecar`], its
//! `instances`) carries them: one entry per
//! instance (a glTF node that draws a mesh; a mesh several nodes share is one instance per
//! node; the copies of one EXT_mesh_gpu_instancing node share its node and so its entry) that
//! some camera sample's ray meets.
//!
//! Everything comes from exact sample counts ([`InstanceSamples`]): in pixel `p` with `n`
//! samples, instance `i`'s visible coverage is `c_vis(i, p) / n` (the samples whose first
//! accepted hit is on `i`) and its amodal coverage `c_amo(i, p) / n` (the samples whose ray
//! pierces `i`, [`crate::render::amodal`]), so amodal ≥ visible in every pixel.
//! - visible mask: pixels with visible coverage ≥ 0.5 (`2·c_vis ≥ n`, in integers);
//!   visible area: the sum of visible coverage (pixels, fractional);
//! - amodal mask: pixels with amodal coverage ≥ 0.5, united with the visible mask; amodal
//!   area: the sum of amodal coverage;
//! - visible fraction: visible area / amodal area (in [0, 1]);
//! - boxes: COCO's `[x, y, width, height]` in pixels, pixel `(i, j)` covering
//!   `[i, i + 1) × [j, j + 1)`, the tight box of the mask (`None` for an empty mask);
//! - the 3D box: the instance's vertices' axis-aligned box in its node's frame, with the
//!   world-from-node transform and the box's 8 corners carried to world space.
//!
//! Category: the job's mapping for the node's name, else for its mesh's name (`--category
//! NAME=CATEGORY`), else the node's `extras.category`, else the mesh's name, else the node's
//! name, else `mesh M`.

use super::rle::Rle;
use crate::render::amodal::InstanceSamples;
use crate::render::ids::{self, NO_ID};
use crate::scene::Scene;
use glam::{Mat4, Vec3};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// One instance's annotations.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct InstanceAnnotation {
    /// The instance ID: the glTF node index (the `instance_id` and `coverage` AOVs' ID).
    pub id: u32,
    /// The node's name.
    pub node_name: Option<String>,
    /// The glTF mesh index the node draws (`None` for meshes made in code).
    pub mesh: Option<u32>,
    /// The mesh's name.
    pub mesh_name: Option<String>,
    /// The material indices of the instance's primitives (glint's default material last).
    pub materials: Vec<u32>,
    /// Their names (empty strings for unnamed materials).
    pub material_names: Vec<String>,
    /// The category (see the module documentation).
    pub category: String,
    /// What the camera sees of it.
    pub visible: Region,
    /// Its whole silhouette, as if nothing hid it.
    pub amodal: Region,
    /// `visible.area / amodal.area`, in [0, 1].
    pub visible_fraction: f64,
    /// Its 3D bounding box.
    pub box_3d: Box3d,
}

/// A mask with its exact area and box.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Region {
    /// The sum of the coverage over all pixels, in pixels (fractional).
    pub area: f64,
    /// The mask, COCO's compressed RLE.
    pub mask: Rle,
    /// Set pixels in the mask.
    pub mask_pixels: u64,
    /// The mask's tight box `[x, y, width, height]`; `None` when the mask is empty.
    pub bbox: Option<[f64; 4]>,
}

/// An instance's 3D box.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Box3d {
    /// The box's smallest corner in the node's frame.
    pub object_min: [f64; 3],
    /// The box's largest corner in the node's frame.
    pub object_max: [f64; 3],
    /// World from node, rows of a 4 × 4 matrix.
    pub world_from_object: [[f64; 4]; 4],
    /// The 8 corners in world space; corner `k` takes x from `object_max` when bit 0 of `k` is
    /// set (else `object_min`), y by bit 1, z by bit 2.
    pub world_corners: [[f64; 3]; 8],
}

/// Per-instance sums gathered over the image.
#[derive(Default)]
struct Gather {
    visible_area: f64,
    amodal_area: f64,
    /// Column-major indices of mask pixels.
    visible: Vec<u64>,
    amodal: Vec<u64>,
}

/// What the scene says about one instance: its materials and its box in the node's frame.
struct Geometry {
    materials: Vec<u32>,
    lo: Vec3,
    hi: Vec3,
}

/// The annotations of every instance that some camera sample's ray meets (amodal area > 0),
/// by increasing ID. `categories` maps node or mesh names to categories (the job's mapping).
pub fn annotate(
    scene: &Scene,
    samples: &InstanceSamples,
    categories: &BTreeMap<String, String>,
) -> Vec<InstanceAnnotation> {
    let (width, height) = (samples.width, samples.height);
    let mut gathered: BTreeMap<u32, Gather> = BTreeMap::new();
    // Pixels in column-major order, so that every mask's indices arrive sorted.
    for x in 0..width {
        for y in 0..height {
            let index = y as usize * width as usize + x as usize;
            let n = samples.samples(index);
            let (Some(visible), Some(amodal)) =
                (samples.visible.get(index), samples.amodal.get(index))
            else {
                continue;
            };
            if n == 0 {
                continue;
            }
            let column_major = u64::from(x) * u64::from(height) + u64::from(y);
            for &(id, c_amo) in amodal {
                if id == NO_ID {
                    continue;
                }
                let c_vis = u64::from(InstanceSamples::count_of(visible, id));
                let c_amo = u64::from(c_amo).max(c_vis);
                let g = gathered.entry(id).or_default();
                g.visible_area += c_vis as f64 / n as f64;
                g.amodal_area += c_amo as f64 / n as f64;
                let in_visible = c_vis > 0 && 2 * c_vis >= n;
                if in_visible {
                    g.visible.push(column_major);
                }
                if in_visible || 2 * c_amo >= n {
                    g.amodal.push(column_major);
                }
            }
        }
    }
    let geometry = geometry_of(scene, &gathered);
    gathered
        .into_iter()
        .filter(|(_, g)| g.amodal_area > 0.0)
        .map(|(id, g)| {
            let info = scene.nodes.get(id as usize).and_then(Option::as_ref);
            let node_name = info.and_then(|i| i.name.clone());
            let mesh_name = info.and_then(|i| i.mesh_name.clone());
            let category = [&node_name, &mesh_name]
                .into_iter()
                .flatten()
                .find_map(|name| categories.get(name).cloned())
                .or_else(|| info.and_then(|i| i.category.clone()))
                .or_else(|| mesh_name.clone())
                .or_else(|| node_name.clone())
                .unwrap_or_else(|| format!("mesh {}", info.map_or(id, |i| i.mesh)));
            let world_from_node = info.map_or(Mat4::IDENTITY, |i| i.world_from_node);
            let geom = geometry.get(&id);
            let materials = geom.map(|g| g.materials.clone()).unwrap_or_default();
            let material_names = materials
                .iter()
                .map(|&m| {
                    scene
                        .materials
                        .get(m as usize)
                        .map(|m| m.name.clone())
                        .unwrap_or_default()
                })
                .collect();
            let (lo, hi) = geom.map_or((Vec3::ZERO, Vec3::ZERO), |g| (g.lo, g.hi));
            let visible_fraction = if g.amodal_area > 0.0 {
                (g.visible_area / g.amodal_area).min(1.0)
            } else {
                0.0
            };
            InstanceAnnotation {
                id,
                node_name,
                mesh: info.map(|i| i.mesh),
                mesh_name,
                materials,
                material_names,
                category,
                visible: region(width, height, g.visible_area, &g.visible),
                amodal: region(width, height, g.amodal_area, &g.amodal),
                visible_fraction,
                box_3d: box_3d(lo, hi, world_from_node),
            }
        })
        .collect()
}

/// A mask's region from its column-major pixels (sorted).
fn region(width: u32, height: u32, area: f64, pixels: &[u64]) -> Region {
    let h = u64::from(height.max(1));
    let bbox = pixels.first().map(|_| {
        let (mut x0, mut y0, mut x1, mut y1) = (u64::MAX, u64::MAX, 0, 0);
        for &p in pixels {
            let (x, y) = (p / h, p % h);
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
        [
            x0 as f64,
            y0 as f64,
            (x1 + 1 - x0) as f64,
            (y1 + 1 - y0) as f64,
        ]
    });
    Region {
        area,
        mask: Rle::from_column_major(width, height, pixels),
        mask_pixels: pixels.len() as u64,
        bbox,
    }
}

/// The materials and node-frame boxes of the instances in `wanted`.
fn geometry_of<T>(scene: &Scene, wanted: &BTreeMap<u32, T>) -> BTreeMap<u32, Geometry> {
    let mut out: BTreeMap<u32, Geometry> = BTreeMap::new();
    for (geom_id, mesh) in scene.meshes.iter().enumerate() {
        for copy in 0..mesh.copies() as u32 {
            let id = ids::instance_id(scene, geom_id as u32, copy);
            if !wanted.contains_key(&id) {
                continue;
            }
            let node_from_world = scene
                .nodes
                .get(id as usize)
                .and_then(Option::as_ref)
                .map_or(Mat4::IDENTITY, |i| i.world_from_node.inverse());
            let placement = mesh.placement(copy);
            let entry = out.entry(id).or_insert(Geometry {
                materials: Vec::new(),
                lo: Vec3::INFINITY,
                hi: Vec3::NEG_INFINITY,
            });
            let material = u32::try_from(mesh.material).unwrap_or(NO_ID);
            if !entry.materials.contains(&material) {
                entry.materials.push(material);
                entry.materials.sort_unstable();
            }
            for &p in &mesh.positions {
                let world = placement.map_or(p, |pl| pl.point(p));
                let local = node_from_world.transform_point3(world);
                entry.lo = entry.lo.min(local);
                entry.hi = entry.hi.max(local);
            }
        }
    }
    for g in out.values_mut() {
        if !(g.lo.is_finite() && g.hi.is_finite()) {
            (g.lo, g.hi) = (Vec3::ZERO, Vec3::ZERO);
        }
    }
    out
}

/// The 3D box record of a node-frame box.
fn box_3d(lo: Vec3, hi: Vec3, world_from_node: Mat4) -> Box3d {
    let corner = |k: usize| {
        let pick = |bit: usize, a: f32, b: f32| if k & bit != 0 { b } else { a };
        let local = Vec3::new(
            pick(1, lo.x, hi.x),
            pick(2, lo.y, hi.y),
            pick(4, lo.z, hi.z),
        );
        world_from_node
            .transform_point3(local)
            .as_dvec3()
            .to_array()
    };
    let rows = world_from_node.transpose().to_cols_array_2d();
    Box3d {
        object_min: lo.as_dvec3().to_array(),
        object_max: hi.as_dvec3().to_array(),
        world_from_object: rows.map(|r| r.map(f64::from)),
        world_corners: std::array::from_fn(corner),
    }
}
