//! Wrapper lifetimes: building and dropping thousands of scenes releases every Embree handle.
//! The shim counts the device, scene and geometry handles it creates and releases
//! (`glint_live_handles`); the count must come back to where it started. (A valgrind run of
//! this test, as the README describes, confirms the count with Embree's own allocations.)

#![cfg(feature = "embree")]

use glam::Vec3;
use glint::accel::embree::{self, EmbreeAccel};
use glint::accel::{Accel, BuildOptions, BuildQuality, Ray, TriangleMesh};
use glint::procedural;

/// The handle count is process-wide: the tests in this file must not run at the same time.
static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn serial() -> std::sync::MutexGuard<'static, ()> {
    SERIAL
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

#[test]
fn thousands_of_scenes_release_their_handles() {
    let _serial = serial();
    let small = procedural::displaced_sphere(1, 0.0, 1);
    let soup = procedural::triangle_soup(50, 0.1, 2);
    let meshes = [small.as_triangle_mesh(), soup.as_triangle_mesh()];
    // The first build creates the process-wide device, which lives on by design.
    drop(EmbreeAccel::build(&meshes, BuildOptions::default()).expect("build"));
    let baseline = embree::live_handles();
    for i in 0..3_000 {
        let options = BuildOptions {
            quality: BuildQuality::ALL[i % 3],
            robust: i % 2 == 0,
            ..BuildOptions::default()
        };
        let accel = EmbreeAccel::build(&meshes, options).expect("build");
        // Use it, so a lazily built structure really exists.
        assert!(
            accel
                .intersect(&Ray::new(Vec3::Z * 3.0, -Vec3::Z))
                .is_some()
        );
        assert!(embree::live_handles() > baseline);
    }
    assert_eq!(embree::live_handles(), baseline, "scenes leaked handles");
}

#[test]
fn scenes_outlive_a_dropped_device() {
    let _serial = serial();
    let mesh = procedural::displaced_sphere(1, 0.0, 1);
    let before = embree::live_handles();
    let device = std::sync::Arc::new(embree::Device::new().expect("device"));
    let accel = EmbreeAccel::build_on(
        std::sync::Arc::clone(&device),
        &[mesh.as_triangle_mesh()],
        BuildOptions::default(),
    )
    .expect("build");
    drop(device);
    // The scene holds the device: queries still work.
    assert!(
        accel
            .intersect(&Ray::new(Vec3::Z * 3.0, -Vec3::Z))
            .is_some()
    );
    drop(accel);
    assert_eq!(embree::live_handles(), before);
}

#[test]
fn embree_errors_become_rust_errors() {
    let _serial = serial();
    // An empty scene is valid; a mesh with no triangles is valid too. Rejections happen in
    // glint's own validation before Embree sees the data.
    let positions = [Vec3::ZERO, Vec3::new(f32::NAN, 0.0, 0.0), Vec3::Y];
    let indices = [[0u32, 1, 2]];
    let mesh = [TriangleMesh {
        positions: &positions,
        indices: &indices,
        instances: &[],
    }];
    let err = glint::accel::build(
        glint::accel::BackendKind::Embree,
        &mesh,
        BuildOptions::default(),
    )
    .err()
    .expect("NaN rejected");
    assert!(err.to_string().contains("non-finite"), "{err}");
    let indices = [[0u32, 1, 7]];
    let mesh = [TriangleMesh {
        positions: &positions[..1],
        indices: &indices,
        instances: &[],
    }];
    let err = glint::accel::build(
        glint::accel::BackendKind::Bvh,
        &mesh,
        BuildOptions::default(),
    )
    .err()
    .expect("bad index rejected");
    assert!(err.to_string().contains("indexes past"), "{err}");
    // An empty scene builds and misses everything on both backends.
    for &kind in glint::accel::BackendKind::available() {
        let accel = glint::accel::build(kind, &[], BuildOptions::default()).expect("empty");
        assert!(accel.intersect(&Ray::new(Vec3::ZERO, Vec3::X)).is_none());
        assert!(!accel.occluded(&Ray::new(Vec3::ZERO, Vec3::X)));
    }
}
