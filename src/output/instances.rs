//! Per-instance annotations of a render, as the camera sidecar ([`super::sidecar`]) carries
//! them: one entry per instance (a glTF node with a mesh, instanced copies included) that
//! covers any pixel.
//!
//! Placeholder: the per-instance annotation work (visible and amodal masks, boxes, the COCO
//! writer) owns this module and fills [`InstanceAnnotation`]; the sidecar only holds the list.

use serde::{Deserialize, Serialize};

/// One instance's annotations in the sidecar (filled by the per-instance annotation module;
/// empty until then).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct InstanceAnnotation {}
