//! Feature `denoise`: when Open Image Denoise comes from a folder (`OIDN_DIR`, which
//! `.cargo/config.toml` points at the `.oidn/` that `scripts/fetch-oidn.sh` fills), the extension
//! module finds it at import time through an rpath, as glint's own binaries do (glint's
//! build.rs). A system install needs nothing.

use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=OIDN_DIR");
    if std::env::var_os("CARGO_FEATURE_DENOISE").is_none() {
        return;
    }
    if let Some(dir) = std::env::var_os("OIDN_DIR").map(PathBuf::from) {
        let lib = dir.join("lib");
        if lib.join("libOpenImageDenoise.so").exists() {
            println!("cargo:rustc-link-arg-cdylib=-Wl,-rpath,{}", lib.display());
        }
    }
}
