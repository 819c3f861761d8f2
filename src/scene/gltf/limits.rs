//! What the loader accepts: where external files may come from, how big textures may be, and
//! which magnitudes a scene may hold. Everything here is checked before the memory or the
//! ray-query structure is committed to it.

use super::LoadError;
use super::source::Origin;
use crate::scene::{Light, Projection, Scene};
use std::path::PathBuf;

/// Default per-image texel budget: 8192 × 8192 texels (1 GiB as linear RGBA f32).
pub const DEFAULT_MAX_TEXTURE_PIXELS: u64 = 8192 * 8192;

/// Default geometry budget: 4 GiB of decoded vertices and indices per scene (about 50 million
/// vertices at [`GEOMETRY_BYTES_PER_VERTEX`]).
pub const DEFAULT_MAX_GEOMETRY_BYTES: u64 = 4 << 30;

/// What one vertex of a built mesh may cost, for the geometry budget: position, normal,
/// tangent, two texture coordinate sets and a colour (12 + 12 + 16 + 8 + 8 + 16 bytes).
pub const GEOMETRY_BYTES_PER_VERTEX: u64 = 72;

/// What one index of a built mesh costs (u32).
pub const GEOMETRY_BYTES_PER_INDEX: u64 = 4;

/// Largest coordinate magnitude a scene may hold (positions, camera and light positions,
/// orthographic extents): the ray queries' limit, [`crate::accel::MAX_COORDINATE`] (2^40).
pub const MAX_COORDINATE: f32 = crate::accel::MAX_COORDINATE;

/// Largest emitted quantity a material or light may carry (radiance in W/(sr·m²), intensity in
/// W/sr, irradiance in W/m²): 1e20. Sums of a few billion samples of it stay finite in f32
/// (3.4e38), so no pixel becomes infinite.
pub const MAX_EMISSION: f32 = 1e20;

/// Least number of bytes an accessor without a buffer view may always expand to (1 MiB:
/// 87,381 zeroed VEC3 floats), whatever the size of the file's buffers. Above it such an
/// accessor may expand to at most as many bytes as the file's buffers hold: its elements cost
/// nothing in the file, and a sane one mirrors data that is in the buffers (a sparse morph
/// target has as many elements as the POSITION it displaces).
pub const VIEWLESS_ACCESSOR_FLOOR_BYTES: usize = 1 << 20;

/// Options of a load: the asset root and the size budgets.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LoadOptions {
    /// When set, every external file a glTF refers to must resolve (after following symbolic
    /// links) inside this folder, or the load fails naming the URI. When unset, relative URIs
    /// (`../` included) resolve against the scene's folder.
    /// In both cases absolute paths and non-regular files (devices, FIFOs, sockets) are refused.
    pub asset_root: Option<PathBuf>,
    /// Most texels one texture image may have; its header is read and checked before it is
    /// decoded.
    pub max_texture_pixels: u64,
    /// Most bytes of geometry a scene may decode and build: compressed buffer views
    /// (EXT_meshopt_compression) and Draco primitives as declared, and each primitive's
    /// vertices and indices as they will be built (skinned and morphed copies included),
    /// checked before the memory is allocated.
    pub max_geometry_bytes: u64,
}

impl Default for LoadOptions {
    fn default() -> Self {
        Self {
            asset_root: None,
            max_texture_pixels: DEFAULT_MAX_TEXTURE_PIXELS,
            max_geometry_bytes: DEFAULT_MAX_GEOMETRY_BYTES,
        }
    }
}

impl LoadOptions {
    /// Most texels all the scene's texture images together may have: four images at the
    /// per-image limit (4 GiB at the default), so that many small but highly compressible
    /// files cannot add up to an out-of-memory kill.
    pub fn max_total_texture_pixels(&self) -> u64 {
        self.max_texture_pixels.saturating_mul(4)
    }
}

/// Refuses a scene whose geometry, cameras or lights lie beyond [`MAX_COORDINATE`] (f32 rays
/// there lose all precision, and Embree aborts on them), or whose lights emit more than
/// [`MAX_EMISSION`]. Called on the finished scene, before any ray-query structure is built.
pub fn check_scene(scene: &Scene, origin: Origin<'_>) -> Result<(), LoadError> {
    let far = |v: glam::Vec3| v.is_nan() || v.abs().max_element() > MAX_COORDINATE;
    let fail = |what: &str, problem: String| LoadError::Node {
        path: origin.file.to_path_buf(),
        what: what.to_string(),
        problem,
    };
    for mesh in &scene.meshes {
        if !mesh.instances.is_empty()
            && let Some((lo, hi)) = mesh.world_bounds()
            && (far(lo) || far(hi))
        {
            return Err(LoadError::Primitive {
                path: origin.file.to_path_buf(),
                primitive: mesh.name.clone(),
                problem: format!(
                    "its copies reach {lo} .. {hi}, beyond ±{MAX_COORDINATE:e} where f32 rays lose all \
                     precision (scale the scene down or fix the node or instance transforms)"
                ),
            });
        }
        if let Some((vertex, p)) = mesh.positions.iter().enumerate().find(|(_, p)| far(**p)) {
            return Err(LoadError::Primitive {
                path: origin.file.to_path_buf(),
                primitive: mesh.name.clone(),
                problem: format!(
                    "world-space vertex {vertex} is at {p}, beyond ±{MAX_COORDINATE:e} where f32 rays lose \
                     all precision (scale the scene down or fix the node transforms)"
                ),
            });
        }
    }
    for camera in &scene.cameras {
        let position = camera.world_from_camera.w_axis.truncate();
        if far(position) {
            return Err(fail(
                &camera.name,
                format!(
                    "the camera is at {position}, beyond ±{MAX_COORDINATE:e} where f32 rays lose all \
                     precision (move it or scale the scene down)"
                ),
            ));
        }
        if let Projection::Orthographic { xmag, ymag } = camera.projection
            && !(xmag.abs() <= MAX_COORDINATE && ymag.abs() <= MAX_COORDINATE)
        {
            return Err(fail(
                &camera.name,
                format!("xmag {xmag} / ymag {ymag} exceed ±{MAX_COORDINATE:e}"),
            ));
        }
    }
    for (index, light) in scene.lights.iter().enumerate() {
        let (position, emitted) = match light {
            Light::Point {
                position,
                intensity,
                ..
            }
            | Light::Spot {
                position,
                intensity,
                ..
            } => (Some(*position), *intensity),
            Light::Directional { irradiance, .. } => (None, *irradiance),
            #[allow(unreachable_patterns)]
            _ => continue,
        };
        let what = format!("light {index}");
        if let Some(position) = position
            && far(position)
        {
            return Err(fail(
                &what,
                format!("the light is at {position}, beyond ±{MAX_COORDINATE:e}"),
            ));
        }
        if emitted.is_nan() || emitted.max_element() > MAX_EMISSION {
            return Err(fail(
                &what,
                format!(
                    "intensity × color is {emitted}, above {MAX_EMISSION:e}; sums of such samples overflow \
                     (fix the light's intensity)"
                ),
            ));
        }
    }
    Ok(())
}

/// A material factor clamped to `[lo, hi]`, with a warning naming the material when it was
/// outside (NaN becomes `lo`).
pub fn clamp_factor(
    value: f32,
    lo: f32,
    hi: f32,
    what: &str,
    origin: Origin<'_>,
    warnings: &mut Vec<String>,
) -> f32 {
    if value >= lo && value <= hi {
        return value;
    }
    let clamped = if value > hi { hi } else { lo };
    warnings.push(format!(
        "{}: {what} is {value}, outside [{lo}, {hi}]; clamped to {clamped}",
        origin.file.display()
    ));
    clamped
}

/// The geometry a load has committed to so far, against [`LoadOptions::max_geometry_bytes`].
#[derive(Debug)]
pub struct GeometryBudget {
    limit: u64,
    spent: u64,
}

impl GeometryBudget {
    /// A budget of `options.max_geometry_bytes`, nothing spent.
    pub fn new(options: &LoadOptions) -> Self {
        Self {
            limit: options.max_geometry_bytes,
            spent: 0,
        }
    }

    /// Bytes still available.
    pub fn left(&self) -> u64 {
        self.limit.saturating_sub(self.spent)
    }

    /// Commits `bytes` for `what` (`buffer view 3 (EXT_meshopt_compression)`), or refuses
    /// before anything is allocated when they do not fit.
    pub fn charge(&mut self, bytes: u64, what: &str, origin: Origin<'_>) -> Result<(), LoadError> {
        if bytes > self.left() {
            return Err(LoadError::Data {
                path: origin.file.to_path_buf(),
                what: what.to_string(),
                problem: format!(
                    "needs {bytes} bytes of geometry, more than the {} left of the scene's geometry \
                     budget of {} bytes (raise --max-geometry-bytes if the scene is real)",
                    self.left(),
                    self.limit
                ),
            });
        }
        self.spent += bytes;
        Ok(())
    }
}
