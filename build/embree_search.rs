//! Where Embree is: `EMBREE_DIR` / `EMBREE_INCLUDE_DIR` / `EMBREE_LIB_DIR` / `EMBREE_LIB`,
//! then pkg-config (`embree4`, `embree3`), then the standard include and library paths
//! (Debian ships no pkg-config file for Embree, so the standard paths are what finds it
//! there). A folder given explicitly that holds no Embree is an error, never a silent
//! fall-back to another install.

use std::env;
use std::path::{Path, PathBuf};

/// Where Embree was found.
pub struct Embree {
    pub major: u32,
    pub include_dir: PathBuf,
    pub lib_dirs: Vec<PathBuf>,
    pub lib_name: String,
}

/// Why no usable Embree was found; each line becomes one line of the build error.
pub type Failure = Vec<String>;

const NOT_FOUND: &[&str] = &[
    "glint: Embree 3 or 4 was not found (no embree4/ or embree3/ headers with their library in \
     EMBREE_DIR, pkg-config or the standard paths).",
    "  Install it:  sudo apt-get install libembree-dev   (Debian/Ubuntu; scripts/setup.sh does it)",
    "  or point EMBREE_DIR at an Embree 3 or 4 install (a folder with include/ and lib/),",
    "  or build the pure-Rust backend alone:  cargo build --no-default-features",
];

/// The header subfolder that marks an Embree of the given major version.
pub fn header_dir(major: u32) -> String {
    format!("embree{major}")
}

/// Which major version the include folder holds, 4 preferred.
fn major_in(include_dir: &Path) -> Option<u32> {
    [4, 3]
        .into_iter()
        .find(|m| include_dir.join(header_dir(*m)).join("rtcore.h").is_file())
}

pub fn find_embree() -> Result<Embree, Failure> {
    if let Some(found) = from_explicit_dirs()? {
        return Ok(found);
    }
    if let Some(found) = from_pkg_config() {
        return Ok(found);
    }
    from_standard_paths().ok_or_else(|| NOT_FOUND.iter().map(|s| s.to_string()).collect())
}

/// Whether a library file name was given (`libembree4-xyz.so.4`) rather than a link name.
pub fn is_file_name(lib: &str) -> bool {
    lib.contains(".so") || lib.ends_with(".dylib")
}

/// `EMBREE_DIR` / `EMBREE_INCLUDE_DIR` / `EMBREE_LIB_DIR` / `EMBREE_LIB`. `Ok(None)` when none
/// of the folders is set; an error when one is set but holds no Embree.
fn from_explicit_dirs() -> Result<Option<Embree>, Failure> {
    let prefix = env::var_os("EMBREE_DIR").map(PathBuf::from);
    let (include_dir, include_var) = match env::var_os("EMBREE_INCLUDE_DIR") {
        Some(dir) => (PathBuf::from(dir), "EMBREE_INCLUDE_DIR"),
        None => match &prefix {
            Some(p) => (p.join("include"), "EMBREE_DIR"),
            None => return Ok(None),
        },
    };
    let Some(major) = major_in(&include_dir) else {
        return Err(vec![
            format!(
                "glint: {include_var} is set, but {} holds neither embree4/rtcore.h nor \
                 embree3/rtcore.h.",
                include_dir.display()
            ),
            format!(
                "  Fix {include_var} (EMBREE_DIR is the install prefix, EMBREE_INCLUDE_DIR the \
                 folder that contains embree4/), or unset it to use the system's Embree \
                 (sudo apt-get install libembree-dev),"
            ),
            "  or build the pure-Rust backend alone:  cargo build --no-default-features".into(),
        ]);
    };
    let lib_dirs: Vec<PathBuf> = match env::var_os("EMBREE_LIB_DIR") {
        Some(dir) => vec![PathBuf::from(dir)],
        None => prefix
            .iter()
            .flat_map(|p| [p.join("lib"), p.join("lib64")])
            .filter(|d| d.is_dir())
            .collect(),
    };
    let lib_name = env::var("EMBREE_LIB").unwrap_or_else(|_| format!("embree{major}"));
    // With no folder given the linker's default path is searched; with one, check it here so
    // a wrong folder is reported by name rather than as an `ld` error.
    if !lib_dirs.is_empty() {
        let candidates: Vec<String> = if is_file_name(&lib_name) {
            vec![lib_name.clone()]
        } else {
            ["so", "dylib", "a"]
                .iter()
                .map(|ext| format!("lib{lib_name}.{ext}"))
                .collect()
        };
        let found = lib_dirs
            .iter()
            .any(|d| candidates.iter().any(|c| d.join(c).exists()));
        if !found {
            let dirs: Vec<String> = lib_dirs.iter().map(|d| d.display().to_string()).collect();
            return Err(vec![
                format!(
                    "glint: Embree {major} headers are in {}, but {} is not in {}.",
                    include_dir.display(),
                    candidates.join(" / "),
                    dirs.join(", ")
                ),
                "  Set EMBREE_LIB_DIR to the folder holding the library, and EMBREE_LIB to its \
                 link name (embree4) or exact file name (libembree4-xyz.so.4)."
                    .into(),
            ]);
        }
    }
    Ok(Some(Embree {
        major,
        include_dir,
        lib_dirs,
        lib_name,
    }))
}

fn from_pkg_config() -> Option<Embree> {
    for major in [4, 3] {
        let probe = pkg_config::Config::new()
            .cargo_metadata(false)
            .probe(&format!("embree{major}"));
        if let Ok(lib) = probe {
            let include_dir = lib
                .include_paths
                .iter()
                .find(|p| p.join(header_dir(major)).join("rtcore.h").is_file())
                .cloned()
                .or_else(|| {
                    // Some .pc files point at include/embree4 itself.
                    lib.include_paths
                        .iter()
                        .filter_map(|p| p.parent())
                        .find(|p| p.join(header_dir(major)).join("rtcore.h").is_file())
                        .map(Path::to_path_buf)
                })?;
            return Some(Embree {
                major,
                include_dir,
                lib_dirs: lib.link_paths.clone(),
                lib_name: format!("embree{major}"),
            });
        }
    }
    None
}

fn from_standard_paths() -> Option<Embree> {
    let target = env::var("TARGET").unwrap_or_default();
    let multiarch = match target.split('-').next() {
        Some("x86_64") => "x86_64-linux-gnu",
        Some("aarch64") => "aarch64-linux-gnu",
        _ => "",
    };
    let include_roots = [
        "/usr/include",
        "/usr/local/include",
        "/opt/homebrew/include",
    ];
    let lib_roots: Vec<PathBuf> = [
        format!("/usr/lib/{multiarch}"),
        "/usr/lib".into(),
        "/usr/lib64".into(),
        "/usr/local/lib".into(),
        "/usr/local/lib64".into(),
        "/opt/homebrew/lib".into(),
    ]
    .into_iter()
    .map(PathBuf::from)
    .collect();
    for major in [4, 3] {
        let Some(include_dir) = include_roots
            .iter()
            .map(PathBuf::from)
            .find(|root| root.join(header_dir(major)).join("rtcore.h").is_file())
        else {
            continue;
        };
        let lib_name = format!("embree{major}");
        let has_lib = |dir: &PathBuf| {
            ["so", "dylib", "a"]
                .iter()
                .any(|ext| dir.join(format!("lib{lib_name}.{ext}")).exists())
        };
        if let Some(dir) = lib_roots.iter().find(|d| has_lib(d)) {
            return Some(Embree {
                major,
                include_dir,
                lib_dirs: vec![dir.clone()],
                lib_name,
            });
        }
    }
    None
}
