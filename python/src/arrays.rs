//! A finished render as numpy arrays: a dict from layer name to array, rows top first.
//!
//! | key | dtype | shape |
//! |---|---|---|
//! | `radiance` | float32 | H×W×3, W/(m²·sr) (denoised with `denoise=True`) |
//! | `noisy` | float32 | H×W×3, the radiance before denoising (only with `denoise=True`) |
//! | `alpha` | float32 | H×W, coverage: the fraction of camera samples that hit the scene |
//! | `albedo`, `normal` | float32 | H×W×3 |
//! | `depth` | float32 | H×W |
//! | `instance_id`, `material_id` | uint32 | H×W (`NO_ID` where nothing is hit) |
//! | `coverage_ids` | uint32 | H×W×K |
//! | `coverage` | float32 | H×W×K (fractions of the pixel's samples) |
//! | `samples` | uint32 | H×W, samples each pixel took (only when adaptive sampling ran) |

use glam::Vec3;
use glint::job::JobImages;
use glint::render::{Image, ids::COVERAGE_LAYERS};
use numpy::ndarray::{Array2, Array3};
use numpy::{Element, IntoPyArray};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// An H×W×C array of `image`'s pixels, each `channels(pixel)`.
fn planes<'py, T: Copy, E: Element, const C: usize>(
    py: Python<'py>,
    image: &Image<T>,
    channels: impl Fn(T) -> [E; C],
) -> PyResult<Bound<'py, PyAny>> {
    let data: Vec<E> = image.pixels.iter().flat_map(|&p| channels(p)).collect();
    let shape = (image.height as usize, image.width as usize, C);
    let array = Array3::from_shape_vec(shape, data)
        .map_err(|e| crate::glint_error(format!("image of the wrong size: {e}")))?;
    Ok(array.into_pyarray(py).into_any())
}

/// An H×W array of `image`'s pixels.
fn plane<'py, E: Element + Copy>(py: Python<'py>, image: &Image<E>) -> PyResult<Bound<'py, PyAny>> {
    let shape = (image.height as usize, image.width as usize);
    let array = Array2::from_shape_vec(shape, image.pixels.clone())
        .map_err(|e| crate::glint_error(format!("image of the wrong size: {e}")))?;
    Ok(array.into_pyarray(py).into_any())
}

/// The dict of arrays of a render (see the module documentation for keys, dtypes and shapes).
pub fn images_to_dict<'py>(py: Python<'py>, images: &JobImages) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    let rgb = |v: Vec3| v.to_array();
    dict.set_item("radiance", planes(py, &images.image, rgb)?)?;
    if let Some(noisy) = &images.noisy {
        dict.set_item("noisy", planes(py, noisy, rgb)?)?;
    }
    let aovs = &images.aovs;
    if let Some(alpha) = &aovs.alpha {
        dict.set_item("alpha", plane(py, alpha)?)?;
    }
    if let Some(albedo) = &aovs.albedo {
        dict.set_item("albedo", planes(py, albedo, rgb)?)?;
    }
    if let Some(normal) = &aovs.normal {
        dict.set_item("normal", planes(py, normal, rgb)?)?;
    }
    if let Some(depth) = &aovs.depth {
        dict.set_item("depth", plane(py, depth)?)?;
    }
    if let Some(ids) = &aovs.instance_id {
        dict.set_item("instance_id", plane(py, ids)?)?;
    }
    if let Some(ids) = &aovs.material_id {
        dict.set_item("material_id", plane(py, ids)?)?;
    }
    if let Some(z) = &aovs.z {
        dict.set_item("z", plane(py, z)?)?;
    }
    if let Some(position) = &aovs.position {
        dict.set_item("position", planes(py, position, rgb)?)?;
    }
    let pair = |v: glam::Vec2| v.to_array();
    for (key, image) in [
        ("uv", &aovs.uv),
        ("flow", &aovs.flow),
        ("flow_backward", &aovs.flow_backward),
    ] {
        if let Some(image) = image {
            dict.set_item(key, planes(py, image, pair)?)?;
        }
    }
    // The camera sidecar as a dict, through Python's json module (the record is plain JSON).
    let text = serde_json::to_string(&images.sidecar)
        .map_err(|e| crate::glint_error(format!("camera record: {e}")))?;
    let camera = py.import("json")?.call_method1("loads", (text,))?;
    // With annotations, the sidecar's per-instance list is also a key of its own.
    if aovs.instance_samples.is_some() {
        dict.set_item("instances", camera.get_item("instances")?)?;
    }
    dict.set_item("camera", camera)?;
    if let Some(coverage) = &aovs.coverage {
        let same = |p: [u32; COVERAGE_LAYERS]| p;
        dict.set_item("coverage_ids", planes(py, &coverage.ids, same)?)?;
        let same = |p: [f32; COVERAGE_LAYERS]| p;
        dict.set_item("coverage", planes(py, &coverage.fractions, same)?)?;
    }
    if let Some(samples) = &aovs.samples {
        dict.set_item("samples", plane(py, samples)?)?;
    }
    Ok(dict)
}
