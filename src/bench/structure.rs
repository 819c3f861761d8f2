//! A built acceleration structure as the benchmark sees it: the backend's [`Accel`], plus, for
//! Embree, the choice between single rays and 8-wide packets that the trait hides.

#[cfg(feature = "embree")]
use crate::accel::embree::EmbreeAccel;
use crate::accel::{
    Accel, AccelError, BackendKind, BuildOptions, Coherence, Hit, Ray, TriangleMesh,
    build_validated,
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

/// A built structure of one backend ([`crate::accel::build_validated`]), with the Embree
/// backend's own entry points reachable ([`Accel::as_embree`]).
pub struct Structure {
    accel: Box<dyn Accel>,
}

impl Structure {
    /// Builds `kind` over `meshes`, which the caller has checked with
    /// [`crate::accel::validate`] (so that the build alone is timed).
    pub fn build(
        kind: BackendKind,
        meshes: &[TriangleMesh<'_>],
        options: BuildOptions,
    ) -> Result<Self, AccelError> {
        Ok(Self {
            accel: build_validated(kind, meshes, options)?,
        })
    }

    /// The structure behind the common trait.
    pub fn accel(&self) -> &dyn Accel {
        self.accel.as_ref()
    }

    /// Embree, kept concrete to reach its single-ray and packet entry points.
    #[cfg(feature = "embree")]
    fn embree(&self) -> Option<&EmbreeAccel> {
        self.accel.as_embree()
    }

    /// The ways this backend can take a batch of rays.
    pub fn methods(&self) -> &'static [Method] {
        #[cfg(feature = "embree")]
        if self.embree().is_some() {
            return &[Method::Single, Method::Packet8];
        }
        &[Method::Single]
    }

    /// The method [`Accel::intersect_many`] and [`Accel::occluded_many`] use.
    pub fn default_method(&self) -> Method {
        #[cfg(feature = "embree")]
        if self.embree().is_some() {
            return Method::Packet8;
        }
        Method::Single
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
            .for_each(|(rays, hits)| {
                #[cfg(feature = "embree")]
                if let Some(embree) = self.embree() {
                    return match method {
                        Method::Single => embree.intersect_single(rays, hits, coherence),
                        Method::Packet8 => embree.intersect_packets(rays, hits, coherence),
                    };
                }
                self.accel.intersect_many(rays, hits, coherence)
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
            .for_each(|(rays, out)| {
                #[cfg(feature = "embree")]
                if let Some(embree) = self.embree() {
                    return match method {
                        Method::Single => embree.occluded_single(rays, out, coherence),
                        Method::Packet8 => embree.occluded_packets(rays, out, coherence),
                    };
                }
                self.accel.occluded_many(rays, out, coherence)
            });
    }
}
