//! Finds Embree (4 or 3), compiles the C shim in `ffi/` against it, and generates the Rust
//! bindings of the shim's own header with bindgen.
//!
//! Search order: `EMBREE_DIR` (a prefix with `include/embree{4,3}` and `lib`), then pkg-config
//! (`embree4`, `embree3`), then the standard include and library paths. Debian ships no
//! pkg-config file for Embree, so the standard paths are what finds it there.
//!
//! Overrides for unusual installs (e.g. a library taken from a Python wheel):
//! `EMBREE_INCLUDE_DIR`, `EMBREE_LIB_DIR` and `EMBREE_LIB` (the library's link name).

use std::env;
use std::path::{Path, PathBuf};

/// Where Embree was found.
struct Embree {
    major: u32,
    include_dir: PathBuf,
    lib_dirs: Vec<PathBuf>,
    lib_name: String,
}

const INSTALL_HINT: &str = "glint: Embree was not found.\n\
  Install it:  sudo apt-get install libembree-dev   (Debian/Ubuntu; or run scripts/setup.sh)\n\
  or point EMBREE_DIR at an Embree 3 or 4 install (a folder with include/ and lib/),\n\
  or build the pure-Rust backend alone:  cargo build --no-default-features";

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=ffi/shim.h");
    println!("cargo:rerun-if-changed=ffi/shim.c");
    for var in [
        "EMBREE_DIR",
        "EMBREE_INCLUDE_DIR",
        "EMBREE_LIB_DIR",
        "EMBREE_LIB",
    ] {
        println!("cargo:rerun-if-env-changed={var}");
    }
    if env::var_os("CARGO_FEATURE_EMBREE").is_none() {
        return;
    }
    let embree = match find_embree() {
        Some(found) => found,
        None => {
            // One clear message and a failed build, not a wall of linker errors.
            eprintln!("\n{INSTALL_HINT}\n");
            println!("cargo:warning={}", INSTALL_HINT.replace('\n', " "));
            std::process::exit(1);
        }
    };
    println!(
        "cargo:rustc-env=GLINT_EMBREE_INCLUDE={}",
        embree.include_dir.display()
    );
    compile_shim(&embree);
    generate_bindings();
}

/// The header subfolder that marks an Embree of the given major version.
fn header_dir(major: u32) -> String {
    format!("embree{major}")
}

/// Which major version the include folder holds, 4 preferred.
fn major_in(include_dir: &Path) -> Option<u32> {
    [4, 3]
        .into_iter()
        .find(|m| include_dir.join(header_dir(*m)).join("rtcore.h").is_file())
}

fn find_embree() -> Option<Embree> {
    if let Some(found) = from_explicit_dirs() {
        return Some(found);
    }
    if let Some(found) = from_pkg_config() {
        return Some(found);
    }
    from_standard_paths()
}

fn from_explicit_dirs() -> Option<Embree> {
    let prefix = env::var_os("EMBREE_DIR").map(PathBuf::from);
    let include_dir = env::var_os("EMBREE_INCLUDE_DIR")
        .map(PathBuf::from)
        .or_else(|| prefix.as_ref().map(|p| p.join("include")))?;
    let major = major_in(&include_dir)?;
    let lib_dirs: Vec<PathBuf> = match env::var_os("EMBREE_LIB_DIR") {
        Some(dir) => vec![PathBuf::from(dir)],
        None => prefix
            .iter()
            .flat_map(|p| [p.join("lib"), p.join("lib64")])
            .filter(|d| d.is_dir())
            .collect(),
    };
    let lib_name = env::var("EMBREE_LIB").unwrap_or_else(|_| format!("embree{major}"));
    Some(Embree {
        major,
        include_dir,
        lib_dirs,
        lib_name,
    })
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

fn compile_shim(embree: &Embree) {
    cc::Build::new()
        .file("ffi/shim.c")
        .include("ffi")
        .include(&embree.include_dir)
        .define("GLINT_EMBREE_MAJOR", embree.major.to_string().as_str())
        .flag_if_supported("-std=c11")
        .warnings(true)
        .extra_warnings(true)
        .opt_level(3)
        .compile("glint_shim");
    for dir in &embree.lib_dirs {
        println!("cargo:rustc-link-search=native={}", dir.display());
        // Libraries outside the loader's default path (EMBREE_DIR, a wheel) must still be found
        // when the binaries and tests run.
        if !dir.starts_with("/usr/lib") && !dir.starts_with("/lib") {
            println!("cargo:rustc-link-arg=-Wl,-rpath,{}", dir.display());
        }
    }
    println!("cargo:rustc-link-lib=dylib={}", embree.lib_name);
    println!("cargo:rustc-env=GLINT_EMBREE_MAJOR={}", embree.major);
}

fn generate_bindings() {
    let out = PathBuf::from(env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let bindings = bindgen::Builder::default()
        .header("ffi/shim.h")
        .allowlist_function("glint_.*")
        .allowlist_type("glint_.*")
        .allowlist_var("GLINT_.*")
        .rustified_enum("glint_build_quality")
        .derive_default(true)
        .derive_copy(true)
        .layout_tests(true)
        .generate()
        .unwrap_or_else(|e| {
            eprintln!(
                "glint: bindgen could not read ffi/shim.h ({e}).\n  bindgen needs libclang: sudo apt-get install libclang-dev   (or run scripts/setup.sh)"
            );
            std::process::exit(1);
        });
    bindings
        .write_to_file(out.join("shim_bindings.rs"))
        .expect("OUT_DIR is writable");
}
