//! Where a batch may write: every output must resolve inside the output root (by default the
//! job file's folder; `--output-root DIR` or the job file's top-level `output_root` key set
//! another), after `..` and symbolic links are followed, so that a job file cannot write
//! `../../elsewhere` or `/etc/...` by accident or by design. And every output folder is
//! checked to be writable before anything renders, so that a read-only folder fails at once
//! rather than after hours of rendering.

use std::path::{Path, PathBuf};

pub use crate::output::plan::resolve;

/// Checks that `output` resolves inside `root` (itself resolved). Returns the resolved
/// output; the error says where it resolves and how to allow it.
pub fn confine(output: &Path, root: &Path) -> Result<PathBuf, String> {
    let root = resolve(root)
        .map_err(|e| format!("cannot resolve the output root {}: {e}", root.display()))?;
    let resolved = resolve(output)
        .map_err(|e| format!("cannot resolve the output {}: {e}", output.display()))?;
    if resolved.starts_with(&root) && resolved != root {
        Ok(resolved)
    } else {
        Err(format!(
            "output {} resolves to {}, outside the output root {}; write outputs inside the \
             job file's folder, or allow another folder with glint batch --output-root DIR \
             (or output_root = \"DIR\" at the top of the job file)",
            output.display(),
            resolved.display(),
            root.display()
        ))
    }
}

/// Creates `folder` if missing and proves it writable by creating and removing a probe file
/// (`.glint-probe-PID`), so that permissions, read-only mounts and full quotas show before
/// any render. The error names the folder and the fix.
pub fn probe_writable(folder: &Path) -> Result<(), String> {
    std::fs::create_dir_all(folder).map_err(|e| {
        format!(
            "cannot create the output folder {}: {e}; fix the job's output path or the \
             folder's permissions",
            folder.display()
        )
    })?;
    let probe = folder.join(format!(".glint-probe-{}", std::process::id()));
    let _ = std::fs::remove_file(&probe);
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .and_then(|mut f| std::io::Write::write_all(&mut f, b"probe"))
        .map_err(|e| {
            let _ = std::fs::remove_file(&probe);
            format!(
                "the output folder {} is not writable ({e}); nothing was rendered for it: fix \
                 its permissions or choose another output path",
                folder.display()
            )
        })?;
    std::fs::remove_file(&probe).map_err(|e| {
        format!(
            "cannot remove the probe file {} ({e}); check the folder's permissions",
            probe.display()
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_by_dot_dot_absolute_paths_and_links_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().join("jobs");
        std::fs::create_dir_all(root.join("out")).unwrap();
        assert!(confine(&root.join("out/a.png"), &root).is_ok());
        assert!(confine(&root.join("new/deeper/a.png"), &root).is_ok());
        assert!(confine(&root.join("out/../b.png"), &root).is_ok());
        let err = confine(&root.join("../outside.png"), &root).unwrap_err();
        assert!(err.contains("outside the output root"), "{err}");
        assert!(confine(&root.join("out/../../x/../../y.png"), &root).is_err());
        assert!(confine(Path::new("/etc/glint-test.png"), &root).is_err());
        assert!(confine(&root, &root).is_err(), "the root itself is no file");
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(dir.path(), root.join("link")).unwrap();
            let err = confine(&root.join("link/escaped.png"), &root).unwrap_err();
            assert!(err.contains("escaped.png"), "{err}");
        }
    }

    #[test]
    fn a_folder_blocked_by_a_file_fails_the_probe() {
        let dir = tempfile::tempdir().unwrap();
        assert!(probe_writable(&dir.path().join("fresh/sub")).is_ok());
        assert_eq!(
            std::fs::read_dir(dir.path().join("fresh/sub"))
                .unwrap()
                .count(),
            0,
            "the probe file is removed"
        );
        std::fs::write(dir.path().join("file"), b"x").unwrap();
        let err = probe_writable(&dir.path().join("file/sub")).unwrap_err();
        assert!(err.contains("file/sub"), "{err}");
    }
}
