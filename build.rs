//! The build script: three jobs, one module each under `build/`.
//!
//! - `build/embree_search.rs`: finds Embree (4 or 3); the search order and the overrides for
//!   unusual installs (e.g. a library taken from a Python wheel, see `tools/check-embree4.sh`)
//!   are documented there and in docs/embree4.md.
//! - `build/shim.rs`: compiles the C shim in `ffi/` against it and generates the Rust bindings
//!   of the shim's own header with bindgen.
//! - `build/albedo_table.rs`: tabulates the directional albedo of single-scattering GGX
//!   (`src/bsdf/albedo_quadrature.rs`, compiled into this script as a module).
//!
//! Every failure stops the build with one message (`cargo::error`) that names the fix.

use std::env;
use std::path::PathBuf;

// The quadrature behind the energy-compensation table, shared with the crate (which tests
// the table against it); it uses only glam, std and the microfacet model.
#[allow(dead_code)]
#[path = "src/bsdf/albedo_quadrature.rs"]
mod albedo_quadrature;
#[allow(dead_code)]
#[path = "src/bsdf/microfacet.rs"]
mod microfacet;

#[path = "build/albedo_table.rs"]
mod albedo_table;
#[path = "build/embree_search.rs"]
mod embree_search;
#[path = "build/shim.rs"]
mod shim;

use embree_search::{find_embree, header_dir};

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=build");
    denoise_rpath();
    albedo_table::ggx_albedo_table();
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
    shim::compile_shim(&embree);
    shim::generate_bindings();
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
pub fn fail(lines: &[String]) -> ! {
    for line in lines {
        println!("cargo::error={line}");
    }
    // Cargo fails the build because errors were logged; exiting 0 keeps it from adding the
    // script's whole stdout and stderr to the message.
    std::process::exit(0)
}
