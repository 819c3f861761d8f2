//! Ray queries: one trait, two interchangeable backends.
//!
//! - [`embree`]: Intel Embree through the C shim in `ffi/` (feature `embree`, the default).
//! - [`bvh`]: a pure-Rust compressed-wide BVH from the `obvhs` crate.
//!
//! Both answer the same two questions over the same triangles: the closest hit in
//! `[tnear, tfar]`, and whether anything at all lies in `[tnear, tfar]` (shadow rays). Geometry
//! id `g` is the index of the mesh in the slice given to [`build`]; primitive id `p` is the
//! triangle's index within that mesh; for a mesh with [`Placement`]s, [`Hit::instance`] says
//! which copy was hit. The geometric normal follows glTF's winding, in world space:
//! `normalize((v1 - v0) × (v2 - v0))`, front face counter-clockwise (for a placed mesh, the
//! object-space normal carried to world space, so a mirroring placement keeps its front side).

// One of the two modules allowed `unsafe`: the Embree FFI wrapper (the other is OIDN's device
// set-up, `denoise::oidn_cpu`; the crate denies it elsewhere).
#[cfg(feature = "embree")]
#[allow(unsafe_code)]
pub mod embree;

pub mod bvh;
pub mod instance;
pub mod kernels;
mod triangle;

pub use instance::Placement;
pub use kernels::EmbreeIsa;

use glam::Vec3;
use std::fmt;
use std::str::FromStr;

/// A ray with its parametric interval. `dir` need not be normalised; `t` is in units of `dir`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Origin.
    pub origin: Vec3,
    /// Direction (any non-zero length).
    pub dir: Vec3,
    /// Smallest accepted hit distance.
    pub tnear: f32,
    /// Largest accepted hit distance.
    pub tfar: f32,
}

impl Ray {
    /// A ray over `[0, ∞)`.
    #[inline]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self {
            origin,
            dir,
            tnear: 0.0,
            tfar: f32::INFINITY,
        }
    }

    /// A ray over `[tnear, tfar]`.
    #[inline]
    pub fn segment(origin: Vec3, dir: Vec3, tnear: f32, tfar: f32) -> Self {
        Self {
            origin,
            dir,
            tnear,
            tfar,
        }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

/// The closest hit along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the ray, in units of `Ray::dir`.
    pub t: f32,
    /// Index of the mesh given to [`build`].
    pub geom_id: u32,
    /// Index of the triangle within that mesh.
    pub prim_id: u32,
    /// Which of the mesh's placements was hit (0 for a mesh without placements).
    pub instance: u32,
    /// Barycentric weight of the triangle's second vertex.
    pub u: f32,
    /// Barycentric weight of the triangle's third vertex.
    pub v: f32,
    /// Unit geometric normal in world space, `normalize((v1 - v0) × (v2 - v0))` (object-space
    /// vertices for a placed mesh, the normal then carried to world space).
    pub ng: Vec3,
}

/// Triangles borrowed while a backend builds its acceleration structure. Backends copy what
/// they need; the mesh may be dropped after [`build`].
#[derive(Clone, Copy, Debug, Default)]
pub struct TriangleMesh<'a> {
    /// Vertex positions: world space without placements, object space with them.
    pub positions: &'a [Vec3],
    /// Vertex indices, three per triangle.
    pub indices: &'a [[u32; 3]],
    /// Where the mesh is drawn. Empty: once, as given (world space). Otherwise once per
    /// placement, from one shared structure (a two-level scene).
    pub instances: &'a [Placement],
}

impl TriangleMesh<'_> {
    /// Triangles drawn: the mesh's count times its copies.
    pub fn drawn_triangles(&self) -> usize {
        self.indices.len() * self.instances.len().max(1)
    }
}

/// Which backend answers the ray queries. Serialised (bench reports) as its command-line name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum BackendKind {
    /// Intel Embree (needs the `embree` feature).
    #[cfg_attr(feature = "embree", default)]
    Embree,
    /// The pure-Rust obvhs CWBVH.
    #[cfg_attr(not(feature = "embree"), default)]
    Bvh,
}

impl BackendKind {
    /// Every backend compiled into this build.
    pub fn available() -> &'static [BackendKind] {
        #[cfg(feature = "embree")]
        {
            &[BackendKind::Embree, BackendKind::Bvh]
        }
        #[cfg(not(feature = "embree"))]
        {
            &[BackendKind::Bvh]
        }
    }

    /// Sets up the calling thread for tracing rays with this backend; render pools call it
    /// from each worker's start handler. Embree asks for flush-to-zero and
    /// denormals-are-zero on every thread that traces; the BVH needs nothing.
    pub fn prepare_worker_thread(self) {
        #[cfg(feature = "embree")]
        if self == BackendKind::Embree {
            embree::set_denormal_modes();
        }
    }

    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            BackendKind::Embree => "embree",
            BackendKind::Bvh => "bvh",
        }
    }
}

impl fmt::Display for BackendKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for BackendKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "embree" => Ok(BackendKind::Embree),
            "bvh" | "obvhs" => Ok(BackendKind::Bvh),
            other => Err(format!(
                "unknown backend '{other}' (expected embree or bvh)"
            )),
        }
    }
}

/// How much time to spend building the acceleration structure, for faster queries.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum BuildQuality {
    /// Fastest build (Embree LOW, obvhs `fast_build`).
    Low,
    /// The default (Embree MEDIUM, obvhs `medium_build`).
    #[default]
    Medium,
    /// Best trees (Embree HIGH with spatial splits, obvhs `very_slow_build`).
    High,
}

impl BuildQuality {
    /// All qualities, fastest build first.
    pub const ALL: [BuildQuality; 3] =
        [BuildQuality::Low, BuildQuality::Medium, BuildQuality::High];

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            BuildQuality::Low => "low",
            BuildQuality::Medium => "medium",
            BuildQuality::High => "high",
        }
    }
}

impl FromStr for BuildQuality {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "low" => Ok(BuildQuality::Low),
            "medium" => Ok(BuildQuality::Medium),
            "high" => Ok(BuildQuality::High),
            other => Err(format!(
                "unknown build quality '{other}' (expected low, medium or high)"
            )),
        }
    }
}

/// Settings for building an acceleration structure.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct BuildOptions {
    /// Build effort.
    pub quality: BuildQuality,
    /// Embree's robust mode (`RTC_SCENE_FLAG_ROBUST`): watertight traversal at some speed cost.
    /// obvhs has no such switch and ignores it.
    pub robust: bool,
    /// Which of Embree's kernels to use ([`kernels`]); `None`: the process's choice
    /// (`--embree-isa`, `GLINT_EMBREE_ISA`, else Embree's own). obvhs ignores it.
    pub embree_isa: Option<EmbreeIsa>,
}

/// Whether a batch of rays is coherent (camera rays of neighbouring pixels) or not (bounces).
/// Embree tunes its traversal with this hint; it never changes the answers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Coherence {
    /// Rays share origin and nearly share direction.
    Coherent,
    /// Rays go anywhere.
    #[default]
    Incoherent,
}

/// Errors from building an acceleration structure.
#[derive(Debug, thiserror::Error)]
pub enum AccelError {
    /// The Embree device could not be created.
    #[error("could not start Embree: {0}")]
    Device(String),
    /// Embree reported an error.
    #[error("Embree error {code}: {message}")]
    Embree {
        /// Embree's RTCError code.
        code: i32,
        /// Embree's message.
        message: String,
    },
    /// The backend is not compiled into this build.
    #[error("the {0} backend is not built into this glint (rebuild with the `embree` feature)")]
    Unavailable(BackendKind),
    /// The input geometry is unusable.
    #[error("invalid geometry in mesh {mesh}: {reason}")]
    InvalidGeometry {
        /// Mesh index.
        mesh: usize,
        /// What is wrong.
        reason: String,
    },
}

/// A built acceleration structure that answers ray queries. Thread-safe: queries may run from
/// any number of threads at once.
pub trait Accel: Send + Sync {
    /// Which backend this is.
    fn kind(&self) -> BackendKind;

    /// Closest hit of one ray in `[tnear, tfar]`.
    fn intersect(&self, ray: &Ray) -> Option<Hit>;

    /// Whether anything lies in `[tnear, tfar]` (any hit; for shadow rays).
    fn occluded(&self, ray: &Ray) -> bool;

    /// Closest hits of many rays. Backends override this with packet or stream traversal where
    /// it pays; the answers equal those of [`Accel::intersect`].
    fn intersect_many(&self, rays: &[Ray], hits: &mut [Option<Hit>], coherence: Coherence) {
        let _ = coherence;
        for (ray, hit) in rays.iter().zip(hits.iter_mut()) {
            *hit = self.intersect(ray);
        }
    }

    /// Occlusion of many rays; the answers equal those of [`Accel::occluded`].
    fn occluded_many(&self, rays: &[Ray], occluded: &mut [bool], coherence: Coherence) {
        let _ = coherence;
        for (ray, out) in rays.iter().zip(occluded.iter_mut()) {
            *out = self.occluded(ray);
        }
    }

    /// Every hit of `ray` in `[tnear, tfar]`: an any-hit walk that never stops, for amodal
    /// masks (every object a camera ray pierces, hidden or not). `out` is cleared, then holds
    /// each hit triangle copy once, in increasing `t` (ties by geometry, copy, primitive), with
    /// the same `t`, `u`, `v` and normal [`Accel::intersect`] would report for it.
    fn all_hits(&self, ray: &Ray, out: &mut Vec<Hit>);

    /// Number of triangles the structure answers for (each placed copy counted).
    fn triangle_count(&self) -> usize;

    /// Bytes the structure holds (nodes, triangles, ids, instance tables), where the backend
    /// can tell; for benchmarks.
    fn memory_bytes(&self) -> Option<usize> {
        None
    }

    /// The code that answers the queries, for outputs that record it (partial EXRs): the
    /// backend, and for Embree its version and kernels (`embree 3.13.5 sse4.2`, `embree
    /// 3.13.5 native (avx2)`). Two renders whose labels are equal used the same arithmetic.
    fn kernels(&self) -> String {
        self.kind().name().to_string()
    }

    /// The Embree backend itself, for callers that reach its single-ray and 8-wide packet
    /// entry points, which this trait hides (the benchmarks compare them); `None` for every
    /// other backend.
    #[cfg(feature = "embree")]
    fn as_embree(&self) -> Option<&embree::EmbreeAccel> {
        None
    }
}

/// Every ray-query configuration this build can run on this CPU, with default build settings
/// otherwise: Embree with its native kernels, Embree pinned to each instruction set the CPU
/// supports ([`EmbreeIsa::supported`]), then obvhs. Embree's kernels round differently, so a
/// test that loops over these catches a kernel-dependent assumption on any machine, not only
/// on the machines whose kernels expose it.
pub fn every_configuration() -> Vec<(BackendKind, BuildOptions)> {
    let mut out = Vec::new();
    if BackendKind::available().contains(&BackendKind::Embree) {
        for isa in std::iter::once(EmbreeIsa::Native).chain(EmbreeIsa::supported()) {
            let options = BuildOptions {
                embree_isa: Some(isa),
                ..BuildOptions::default()
            };
            out.push((BackendKind::Embree, options));
        }
    }
    out.push((BackendKind::Bvh, BuildOptions::default()));
    out
}

/// A short name for a configuration from [`every_configuration`]: `embree/sse4.2`, `bvh`.
pub fn configuration_label(kind: BackendKind, options: &BuildOptions) -> String {
    match (kind, options.embree_isa) {
        (BackendKind::Embree, Some(isa)) => format!("embree/{isa}"),
        (kind, _) => kind.name().to_string(),
    }
}

/// Builds the chosen backend over `meshes`, after [`validate`] has checked them.
pub fn build(
    kind: BackendKind,
    meshes: &[TriangleMesh<'_>],
    options: BuildOptions,
) -> Result<Box<dyn Accel>, AccelError> {
    validate(meshes)?;
    build_validated(kind, meshes, options)
}

/// [`build`] without its [`validate`] pass, for callers that have validated `meshes` already
/// (the benchmarks, which time the build alone): the one place that picks a backend's type.
pub fn build_validated(
    kind: BackendKind,
    meshes: &[TriangleMesh<'_>],
    options: BuildOptions,
) -> Result<Box<dyn Accel>, AccelError> {
    match kind {
        #[cfg(feature = "embree")]
        BackendKind::Embree => Ok(Box::new(embree::EmbreeAccel::build(meshes, options)?)),
        #[cfg(not(feature = "embree"))]
        BackendKind::Embree => Err(AccelError::Unavailable(BackendKind::Embree)),
        BackendKind::Bvh => Ok(Box::new(bvh::BvhAccel::build(meshes, options))),
    }
}

/// Largest coordinate magnitude [`build`] accepts (and the glTF loader, which refuses scenes
/// beyond it): 2^40 ≈ 1.1e12. Beyond it an f32 has a spacing of 2^17 or more, so a ray
/// starting there cannot resolve anything smaller than a 100-km step, and Embree rejects rays
/// whose origin exceeds ~1.8e18 outright (an assertion that aborts the process).
pub const MAX_COORDINATE: f32 = (1u64 << 40) as f32;

/// Rejects input that would make either backend misbehave: out-of-range indices, non-finite
/// positions. Catching it here keeps both backends' behaviour identical and defined. [`build`]
/// calls it; callers that build a backend directly (`EmbreeAccel::build`, `BvhAccel::build`)
/// must call it first.
pub fn validate(meshes: &[TriangleMesh<'_>]) -> Result<(), AccelError> {
    for (mesh_index, mesh) in meshes.iter().enumerate() {
        let n = mesh.positions.len();
        if let Some(bad) = mesh.positions.iter().position(|p| !p.is_finite()) {
            return Err(AccelError::InvalidGeometry {
                mesh: mesh_index,
                reason: format!("vertex {bad} has a non-finite position"),
            });
        }
        // Finite but huge coordinates overflow inside the builders (obvhs indexes out of
        // bounds) and give rays Embree rejects with an abort; the loader refuses them with a
        // better message, this keeps every other caller safe too.
        if let Some(bad) = mesh
            .positions
            .iter()
            .position(|p| p.abs().max_element() > MAX_COORDINATE)
        {
            return Err(AccelError::InvalidGeometry {
                mesh: mesh_index,
                reason: format!(
                    "vertex {bad} lies beyond ±{MAX_COORDINATE:e}, where f32 rays lose all precision"
                ),
            });
        }
        if let Some((tri, _)) = mesh
            .indices
            .iter()
            .enumerate()
            .find(|(_, t)| t.iter().any(|&i| i as usize >= n))
        {
            return Err(AccelError::InvalidGeometry {
                mesh: mesh_index,
                reason: format!("triangle {tri} indexes past the {n} vertices"),
            });
        }
    }
    Ok(())
}

/// Barycentric coordinates `(u, v)` of the point where `ray` meets the plane of the triangle,
/// with `u` the weight of `v1` and `v` of `v2`; `None` for a ray parallel to it.
#[inline]
pub fn barycentrics(ray: &Ray, v0: Vec3, v1: Vec3, v2: Vec3) -> Option<(f32, f32)> {
    let e1 = v1 - v0;
    let e2 = v2 - v0;
    let p = ray.dir.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 {
        return None;
    }
    let inv = 1.0 / det;
    let s = ray.origin - v0;
    let u = s.dot(p) * inv;
    let q = s.cross(e1);
    let v = ray.dir.dot(q) * inv;
    Some((u, v))
}

/// Unit geometric normal of a triangle in glTF's winding; zero for a degenerate triangle.
#[inline]
pub fn triangle_normal(v0: Vec3, v1: Vec3, v2: Vec3) -> Vec3 {
    (v1 - v0).cross(v2 - v0).normalize_or_zero()
}

/// Puts the hits of [`Accel::all_hits`] in their documented order and drops repeats of one
/// triangle copy (a triangle that spatial splits reference from several leaves).
pub(crate) fn order_all_hits(out: &mut Vec<Hit>) {
    let key = |h: &Hit| (h.geom_id, h.instance, h.prim_id);
    out.sort_by(|a, b| a.t.total_cmp(&b.t).then(key(a).cmp(&key(b))));
    let mut seen = std::collections::HashSet::with_capacity(out.len());
    out.retain(|h| seen.insert(key(h)));
}
