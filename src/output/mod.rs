//! Writing renders to disk: PNG (display-referred, 8 or 16 bit), OpenEXR (linear radiance,
//! 32-bit float), and partial renders' sample sums ([`partial`], read back by `glint merge`).
//! Every file is written atomically ([`atomic`]): a failed write leaves neither the file nor a
//! temporary behind, and an existing file is replaced only by a complete one.

pub mod atomic;
pub mod budget;
pub mod exr;
pub mod fingerprint;
pub mod instances;
pub mod partial;
pub mod plan;
pub mod png;
pub mod rle;
pub mod sidecar;

pub use atomic::write_atomically;
pub use exr::{write_exr, write_exr_annotated, write_exr_layers};
pub use plan::{OutputPlan, PlanError};
pub use png::{PngDepth, PngOptions, write_png};
pub use sidecar::{Sidecar, read_sidecar, sidecar_path, write_sidecar};

use std::path::{Path, PathBuf};

/// Why an output file could not be written. Each names the file and suggests a fix.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The extension names no supported format.
    #[error("{path}: unsupported output format '{extension}'; use a .png or .exr file name")]
    Format {
        /// The output path.
        path: PathBuf,
        /// Its extension (empty if none).
        extension: String,
    },
    /// The file system refused.
    #[error("cannot write {path}: {source}; check that the folder exists and is writable")]
    Io {
        /// The output path.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The encoder failed.
    #[error("cannot encode {path} as {format}: {message}")]
    Encode {
        /// The output path.
        path: PathBuf,
        /// PNG or EXR.
        format: &'static str,
        /// The encoder's message.
        message: String,
    },
}

/// The formats glint writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    /// Portable Network Graphics, sRGB-encoded.
    Png,
    /// OpenEXR, linear.
    Exr,
}

impl OutputFormat {
    /// The format named by `path`'s extension (case-insensitive).
    pub fn from_path(path: &Path) -> Result<Self, OutputError> {
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        match extension.as_str() {
            "png" => Ok(OutputFormat::Png),
            "exr" => Ok(OutputFormat::Exr),
            _ => Err(OutputError::Format {
                path: path.to_path_buf(),
                extension,
            }),
        }
    }
}
