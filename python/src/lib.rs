//! glint's Python extension module, `glint._glint` (re-exported by the package `glint`).
//!
//! - [`scene`]: `glint.load` and the `Scene` class: a loaded, prepared scene (ray-query
//!   structure, MIP chains, area lights built once) that serves any number of renders.
//! - [`options`]: a render's keyword arguments → a library [`glint::job::Job`].
//! - [`arrays`]: a finished render → a dict of numpy arrays.
//! - [`interrupt`]: runs a render with the GIL released, stopping it on Ctrl-C.
//! - [`batch`]: `glint.render_batch`, many jobs on one thread pool.
//!
//! Errors from glint become `glint.GlintError` carrying glint's message; bad Python arguments
//! become `TypeError`/`ValueError`. No `unsafe` here: pyo3's and numpy's safe API only.

mod arrays;
mod batch;
mod interrupt;
mod options;
mod scene;

use pyo3::prelude::*;

pyo3::create_exception!(
    glint,
    GlintError,
    pyo3::exceptions::PyException,
    "An error from glint: a scene that cannot be loaded, a camera that does not exist, \
     options that cannot be honoured. The message is glint's own, naming the file, node or \
     option at fault and how to fix it."
);

/// A glint error as a Python exception.
pub(crate) fn glint_error(error: impl std::fmt::Display) -> PyErr {
    GlintError::new_err(error.to_string())
}

/// The module `glint._glint`.
#[pymodule]
fn _glint(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // This extension links its own copy of Rust's standard library, so the hook is glint's
    // alone: a panic inside glint prints nothing and becomes one GlintError line.
    glint::panics::install_quiet_hook();
    m.add("GlintError", m.py().get_type::<GlintError>())?;
    m.add("NO_ID", glint::render::ids::NO_ID)?;
    m.add("COVERAGE_LAYERS", glint::render::ids::COVERAGE_LAYERS)?;
    m.add("AOVS", options::AOV_NAMES.to_vec())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<scene::Camera>()?;
    m.add_function(wrap_pyfunction!(scene::load, m)?)?;
    m.add_function(wrap_pyfunction!(batch::render_batch, m)?)?;
    Ok(())
}
