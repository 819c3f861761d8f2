//! The output plan: every file one glint command will write, and every file it reads,
//! gathered before anything renders, so that no output replaces an input or another output.
//!
//! Each path is normalised the way the batch's output-root confinement normalises it
//! ([`resolve`]: absolute, `.` and `..` applied, symbolic links of every existing ancestor
//! followed), and an existing file is also known by its device and inode, so that `./a.png`,
//! `sub/../a.png`, `link/a.png` and a hard link of `a.png` are one file. The plan refuses, in
//! one line naming both uses:
//!
//! - two outputs that are the same file (two images, an image and a sidecar, the COCO file and
//!   the report, ...);
//! - an output that is an input (the scene, its buffers and images, the job file, the
//!   environment map, a lights file).
//!
//! And it admits only regular files: an input or an existing output that is a FIFO, a socket,
//! a device or a folder is refused at once (opening a FIFO would block until a writer
//! appears).

use std::path::{Component, Path, PathBuf};

/// Why a plan refuses a file. The message is one line naming the file and both of its uses.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct PlanError(pub String);

/// One file of the plan.
#[derive(Clone, Debug)]
struct Entry {
    /// As the user spelled it.
    given: PathBuf,
    /// [`resolve`]d.
    resolved: PathBuf,
    /// Device and inode, for a file that exists.
    inode: Option<(u64, u64)>,
    /// What the command does with it: "the image of [[job]] 2", "the scene", ...
    what: String,
}

impl Entry {
    fn same_file(&self, other: &Entry) -> bool {
        self.resolved == other.resolved || (self.inode.is_some() && self.inode == other.inode)
    }
}

/// Every file one command writes and reads (see the module documentation).
#[derive(Clone, Debug, Default)]
pub struct OutputPlan {
    outputs: Vec<Entry>,
    inputs: Vec<Entry>,
    /// Resolved output paths, for the quick duplicate check of large batches.
    written: std::collections::HashMap<PathBuf, usize>,
}

impl OutputPlan {
    /// An empty plan.
    pub fn new() -> Self {
        Self::default()
    }

    /// Records that the command writes `path` as `what` ("the image of [[job]] 2"). Refused
    /// when `path` is already an output or an input of the plan, or exists and is not a
    /// regular file.
    pub fn output(&mut self, path: &Path, what: impl Into<String>) -> Result<(), PlanError> {
        let entry = entry(path, what.into())?;
        if let Some(&i) = self.written.get(&entry.resolved) {
            return Err(twice(&self.outputs[i], &entry));
        }
        if entry.inode.is_some()
            && let Some(first) = self.outputs.iter().find(|o| o.same_file(&entry))
        {
            return Err(twice(first, &entry));
        }
        if let Some(input) = self.inputs.iter().find(|i| i.same_file(&entry)) {
            return Err(clobbers(input, &entry));
        }
        self.written
            .insert(entry.resolved.clone(), self.outputs.len());
        self.outputs.push(entry);
        Ok(())
    }

    /// Records that the command reads `path` as `what` ("the scene", "the job file"). Refused
    /// when `path` is an output of the plan, or exists and is not a regular file (a missing
    /// input is left to its reader, which names it).
    pub fn input(&mut self, path: &Path, what: impl Into<String>) -> Result<(), PlanError> {
        let entry = entry(path, what.into())?;
        if let Some(&i) = self.written.get(&entry.resolved) {
            return Err(clobbers(&entry, &self.outputs[i]));
        }
        if entry.inode.is_some()
            && let Some(output) = self.outputs.iter().find(|o| o.same_file(&entry))
        {
            return Err(clobbers(&entry, output));
        }
        // Inputs may repeat (jobs share a scene); one entry is enough.
        if !self.inputs.iter().any(|i| i.same_file(&entry)) {
            self.inputs.push(entry);
        }
        Ok(())
    }

    /// Records the scene file at `path` and the external buffers and images it names as
    /// inputs (`label` names the scene in messages).
    pub fn scene(&mut self, path: &Path, label: &str) -> Result<(), PlanError> {
        self.input(path, format!("the scene {label}"))?;
        // A scene that cannot be read names no files; its loader reports why.
        for file in super::fingerprint::external_files(path).unwrap_or_default() {
            self.input(&file.path, format!("{} of the scene {label}", file.what))?;
        }
        Ok(())
    }

    /// The outputs planned, as given, in order.
    pub fn outputs(&self) -> impl Iterator<Item = &Path> {
        self.outputs.iter().map(|o| o.given.as_path())
    }
}

fn twice(first: &Entry, second: &Entry) -> PlanError {
    PlanError(format!(
        "{} would be written twice: as {} and as {} (the same file as {}); give each output \
         its own file name",
        second.given.display(),
        first.what,
        second.what,
        first.given.display()
    ))
}

fn clobbers(input: &Entry, output: &Entry) -> PlanError {
    PlanError(format!(
        "{} is {}, which glint reads, and would be replaced as {} (the same file as {}); \
         write the output elsewhere",
        output.given.display(),
        input.what,
        output.what,
        input.given.display()
    ))
}

fn entry(path: &Path, what: String) -> Result<Entry, PlanError> {
    let resolved = resolve(path)
        .map_err(|e| PlanError(format!("cannot resolve {} ({what}): {e}", path.display())))?;
    let inode = match std::fs::metadata(path) {
        Ok(meta) => {
            require_regular_meta(path, &meta, &what)?;
            inode_of(&meta)
        }
        Err(_) => None,
    };
    Ok(Entry {
        given: path.to_path_buf(),
        resolved,
        inode,
        what,
    })
}

#[cfg(unix)]
fn inode_of(meta: &std::fs::Metadata) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    Some((meta.dev(), meta.ino()))
}

#[cfg(not(unix))]
fn inode_of(_: &std::fs::Metadata) -> Option<(u64, u64)> {
    None
}

/// Refuses a path that exists and is not a regular file (after following links): a FIFO, a
/// socket, a device or a folder. A missing path passes (its reader or writer says why).
/// `what` names its use ("the scene", "check-gt's input").
pub fn require_regular(path: &Path, what: &str) -> Result<(), PlanError> {
    match std::fs::metadata(path) {
        Ok(meta) => require_regular_meta(path, &meta, what),
        Err(_) => Ok(()),
    }
}

fn require_regular_meta(
    path: &Path,
    meta: &std::fs::Metadata,
    what: &str,
) -> Result<(), PlanError> {
    if meta.is_file() {
        return Ok(());
    }
    let kind = file_kind(meta);
    Err(PlanError(format!(
        "{} ({what}) is {kind}, not a regular file; glint reads and writes regular files only",
        path.display()
    )))
}

fn file_kind(meta: &std::fs::Metadata) -> &'static str {
    if meta.is_dir() {
        return "a folder";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = meta.file_type();
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_socket() {
            return "a socket";
        }
        if t.is_block_device() || t.is_char_device() {
            return "a device";
        }
    }
    "not a regular file"
}

/// The real path `path` names (absolute, `.`/`..` and symbolic links resolved), including
/// the part that does not exist yet. A `..` is applied to the real path of what precedes it,
/// as the kernel does, so a symbolic link followed by `..` goes where the file system goes.
pub fn resolve(path: &Path) -> std::io::Result<PathBuf> {
    let absolute = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir()?.join(path)
    };
    let mut resolved = PathBuf::new();
    for component in absolute.components() {
        match component {
            Component::Prefix(_) | Component::RootDir => resolved.push(component),
            Component::CurDir => {}
            Component::ParentDir => {
                resolved = real(&resolved);
                resolved.pop();
            }
            Component::Normal(name) => resolved.push(name),
        }
    }
    Ok(real(&resolved))
}

/// `path` with its longest existing ancestor canonicalised (the rest cannot hold links).
fn real(path: &Path) -> PathBuf {
    let mut existing = path;
    let mut rest = Vec::new();
    loop {
        if let Ok(canonical) = std::fs::canonicalize(existing) {
            let mut out = canonical;
            for name in rest.iter().rev() {
                out.push(name);
            }
            return out;
        }
        match (existing.parent(), existing.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name.to_os_string());
                existing = parent;
            }
            _ => return path.to_path_buf(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spellings_of_one_file_are_one_output() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::create_dir(d.join("sub")).unwrap();
        for second in [d.join("./a.png"), d.join("sub/../a.png")] {
            let mut plan = OutputPlan::new();
            plan.output(&d.join("a.png"), "the image of job 0").unwrap();
            let err = plan.output(&second, "the image of job 1").unwrap_err();
            assert!(
                err.0.contains("job 0") && err.0.contains("job 1") && err.0.contains("twice"),
                "{err}"
            );
        }
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(d.join("sub"), d.join("link")).unwrap();
            let mut plan = OutputPlan::new();
            plan.output(&d.join("sub/a.png"), "one").unwrap();
            assert!(plan.output(&d.join("link/a.png"), "two").is_err());
            // A hard link of an existing file.
            std::fs::write(d.join("x.png"), b"x").unwrap();
            std::fs::hard_link(d.join("x.png"), d.join("y.png")).unwrap();
            let mut plan = OutputPlan::new();
            plan.output(&d.join("x.png"), "one").unwrap();
            assert!(plan.output(&d.join("y.png"), "two").is_err());
        }
        let mut plan = OutputPlan::new();
        plan.output(&d.join("a.png"), "one").unwrap();
        plan.output(&d.join("b.png"), "two").unwrap();
    }

    #[test]
    fn an_output_that_is_an_input_is_refused_in_either_order() {
        let dir = tempfile::tempdir().unwrap();
        let scene = dir.path().join("s.gltf");
        std::fs::write(
            &scene,
            br#"{"asset":{"version":"2.0"},"buffers":[{"uri":"b.bin"}]}"#,
        )
        .unwrap();
        let mut plan = OutputPlan::new();
        plan.scene(&scene, "s.gltf").unwrap();
        let err = plan
            .output(&dir.path().join("b.bin"), "the report")
            .unwrap_err();
        assert!(
            err.0.contains("buffer 0") && err.0.contains("the report"),
            "{err}"
        );
        let mut plan = OutputPlan::new();
        plan.output(&scene, "the COCO file").unwrap();
        let err = plan.input(&scene, "the job file").unwrap_err();
        assert!(
            err.0.contains("the job file") && err.0.contains("COCO"),
            "{err}"
        );
    }

    #[cfg(unix)]
    #[test]
    fn fifos_and_folders_are_refused_at_once() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe.png");
        let status = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(status.success());
        let err = OutputPlan::new().output(&fifo, "the image").unwrap_err();
        assert!(err.0.contains("FIFO"), "{err}");
        let err = OutputPlan::new().input(&fifo, "the scene").unwrap_err();
        assert!(err.0.contains("FIFO"), "{err}");
        let err = require_regular(dir.path(), "the scene").unwrap_err();
        assert!(err.0.contains("folder"), "{err}");
        assert!(require_regular(&dir.path().join("missing"), "x").is_ok());
    }
}
