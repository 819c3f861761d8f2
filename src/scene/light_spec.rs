//! Lights given on the command line (`--light`) or in a small lights file.

use super::Light;
use std::path::Path;

/// A light description that could not be understood.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct LightSpecError(pub String);

/// Parses one `--light` value (format in the README).
pub fn parse_light(spec: &str) -> Result<Light, LightSpecError> {
    Err(LightSpecError(format!("cannot parse light '{spec}' yet")))
}

/// Reads a lights file (format in the README).
pub fn load_lights_file(path: &Path) -> Result<Vec<Light>, LightSpecError> {
    Err(LightSpecError(format!("{}: lights files are not supported yet", path.display())))
}
