//! Every shared asset renders without error on both backends, and the two images agree.
//!
//! Bound: relative RMSE (RMSE over the mean radiance of the Embree image) below 1e-3. Both
//! backends see the same triangles and glint shades their hits identically, so the images can
//! only differ where the backends break a tie differently (coincident faces, shared edges):
//! a handful of pixels at most. A real disagreement (a missed or wrong surface over a region)
//! pushes the error far above the bound.

use glam::Vec3;
use glint::accel::{BackendKind, BuildOptions};
use glint::render::{self, PixelSampling, RenderSettings};
use glint::scene::defaults;
use std::path::Path;

const REL_RMSE_MAX: f64 = 1e-3;

const ASSETS: [&str; 5] = [
    "2CylinderEngine/2CylinderEngine.glb",
    "BoxTextured/BoxTextured.gltf",
    "Cameras/Cameras.gltf",
    "DamagedHelmet/glTF/DamagedHelmet.gltf",
    "Suzanne/glTF/Suzanne.gltf",
];

fn render_asset(file: &str, backend: BackendKind) -> Vec<Vec3> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/scenes")
        .join(file);
    let mut scene = glint::scene::gltf::load(&path).unwrap_or_else(|e| panic!("{e}"));
    defaults::complete(&mut scene);
    let camera = scene.cameras[0].clone();
    let accel = render::prepare(&scene, backend, BuildOptions::default())
        .unwrap_or_else(|e| panic!("{file} on {backend}: {e}"));
    let settings = RenderSettings {
        integrator: glint::render::Integrator::Direct,
        width: 160,
        height: 90,
        spp: 1,
        sampling: PixelSampling::PixelCenter,
        ..RenderSettings::default()
    };
    let out = render::render(&scene, accel.as_ref(), &camera, &settings, None)
        .unwrap_or_else(|e| panic!("{file} on {backend}: {e}"));
    out.image.pixels
}

#[test]
fn every_shared_asset_renders_alike_on_both_backends() {
    for file in ASSETS {
        let images: Vec<Vec<Vec3>> = BackendKind::available()
            .iter()
            .map(|&b| render_asset(file, b))
            .collect();
        let reference = &images[0];
        assert!(
            reference
                .iter()
                .all(|p| p.is_finite() && p.min_element() >= 0.0),
            "{file}: negative or non-finite radiance"
        );
        let mean = reference
            .iter()
            .map(|p| p.element_sum() as f64 / 3.0)
            .sum::<f64>()
            / reference.len() as f64;
        let lit = reference.iter().filter(|p| p.max_element() > 0.0).count();
        assert!(lit > reference.len() / 50, "{file}: only {lit} lit pixels");
        for other in &images[1..] {
            let mse = reference
                .iter()
                .zip(other)
                .map(|(a, b)| (*a - *b).length_squared() as f64 / 3.0)
                .sum::<f64>()
                / reference.len() as f64;
            let rel_rmse = mse.sqrt() / mean;
            eprintln!("{file}: mean radiance {mean:.4}, relative RMSE {rel_rmse:.2e}");
            assert!(rel_rmse < REL_RMSE_MAX, "{file}: relative RMSE {rel_rmse}");
        }
    }
}
