//! A built acceleration structure as the benchmark sees it: the backend's [`Accel`], plus, for
//! Embree, the choice between single rays and 8-wide packets that the trait hides.

#[cfg(feature = "embree")]
use crate::accel::embree::EmbreeAccel;
use crate::accel::{
    Accel, AccelError, BackendKind, BuildOptions, Coherence, Hit, Ray, TriangleMesh, bvh::BvhAccel,
};
use rayon::prelude::*;
use serde::Serialize;

/// Rays per rayon task: 64 full 8×8 tiles, enough to amortise scheduling, and few enough per
/// task (hundreds of tasks for a 1024×768 image) for the threads to balance.
pub const TASK_RAYS: usize = 4096;

/// How a batch of rays is handed to the backend.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// One ray per traversal (`rtcIntersect1` for Embree; obvhs's only way).
    Single,
    /// Eight rays per traversal (`rtcIntersect8`).
    Packet8,
}

impl Method {
    /// Name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Method::Single => "single",
            Method::Packet8 => "packet8",
        }
    }
}

/// A built structure of one backend.
pub enum Structure {
    /// Embree, kept concrete to reach its single-ray and packet entry points.
    #[cfg(feature = "embree")]
    Embree(EmbreeAccel),
    /// The obvhs BVH.
    Bvh(Box<BvhAccel>),
}

impl Structure {
    /// Builds `kind` over `meshes`, which the caller has checked with
    /// [`crate::accel::validate`].
    pub fn build(
        kind: BackendKind,
        meshes: &[TriangleMesh<'_>],
        options: BuildOptions,
    ) -> Result<Self, AccelError> {
        match kind {
            #[cfg(feature = "embree")]
            BackendKind::Embree => Ok(Structure::Embree(EmbreeAccel::build(meshes, options)?)),
            #[cfg(not(feature = "embree"))]
            BackendKind::Embree => Err(AccelError::Unavailable(BackendKind::Embree)),
            BackendKind::Bvh => Ok(Structure::Bvh(Box::new(BvhAccel::build(meshes, options)))),
        }
    }

    /// The structure behind the common trait.
    pub fn accel(&self) -> &dyn Accel {
        match self {
            #[cfg(feature = "embree")]
            Structure::Embree(accel) => accel,
            Structure::Bvh(accel) => accel.as_ref(),
        }
    }

    /// The ways this backend can take a batch of rays.
    pub fn methods(&self) -> &'static [Method] {
        match self {
            #[cfg(feature = "embree")]
            Structure::Embree(_) => &[Method::Single, Method::Packet8],
            Structure::Bvh(_) => &[Method::Single],
        }
    }

    /// The method [`Accel::intersect_many`] and [`Accel::occluded_many`] use.
    pub fn default_method(&self) -> Method {
        match self {
            #[cfg(feature = "embree")]
            Structure::Embree(_) => Method::Packet8,
            Structure::Bvh(_) => Method::Single,
        }
    }

    /// Closest hits of `rays` into `hits` on the current rayon pool, [`TASK_RAYS`] per task.
    /// A method the backend lacks falls back to [`Accel::intersect_many`].
    pub fn closest(
        &self,
        method: Method,
        rays: &[Ray],
        hits: &mut [Option<Hit>],
        coherence: Coherence,
    ) {
        rays.par_chunks(TASK_RAYS)
            .zip(hits.par_chunks_mut(TASK_RAYS))
            .for_each(|(rays, hits)| match (self, method) {
                #[cfg(feature = "embree")]
                (Structure::Embree(accel), Method::Single) => {
                    accel.intersect_single(rays, hits, coherence)
                }
                #[cfg(feature = "embree")]
                (Structure::Embree(accel), Method::Packet8) => {
                    accel.intersect_packets(rays, hits, coherence)
                }
                _ => self.accel().intersect_many(rays, hits, coherence),
            });
    }

    /// Occlusion of `rays` into `occluded` on the current rayon pool; see [`Self::closest`].
    pub fn occluded(
        &self,
        method: Method,
        rays: &[Ray],
        occluded: &mut [bool],
        coherence: Coherence,
    ) {
        rays.par_chunks(TASK_RAYS)
            .zip(occluded.par_chunks_mut(TASK_RAYS))
            .for_each(|(rays, out)| match (self, method) {
                #[cfg(feature = "embree")]
                (Structure::Embree(accel), Method::Single) => {
                    accel.occluded_single(rays, out, coherence)
                }
                #[cfg(feature = "embree")]
                (Structure::Embree(accel), Method::Packet8) => {
                    accel.occluded_packets(rays, out, coherence)
                }
                _ => self.accel().occluded_many(rays, out, coherence),
            });
    }
}
