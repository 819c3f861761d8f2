//! The C shim in `ffi/`, compiled against the Embree found, and bindgen's Rust bindings of the
//! shim's own header.

use crate::embree_search::{Embree, is_file_name};
use crate::fail;
use std::env;
use std::path::PathBuf;

/// Compiles `ffi/shim.c` against `embree` and tells cargo how to link Embree.
pub fn compile_shim(embree: &Embree) {
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

/// Writes `$OUT_DIR/shim_bindings.rs` from `ffi/shim.h`.
pub fn generate_bindings() {
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
