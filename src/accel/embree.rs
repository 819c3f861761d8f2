//! The Embree backend: safe RAII wrappers over glint's C shim (`ffi/shim.h`).
//!
//! This module is the only place in glint with `unsafe`. The invariants it relies on:
//! - Every handle comes from the shim and is released exactly once, in `Drop`.
//! - A committed scene is never modified again, and Embree documents queries on a committed
//!   scene as thread-safe: hence `Send + Sync` for [`EmbreeAccel`], and for nothing else.
//! - Ray and hit buffers passed to the shim are Rust slices of the shim's own plain structs,
//!   with the lengths passed alongside.

use super::kernels::{self, EmbreeIsa};
use super::triangle;
use super::{
    Accel, AccelError, BackendKind, BuildOptions, BuildQuality, Coherence, Hit, Placement, Ray,
    TriangleMesh,
};
use glam::{Vec3, Vec3A};
use std::ffi::CStr;
use std::ptr::NonNull;
use std::sync::Arc;

#[allow(
    non_camel_case_types,
    non_upper_case_globals,
    non_snake_case,
    dead_code,
    unsafe_op_in_unsafe_fn,
    clippy::all
)]
mod ffi {
    include!(concat!(env!("OUT_DIR"), "/shim_bindings.rs"));
}

/// Rays per call into the shim: large enough to amortise the FFI call, small enough to stay on
/// the stack.
const CHUNK: usize = 64;

/// Embree's major version (3 or 4) that this build links.
pub fn embree_major() -> i32 {
    // SAFETY: a pure function of the shim with no arguments.
    unsafe { ffi::glint_embree_major() }
}

/// Embree's version string from the headers the shim was compiled against.
pub fn embree_version() -> String {
    // SAFETY: returns a pointer to a static NUL-terminated string literal.
    unsafe { CStr::from_ptr(ffi::glint_embree_version()) }
        .to_string_lossy()
        .into_owned()
}

/// Number of Embree device, scene and geometry handles alive in this process. Used by the
/// leak tests: building and dropping scenes must bring it back to where it was.
pub fn live_handles() -> i64 {
    // SAFETY: reads an atomic counter.
    unsafe { ffi::glint_live_handles() }
}

/// Sets flush-to-zero and denormals-are-zero on the calling thread, as Embree recommends for
/// every thread that traces rays. Call it from each worker thread's start handler.
pub fn set_denormal_modes() {
    // SAFETY: changes only the calling thread's MXCSR register.
    unsafe { ffi::glint_set_denormal_modes() }
}

/// An Embree device. Shared by the scenes built on it.
pub struct Device {
    raw: NonNull<ffi::glint_device>,
}

// SAFETY: Embree devices may be used from any thread; glint creates scenes on one thread at a
// time (building takes `&mut`-free calls guarded by the scene's own ownership).
unsafe impl Send for Device {}
// SAFETY: the device is only read (scene creation, error polling) after construction; Embree
// documents device functions as thread-safe.
unsafe impl Sync for Device {}

impl Device {
    /// Creates a device with Embree's default configuration.
    pub fn new() -> Result<Self, AccelError> {
        Self::with_config("")
    }

    /// Creates a device with an Embree configuration string (`isa=sse4.2,threads=2`; empty
    /// for the defaults).
    pub fn with_config(config: &str) -> Result<Self, AccelError> {
        let config = std::ffi::CString::new(config)
            .map_err(|_| AccelError::Device("the Embree configuration holds a NUL byte".into()))?;
        // SAFETY: a NUL-terminated string that outlives the call (Embree parses it there).
        let raw = unsafe { ffi::glint_device_new(config.as_ptr()) };
        match NonNull::new(raw) {
            Some(raw) => Ok(Self { raw }),
            None => {
                // SAFETY: returns a thread-local NUL-terminated buffer.
                let why = unsafe { CStr::from_ptr(ffi::glint_last_creation_error()) };
                Err(AccelError::Device(format!(
                    "{} (configuration \"{}\")",
                    why.to_string_lossy(),
                    config.to_string_lossy()
                )))
            }
        }
    }

    /// The widest ray packet this device's kernels run natively (16, 8, 4 or 1): which
    /// instruction set it got, up to SSE2/SSE4.2 and AVX/AVX2.
    pub fn native_packet_width(&self) -> u32 {
        // SAFETY: the device handle is live; the call only reads device properties.
        unsafe { ffi::glint_device_native_packet_width(self.raw.as_ptr()) as u32 }
    }

    /// Takes the first error Embree reported since the last call.
    fn take_error(&self) -> Option<AccelError> {
        let mut buf = [0 as std::ffi::c_char; 512];
        // SAFETY: the buffer and its length are passed together; the shim NUL-terminates it.
        let code =
            unsafe { ffi::glint_device_take_error(self.raw.as_ptr(), buf.as_mut_ptr(), buf.len()) };
        if code == 0 {
            return None;
        }
        // SAFETY: NUL-terminated by the shim.
        let message = unsafe { CStr::from_ptr(buf.as_ptr()) }
            .to_string_lossy()
            .into_owned();
        Some(AccelError::Embree { code, message })
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        // SAFETY: the handle is live and released once; scenes hold their own reference.
        unsafe { ffi::glint_device_free(self.raw.as_ptr()) }
    }
}

/// The process-wide device for `isa`, created on first use: creating a device spins up
/// Embree's thread pool, so sharing one across scenes is what Embree recommends. One device
/// per configuration string (at most one per instruction set the tests loop over).
fn shared_device(isa: EmbreeIsa) -> Result<Arc<Device>, AccelError> {
    use std::sync::Mutex;
    static DEVICES: Mutex<Vec<(String, Arc<Device>)>> = Mutex::new(Vec::new());
    let config = kernels::device_config(isa);
    let mut devices = DEVICES
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some((_, device)) = devices.iter().find(|(c, _)| *c == config) {
        return Ok(Arc::clone(device));
    }
    let device = Device::with_config(&config)?;
    if let Some(expected) = isa.packet_width() {
        let got = device.native_packet_width();
        if got != expected {
            return Err(AccelError::Device(format!(
                "asked Embree for its {isa} kernels (\"{config}\") but the device runs \
                 {got}-wide packets, not {expected}: this Embree library was built without them"
            )));
        }
    }
    let device = Arc::new(device);
    devices.push((config, Arc::clone(&device)));
    Ok(device)
}

/// Bytes Embree holds for all of glint's devices (its memory-monitor callback's running sum).
pub fn memory_bytes() -> i64 {
    // SAFETY: reads an atomic counter.
    unsafe { ffi::glint_memory_bytes() }
}

/// A committed Embree scene of triangle meshes: meshes drawn as given are its own geometries;
/// a mesh with placements is a committed scene of its own ([`EmbreeAccel::children`]), and
/// each placement an instance geometry of it in this scene.
pub struct EmbreeAccel {
    raw: NonNull<ffi::glint_scene>,
    device: Arc<Device>,
    triangles: usize,
    /// What each top-level geometry id names.
    geometries: Vec<TopGeometry>,
    /// The instanced scenes. Declared after `raw`'s owner fields and released after it:
    /// `Drop` frees the top level first, then the fields drop.
    children: Vec<EmbreeAccel>,
    /// Embree's bytes for this structure, read from the memory monitor around the build.
    bytes: i64,
    /// Each mesh's triangles (indexed by glint's geometry id), for [`triangle::refine`]:
    /// Embree decides which triangle a ray hits, glint computes the hit's `t`, `u`, `v` and
    /// normal, the same bits whatever kernel Embree chose (see [`super::triangle`]).
    meshes: Vec<MeshCopy>,
    /// The kernels this structure's device runs.
    isa: EmbreeIsa,
}

/// A copy of one mesh's triangles, in the space Embree holds them in (object space for a
/// placed mesh).
#[derive(Default)]
struct MeshCopy {
    positions: Vec<Vec3>,
    indices: Vec<[u32; 3]>,
}

impl MeshCopy {
    /// The corners of triangle `prim`, `None` if out of range.
    #[inline]
    fn corners(&self, prim: u32) -> Option<[Vec3A; 3]> {
        let tri = self.indices.get(prim as usize)?;
        let corner = |i: u32| self.positions.get(i as usize).map(|&p| Vec3A::from(p));
        Some([corner(tri[0])?, corner(tri[1])?, corner(tri[2])?])
    }

    fn bytes(&self) -> usize {
        self.positions.len() * std::mem::size_of::<Vec3>()
            + self.indices.len() * std::mem::size_of::<[u32; 3]>()
    }
}

/// One geometry of the top-level scene: the mesh it draws, which placement, and its transform.
#[derive(Clone, Copy)]
struct TopGeometry {
    geom_id: u32,
    instance: u32,
    placement: Option<Placement>,
}

// SAFETY: the scene is committed in `build` and never modified afterwards; Embree documents
// rtcIntersect*/rtcOccluded* on a committed scene as safe from any number of threads.
unsafe impl Send for EmbreeAccel {}
// SAFETY: as above: all `&self` methods are read-only queries.
unsafe impl Sync for EmbreeAccel {}

impl EmbreeAccel {
    /// Builds a scene on the process-wide device of the kernels `options` name.
    pub fn build(meshes: &[TriangleMesh<'_>], options: BuildOptions) -> Result<Self, AccelError> {
        let isa = kernels::resolve(options.embree_isa).map_err(AccelError::Device)?;
        let mut accel = Self::build_on(shared_device(isa)?, meshes, options)?;
        accel.isa = isa;
        Ok(accel)
    }

    /// The kernels this structure's queries run.
    pub fn isa(&self) -> EmbreeIsa {
        self.isa
    }

    /// Builds a scene on a given device.
    pub fn build_on(
        device: Arc<Device>,
        meshes: &[TriangleMesh<'_>],
        options: BuildOptions,
    ) -> Result<Self, AccelError> {
        let before = memory_bytes();
        let mut accel = Self::new_scene(device, options)?;
        accel.triangles = meshes.iter().map(TriangleMesh::drawn_triangles).sum();
        accel.meshes = meshes
            .iter()
            .map(|mesh| MeshCopy {
                positions: mesh.positions.to_vec(),
                indices: mesh.indices.to_vec(),
            })
            .collect();
        for (index, mesh) in meshes.iter().enumerate() {
            let geom_id = index as u32;
            if mesh.instances.is_empty() {
                let id = accel.add_triangles(mesh)?;
                accel.record(id, index, geom_id, 0, None)?;
                continue;
            }
            let child = Self::new_scene(Arc::clone(&accel.device), options)?;
            child.add_triangles(mesh)?;
            child.commit()?;
            for (instance, placement) in mesh.instances.iter().enumerate() {
                let m = placement.world_from_object();
                let (x, y, z, w) = (
                    m.matrix3.x_axis,
                    m.matrix3.y_axis,
                    m.matrix3.z_axis,
                    m.translation,
                );
                let xfm = [x.x, x.y, x.z, y.x, y.y, y.z, z.x, z.y, z.z, w.x, w.y, w.z];
                // SAFETY: both scene handles are live, the child is committed and kept alive
                // in `children` for as long as the top level; xfm holds the 12 floats read.
                let id = unsafe {
                    ffi::glint_scene_add_instance(
                        accel.raw.as_ptr(),
                        child.raw.as_ptr(),
                        xfm.as_ptr(),
                    )
                };
                if let Some(err) = accel.device.take_error() {
                    return Err(err);
                }
                accel.record(id, index, geom_id, instance as u32, Some(*placement))?;
            }
            accel.children.push(child);
        }
        accel.commit()?;
        let copies: usize = accel.meshes.iter().map(MeshCopy::bytes).sum();
        accel.bytes = memory_bytes() - before + copies as i64;
        Ok(accel)
    }

    /// An empty, uncommitted scene.
    fn new_scene(device: Arc<Device>, options: BuildOptions) -> Result<Self, AccelError> {
        let quality = match options.quality {
            BuildQuality::Low => ffi::glint_build_quality::GLINT_BUILD_LOW,
            BuildQuality::Medium => ffi::glint_build_quality::GLINT_BUILD_MEDIUM,
            BuildQuality::High => ffi::glint_build_quality::GLINT_BUILD_HIGH,
        };
        // SAFETY: the device handle is live for the call (held by the Arc).
        let raw =
            unsafe { ffi::glint_scene_new(device.raw.as_ptr(), quality, options.robust as i32) };
        let raw = NonNull::new(raw).ok_or_else(|| {
            device
                .take_error()
                .unwrap_or_else(|| AccelError::Device("rtcNewScene failed".into()))
        })?;
        // From here on, Drop releases the scene on every error path.
        Ok(Self {
            raw,
            device,
            triangles: 0,
            geometries: Vec::new(),
            children: Vec::new(),
            bytes: 0,
            meshes: Vec::new(),
            isa: EmbreeIsa::Native,
        })
    }

    /// Adds `mesh`'s triangles as given; returns the geometry id.
    fn add_triangles(&self, mesh: &TriangleMesh<'_>) -> Result<i64, AccelError> {
        // SAFETY: Vec3 is three f32s with no padding (glam's Vec3 is #[repr(C)]) and
        // [u32; 3] is three u32s, so the slices are the packed arrays the shim copies; the
        // counts passed are those of the slices.
        let id = unsafe {
            ffi::glint_scene_add_triangles(
                self.raw.as_ptr(),
                mesh.positions.as_ptr().cast::<f32>(),
                mesh.positions.len(),
                mesh.indices.as_ptr().cast::<u32>(),
                mesh.indices.len(),
            )
        };
        match self.device.take_error() {
            Some(err) => Err(err),
            None => Ok(id),
        }
    }

    /// Records what top-level geometry `id` draws. Embree hands ids out densely from 0 in
    /// attach order, which the table relies on.
    fn record(
        &mut self,
        id: i64,
        mesh: usize,
        geom_id: u32,
        instance: u32,
        placement: Option<Placement>,
    ) -> Result<(), AccelError> {
        let expected = self.geometries.len();
        if id != expected as i64 {
            return Err(AccelError::InvalidGeometry {
                mesh,
                reason: format!("Embree gave geometry id {id}, expected {expected}"),
            });
        }
        self.geometries.push(TopGeometry {
            geom_id,
            instance,
            placement,
        });
        Ok(())
    }

    /// Builds the scene's acceleration structure.
    fn commit(&self) -> Result<(), AccelError> {
        // SAFETY: the scene handle is live; commit builds the BVH.
        let code = unsafe { ffi::glint_scene_commit(self.raw.as_ptr()) };
        if let Some(err) = self.device.take_error() {
            return Err(err);
        }
        if code != 0 {
            return Err(AccelError::Embree {
                code,
                message: "rtcCommitScene failed".into(),
            });
        }
        Ok(())
    }

    /// The hit a raw answer for `ray` describes, in glint's ids and world space, with `t`,
    /// `u`, `v` and the normal computed by glint ([`triangle::refine`]) on the triangle
    /// Embree reported.
    #[inline]
    fn hit_of(&self, ray: &Ray, hit: &ffi::glint_hit) -> Option<Hit> {
        if hit.geom_id == ffi::GLINT_INVALID_ID {
            return None;
        }
        let top = if hit.inst_id == ffi::GLINT_INVALID_ID {
            hit.geom_id
        } else {
            hit.inst_id
        };
        let entry = self.geometries.get(top as usize)?;
        let corners = self
            .meshes
            .get(entry.geom_id as usize)
            .and_then(|mesh| mesh.corners(hit.prim_id));
        let object_ray = match &entry.placement {
            Some(placement) => triangle::to_object(ray, placement),
            None => *ray,
        };
        let (t, u, v, ng) = match corners
            .and_then(|[a, b, c]| Some((triangle::refine(a, b, c, &object_ray)?, [a, b, c])))
        {
            Some(((t, u, v), [a, b, c])) => (t, u, v, triangle::winding_normal(a, b, c)),
            // Parallel to the plane by glint's arithmetic (Embree's own rounding found a
            // hit): keep Embree's answer. Its Ng is (v2 − v0) × (v0 − v1) = (v1 − v0) ×
            // (v2 − v0), glTF's side already, in the object space of an instanced geometry.
            None => (hit.t, hit.u, hit.v, Vec3::from_array(hit.ng)),
        };
        let ng = match &entry.placement {
            Some(placement) => placement.normal(ng),
            None => ng,
        };
        Some(Hit {
            t,
            geom_id: entry.geom_id,
            prim_id: hit.prim_id,
            instance: entry.instance,
            u,
            v,
            ng: ng.normalize_or_zero(),
        })
    }

    /// Closest hits one ray at a time (`rtcIntersect1`), for comparing against packets.
    pub fn intersect_single(&self, rays: &[Ray], hits: &mut [Option<Hit>], coherence: Coherence) {
        self.query_hits(rays, hits, coherence, ffi::glint_intersect1);
    }

    /// Closest hits in packets of 8 (`rtcIntersect8`).
    pub fn intersect_packets(&self, rays: &[Ray], hits: &mut [Option<Hit>], coherence: Coherence) {
        self.query_hits(rays, hits, coherence, ffi::glint_intersect8);
    }

    /// Occlusion one ray at a time (`rtcOccluded1`).
    pub fn occluded_single(&self, rays: &[Ray], out: &mut [bool], coherence: Coherence) {
        self.query_occlusion(rays, out, coherence, ffi::glint_occluded1);
    }

    /// Occlusion in packets of 8 (`rtcOccluded8`).
    pub fn occluded_packets(&self, rays: &[Ray], out: &mut [bool], coherence: Coherence) {
        self.query_occlusion(rays, out, coherence, ffi::glint_occluded8);
    }

    fn query_hits(
        &self,
        rays: &[Ray],
        hits: &mut [Option<Hit>],
        coherence: Coherence,
        query: QueryFn<ffi::glint_hit>,
    ) {
        self.query_chunked(rays, hits, coherence, query, |ray, raw| {
            self.hit_of(ray, raw)
        });
    }

    fn query_occlusion(
        &self,
        rays: &[Ray],
        out: &mut [bool],
        coherence: Coherence,
        query: QueryFn<u8>,
    ) {
        self.query_chunked(rays, out, coherence, query, |_, o| *o != 0);
    }

    /// Runs `query` over `rays` in stack-allocated chunks of [`CHUNK`] and converts each raw
    /// answer into `out`.
    fn query_chunked<Raw: Copy + Default, Out>(
        &self,
        rays: &[Ray],
        out: &mut [Out],
        coherence: Coherence,
        query: QueryFn<Raw>,
        convert: impl Fn(&Ray, &Raw) -> Out,
    ) {
        let coherent = (coherence == Coherence::Coherent) as i32;
        let mut raw_rays = [ffi::glint_ray::default(); CHUNK];
        let mut raw_out = [Raw::default(); CHUNK];
        for (ray_chunk, out_chunk) in rays.chunks(CHUNK).zip(out.chunks_mut(CHUNK)) {
            let n = ray_chunk.len().min(out_chunk.len());
            for (dst, src) in raw_rays.iter_mut().zip(ray_chunk) {
                *dst = to_raw(src);
            }
            // SAFETY: both buffers hold at least n elements; the scene is committed.
            unsafe {
                query(
                    self.raw.as_ptr(),
                    raw_rays.as_ptr(),
                    raw_out.as_mut_ptr(),
                    n,
                    coherent,
                )
            };
            for ((dst, src), ray) in out_chunk.iter_mut().zip(&raw_out[..n]).zip(ray_chunk) {
                *dst = convert(ray, src);
            }
        }
    }
}

/// Hits [`Accel::all_hits`] collects without allocating (a camera ray through a few dozen
/// surfaces); more take a second query into a heap buffer.
const ALL_HITS_ON_STACK: usize = 64;

/// A shim query over `n` rays writing one `Raw` answer per ray.
type QueryFn<Raw> =
    unsafe extern "C" fn(*const ffi::glint_scene, *const ffi::glint_ray, *mut Raw, usize, i32);

impl Drop for EmbreeAccel {
    fn drop(&mut self) {
        // SAFETY: the handle is live and released exactly once.
        unsafe { ffi::glint_scene_free(self.raw.as_ptr()) }
    }
}

#[inline]
fn to_raw(ray: &Ray) -> ffi::glint_ray {
    ffi::glint_ray {
        org: ray.origin.to_array(),
        tnear: ray.tnear,
        dir: ray.dir.to_array(),
        tfar: ray.tfar,
    }
}

impl Accel for EmbreeAccel {
    fn kind(&self) -> BackendKind {
        BackendKind::Embree
    }

    fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let raw_ray = to_raw(ray);
        let mut raw_hit = ffi::glint_hit::default();
        // SAFETY: one ray in, one hit out; the scene is committed.
        unsafe { ffi::glint_intersect1(self.raw.as_ptr(), &raw_ray, &mut raw_hit, 1, 0) };
        self.hit_of(ray, &raw_hit)
    }

    fn occluded(&self, ray: &Ray) -> bool {
        let raw_ray = to_raw(ray);
        let mut out = 0u8;
        // SAFETY: one ray in, one flag out; the scene is committed.
        unsafe { ffi::glint_occluded1(self.raw.as_ptr(), &raw_ray, &mut out, 1, 0) };
        out != 0
    }

    fn intersect_many(&self, rays: &[Ray], hits: &mut [Option<Hit>], coherence: Coherence) {
        self.intersect_packets(rays, hits, coherence);
    }

    fn occluded_many(&self, rays: &[Ray], out: &mut [bool], coherence: Coherence) {
        self.occluded_packets(rays, out, coherence);
    }

    fn all_hits(&self, ray: &Ray, out: &mut Vec<Hit>) {
        out.clear();
        let raw_ray = to_raw(ray);
        let mut stack = [ffi::glint_hit::default(); ALL_HITS_ON_STACK];
        // SAFETY: `stack` holds ALL_HITS_ON_STACK hits, the capacity passed; the scene is
        // committed.
        let n = unsafe {
            ffi::glint_all_hits1(self.raw.as_ptr(), &raw_ray, stack.as_mut_ptr(), stack.len())
        };
        let mut heap = Vec::new();
        let raw: &[ffi::glint_hit] = if n <= stack.len() {
            &stack[..n]
        } else {
            // More hits than the stack holds: the same query again with room for all of them.
            heap.resize(n, ffi::glint_hit::default());
            // SAFETY: `heap` holds n hits, the capacity passed; the scene is committed.
            let m = unsafe {
                ffi::glint_all_hits1(self.raw.as_ptr(), &raw_ray, heap.as_mut_ptr(), heap.len())
            };
            &heap[..m.min(n)]
        };
        out.extend(raw.iter().filter_map(|h| self.hit_of(ray, h)));
        super::order_all_hits(out);
    }

    fn triangle_count(&self) -> usize {
        self.triangles
    }

    fn memory_bytes(&self) -> Option<usize> {
        usize::try_from(self.bytes).ok()
    }

    fn kernels(&self) -> String {
        format!(
            "embree {} {}",
            embree_version(),
            kernels::describe(self.isa)
        )
    }

    fn as_embree(&self) -> Option<&EmbreeAccel> {
        Some(self)
    }
}
