//! Atomic file writes: write to a temporary file in the destination's folder, flush it to
//! disk, then rename it over the destination. A rename within one file system is atomic, so
//! readers see either the old file or the complete new one; on any error the temporary file is
//! removed (by `tempfile`'s drop) and the destination is untouched.

use super::OutputError;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

/// Writes `path` atomically; `write` fills the file through a buffered writer (seekable, as
/// some encoders need). An error from `write` aborts the whole write.
pub fn write_atomically<F>(path: &Path, write: F) -> Result<(), OutputError>
where
    F: FnOnce(&mut BufWriter<&mut File>) -> Result<(), OutputError>,
{
    let io = |source: std::io::Error| OutputError::Io {
        path: path.to_path_buf(),
        source,
    };
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    // A hidden name next to the destination: same file system, so the rename is atomic.
    let mut temp = tempfile::Builder::new()
        .prefix(&format!(".{name}."))
        .suffix(".tmp")
        .tempfile_in(folder)
        .map_err(io)?;
    {
        let mut writer = BufWriter::new(temp.as_file_mut());
        write(&mut writer)?;
        writer.flush().map_err(io)?;
    }
    temp.as_file().sync_all().map_err(io)?;
    temp.persist(path).map_err(|e| io(e.error))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replaces_the_file_only_when_complete() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.txt");
        write_atomically(&path, |w| {
            w.write_all(b"first").map_err(|source| OutputError::Io {
                path: path.clone(),
                source,
            })
        })
        .unwrap();
        let failed = write_atomically(&path, |w| {
            let _ = w.write_all(b"partial");
            Err(OutputError::Encode {
                path: path.clone(),
                format: "test",
                message: "injected".into(),
            })
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read(&path).unwrap(), b"first");
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            1,
            "no temp left"
        );
    }
}
