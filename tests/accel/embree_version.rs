//! The Embree the binary links is the one build.rs found: the shim's compiled-in major version
//! and header version agree with what build.rs exported, and, when a script states which major
//! it built against (`GLINT_EXPECT_EMBREE_MAJOR`, set by `tools/check-embree4.sh`), with that.

#![cfg(feature = "embree")]

use glint::accel::embree;

/// The major version build.rs detected from the headers (`cargo:rustc-env`).
fn build_script_major() -> i32 {
    env!("GLINT_EMBREE_MAJOR")
        .parse()
        .expect("build.rs exports GLINT_EMBREE_MAJOR as a number")
}

#[test]
fn shim_major_matches_build_script() {
    let major = embree::embree_major();
    assert!(major == 3 || major == 4, "Embree major {major}");
    assert_eq!(major, build_script_major());
}

#[test]
fn header_version_string_has_the_same_major() {
    let version = embree::embree_version();
    let leading: i32 = version
        .split('.')
        .next()
        .and_then(|m| m.parse().ok())
        .unwrap_or_else(|| panic!("RTC_VERSION_STRING {version:?} is not MAJOR.MINOR.PATCH"));
    assert_eq!(leading, embree::embree_major(), "headers say {version}");
}

#[test]
fn major_is_the_one_the_caller_expects() {
    // Unset in plain `cargo test`: any supported major is fine there.
    let Ok(expected) = std::env::var("GLINT_EXPECT_EMBREE_MAJOR") else {
        return;
    };
    let expected: i32 = expected
        .parse()
        .expect("GLINT_EXPECT_EMBREE_MAJOR must be 3 or 4");
    assert_eq!(
        embree::embree_major(),
        expected,
        "linked Embree {} ({}), expected major {expected}",
        embree::embree_major(),
        embree::embree_version()
    );
}
