//! Finds Embree (4 or 3), compiles the C shim in `ffi/` against it, and generates the Rust
//! bindings of the shim's own header with bindgen.
//!
//! Search order: `EMBREE_DIR` (a prefix with `include/embree{4,3}` and `lib`), then pkg-config
//! (`embree4`, `embree3`), then the standard include and library paths. Debian ships no
//! pkg-config file for Embree, so the standard paths are what finds it there.
//!
//! Overrides for unusual installs (e.g. a library taken from a Python wheel, see
//! `tools/check-embree4.sh`): `EMBREE_INCLUDE_DIR` (the folder holding `embree4/` or
//! `embree3/`), `EMBREE_LIB_DIR`, and `EMBREE_LIB`: the library's link name (`embree4`) or its
//! exact file name (`libembree4-4aef3270.so.4`, linked verbatim). A directory given explicitly
//! that holds no Embree is an error, never a silent fall-back to another install.
//!
//! Every failure stops the build with one message (`cargo::error`) that names the fix.
//!
//! It also tabulates the directional albedo of single-scattering GGX for the BSDFs' energy
//! compensation (`src/bsdf/albedo_quadrature.rs`, compiled into this script as a module), so
//! that no render computes it at start-up.

use std::env;
use std::path::{Path, PathBuf};

// The quadrature behind the energy-compensation table, shared with the crate (which tests
// the table against it); it uses only glam, std and the microfacet model.
#[allow(dead_code)]
#[path = "src/bsdf/albedo_quadrature.rs"]
mod albedo_quadrature;
#[allow(dead_code)]
#[path = "src/bsdf/microfacet.rs"]
mod microfacet;

/// Where Embree was found.
struct Embree {
    major: u32,
    include_dir: PathBuf,
    lib_dirs: Vec<PathBuf>,
    lib_name: String,
}

/// Why no usable Embree was found; each line becomes one line of the build error.
type Failure = Vec<String>;

const NOT_FOUND: &[&str] = &[
    "glint: Embree 3 or 4 was not found (no embree4/ or embree3/ headers with their library in \
     EMBREE_DIR, pkg-config or the standard paths).",
    "  Install it:  sudo apt-get install libembree-dev   (Debian/Ubuntu; scripts/setup.sh does it)",
    "  or point EMBREE_DIR at an Embree 3 or 4 install (a folder with include/ and lib/),",
    "  or build the pure-Rust backend alone:  cargo build --no-default-features",
];

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    denoise_rpath();
    ggx_albedo_table();
    println!("cargo:rerun-if-changed=ffi/shim.h");
    println!("cargo:rerun-if-changed=ffi/shim.c");
    for var in [
        "EMBREE_DIR",
        "EMBREE_INCLUDE_DIR",
        "EMBREE_LIB_DIR",
        "EMBREE_LIB",
        "PKG_CONFIG_PATH",
    ] {
        println!("cargo:rerun-if-env-changed={var}");
    }
    if env::var_os("CARGO_FEATURE_EMBREE").is_none() {
        return;
    }
    let embree = match find_embree() {
        Ok(found) => found,
        Err(lines) => fail(&lines),
    };
    // An upgraded or replaced Embree must rebuild the shim against the new headers.
    println!(
        "cargo:rerun-if-changed={}",
        embree
            .include_dir
            .join(header_dir(embree.major))
            .join("rtcore_config.h")
            .display()
    );
    println!(
        "cargo:rustc-env=GLINT_EMBREE_INCLUDE={}",
        embree.include_dir.display()
    );
    compile_shim(&embree);
    generate_bindings();
}

/// Writes `$OUT_DIR/ggx_albedo_table.rs`: `ALBEDO` (`[E0, E1]` per roughness column and μ
/// row) and `AVERAGE` (`[A0, A1]` per column), as exact f32 bit patterns. The columns are
/// independent, so they are integrated on a few threads and joined in order (the same
/// numbers for any thread count). A table already written from the same sources is kept: the
/// script also reruns for the shim, and the quadrature takes seconds in an unoptimised
/// build script.
fn ggx_albedo_table() {
    use albedo_quadrature::{MU_NODES, ROUGHNESS_NODES, column};
    use std::hash::{Hash, Hasher};
    let sources = ["src/bsdf/microfacet.rs", "src/bsdf/albedo_quadrature.rs"];
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    for source in sources {
        println!("cargo:rerun-if-changed={source}");
        std::fs::read(source)
            .unwrap_or_else(|e| fail(&[format!("glint: cannot read {source}: {e}")]))
            .hash(&mut hasher);
    }
    let stamp = format!("// sources {:016x}\n", hasher.finish());
    let out = PathBuf::from(env::var_os("OUT_DIR").unwrap_or_default()).join("ggx_albedo_table.rs");
    if std::fs::read_to_string(&out).is_ok_and(|old| old.starts_with(&stamp)) {
        return;
    }
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(8);
    let columns: Vec<(Vec<[f32; 2]>, [f32; 2])> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|t| {
                scope.spawn(move || {
                    (t..ROUGHNESS_NODES)
                        .step_by(threads)
                        .map(|j| (j, column(j)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        let mut all: Vec<_> = workers
            .into_iter()
            .flat_map(|w| {
                w.join().unwrap_or_else(|_| {
                    fail(&["glint: the albedo table's quadrature panicked".into()])
                })
            })
            .collect();
        all.sort_by_key(|(j, _)| *j);
        all.into_iter().map(|(_, c)| c).collect()
    });
    let bits = |v: [f32; 2]| {
        format!(
            "[f32::from_bits({:#010x}), f32::from_bits({:#010x})]",
            v[0].to_bits(),
            v[1].to_bits()
        )
    };
    let mut text = stamp;
    text.push_str(&format!(
        "/// `[E0, E1]` at `[j * MU_NODES + i]` (roughness node `j`, μ row `i`), from the build script.\n\
         static ALBEDO: [[f32; 2]; {}] = [\n",
        MU_NODES * ROUGHNESS_NODES
    ));
    for (albedo, _) in &columns {
        for &e in albedo {
            text.push_str(&bits(e));
            text.push_str(",\n");
        }
    }
    text.push_str(&format!(
        "];\n/// `[A0, A1]` per roughness node, from the build script.\nstatic AVERAGE: [[f32; 2]; {ROUGHNESS_NODES}] = [\n"
    ));
    for (_, average) in &columns {
        text.push_str(&bits(*average));
        text.push_str(",\n");
    }
    text.push_str("];\n");
    let tmp = out.with_extension("rs.tmp");
    if let Err(e) = std::fs::write(&tmp, text).and_then(|()| std::fs::rename(&tmp, &out)) {
        fail(&[format!("glint: cannot write {}: {e}", out.display())]);
    }
}

/// Feature `denoise`: when Open Image Denoise comes from a folder (`OIDN_DIR`, set by
/// `.cargo/config.toml` to the `.oidn/` that `scripts/fetch-oidn.sh` fills) rather than the
/// system, glint's binaries, tests and examples find it at run time through an rpath, so no
/// `LD_LIBRARY_PATH` is needed. A system install needs nothing.
fn denoise_rpath() {
    println!("cargo:rerun-if-env-changed=OIDN_DIR");
    if env::var_os("CARGO_FEATURE_DENOISE").is_none() {
        return;
    }
    if let Some(dir) = env::var_os("OIDN_DIR").map(PathBuf::from) {
        let lib = dir.join("lib");
        if lib.join("libOpenImageDenoise.so").exists() {
            println!("cargo:rustc-link-arg=-Wl,-rpath,{}", lib.display());
        }
    }
}

/// Stops the build with one error message, one `cargo::error` per line, instead of a wall of
/// compiler or linker errors further on.
fn fail(lines: &[String]) -> ! {
    for line in lines {
        println!("cargo::error={line}");
    }
    // Cargo fails the build because errors were logged; exiting 0 keeps it from adding the
    // script's whole stdout and stderr to the message.
    std::process::exit(0)
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

fn find_embree() -> Result<Embree, Failure> {
    if let Some(found) = from_explicit_dirs()? {
        return Ok(found);
    }
    if let Some(found) = from_pkg_config() {
        return Ok(found);
    }
    from_standard_paths().ok_or_else(|| NOT_FOUND.iter().map(|s| s.to_string()).collect())
}

/// Whether a library file name was given (`libembree4-xyz.so.4`) rather than a link name.
fn is_file_name(lib: &str) -> bool {
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

fn compile_shim(embree: &Embree) {
    let mut build = cc::Build::new();
    build
        .file("ffi/shim.c")
        .include("ffi")
        .define("GLINT_EMBREE_MAJOR", embree.major.to_string().as_str())
        .flag_if_supported("-std=c11")
        .warnings(true)
        .extra_warnings(true)
        .opt_level(3);
    // Embree's headers are a system library's: their own warnings are not ours to fix.
    if build.get_compiler().is_like_msvc() {
        build.include(&embree.include_dir);
    } else {
        build.flag("-isystem").flag(embree.include_dir.as_os_str());
    }
    build.compile("glint_shim");
    for dir in &embree.lib_dirs {
        println!("cargo:rustc-link-search=native={}", dir.display());
        // Libraries outside the loader's default path (EMBREE_DIR, a wheel) must still be found
        // when the binaries and tests run.
        if !dir.starts_with("/usr/lib") && !dir.starts_with("/lib") {
            println!("cargo:rustc-link-arg=-Wl,-rpath,{}", dir.display());
        }
    }
    if is_file_name(&embree.lib_name) {
        // A file name that does not follow lib<name>.so (a wheel's hashed libembree4-*.so.4).
        println!("cargo:rustc-link-lib=dylib:+verbatim={}", embree.lib_name);
    } else {
        println!("cargo:rustc-link-lib=dylib={}", embree.lib_name);
    }
    println!("cargo:rustc-env=GLINT_EMBREE_MAJOR={}", embree.major);
}

fn generate_bindings() {
    let Some(out) = env::var_os("OUT_DIR").map(PathBuf::from) else {
        fail(&["glint: OUT_DIR is not set; build.rs must be run by cargo.".into()]);
    };
    let bindings = bindgen::Builder::default()
        .header("ffi/shim.h")
        .allowlist_function("glint_.*")
        .allowlist_type("glint_.*")
        .allowlist_var("GLINT_.*")
        .rustified_enum("glint_build_quality")
        .derive_default(true)
        .derive_copy(true)
        .layout_tests(true)
        .generate();
    let bindings = match bindings {
        Ok(b) => b,
        Err(e) => fail(&[
            format!("glint: bindgen could not read ffi/shim.h ({e})."),
            "  bindgen needs libclang: sudo apt-get install libclang-dev   (or run \
             scripts/setup.sh)"
                .into(),
        ]),
    };
    let path = out.join("shim_bindings.rs");
    if let Err(e) = bindings.write_to_file(&path) {
        fail(&[format!("glint: could not write {}: {e}", path.display())]);
    }
}
