//! Determinism: the same seed gives bit-identical images whatever the thread count (and so
//! whatever order tiles finish in); different seeds give different images; passes continue the
//! sample sequence.

use glint::accel::BackendKind;
use glint::render::{
    self, AovSelection, FilterKind, FilterSpec, PixelSampling, RenderSettings, TileScheduler,
};

/// The demo scene (mirrors, several lights) with its camera.
fn demo() -> (glint::scene::Scene, glint::scene::Camera) {
    let mut scene = glint::scene::demo::demo_scene().expect("demo scene");
    glint::scene::defaults::complete(&mut scene);
    let camera = scene.cameras[0].clone();
    (scene, camera)
}

fn bits(image: &render::Image<glam::Vec3>) -> Vec<[u32; 3]> {
    image
        .pixels
        .iter()
        .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
        .collect()
}

fn settings(
    sampling: PixelSampling,
    filter: FilterKind,
    threads: usize,
    seed: u64,
) -> RenderSettings {
    RenderSettings {
        integrator: glint::render::Integrator::Direct,
        width: 61,
        height: 37,
        spp: 6,
        seed,
        sampling,
        filter: FilterSpec::new(filter),
        threads,
        aovs: AovSelection {
            albedo: true,
            normal: true,
            depth: true,
            ..AovSelection::default()
        },
        ..RenderSettings::default()
    }
}

fn backends() -> Vec<BackendKind> {
    let mut v = vec![BackendKind::Bvh];
    if cfg!(feature = "embree") {
        v.push(BackendKind::Embree);
    }
    v
}

#[test]
fn one_thread_and_many_give_identical_bytes() {
    let (scene, camera) = demo();
    for backend in backends() {
        let accel = render::prepare(&scene, backend, Default::default()).expect("build");
        for (sampling, filter) in [
            (PixelSampling::Sobol, FilterKind::Mitchell),
            (PixelSampling::Independent, FilterKind::Gaussian),
            (PixelSampling::Stratified, FilterKind::Box),
        ] {
            let render = |threads| {
                render::render(
                    &scene,
                    accel.as_ref(),
                    &camera,
                    &settings(sampling, filter, threads, 11),
                    None,
                )
                .expect("render")
            };
            let one = render(1);
            assert!(
                one.image.pixels.iter().any(|p| p.x > 0.0),
                "a black image proves nothing"
            );
            for threads in [2, 3, 7] {
                let many = render(threads);
                let what = format!("{backend} {sampling} {filter}, 1 vs {threads} threads");
                assert_eq!(bits(&one.image), bits(&many.image), "{what}");
                assert_eq!(one.aovs, many.aovs, "{what}: AOVs");
            }
        }
    }
}

#[test]
fn different_seeds_give_different_images() {
    let (scene, camera) = demo();
    let accel = render::prepare(&scene, BackendKind::Bvh, Default::default()).expect("build");
    for sampling in [
        PixelSampling::Sobol,
        PixelSampling::Independent,
        PixelSampling::Stratified,
    ] {
        let render = |seed| {
            render::render(
                &scene,
                accel.as_ref(),
                &camera,
                &settings(sampling, FilterKind::Tent, 2, seed),
                None,
            )
            .expect("render")
        };
        let (a, b) = (render(1), render(2));
        let differing = a
            .image
            .pixels
            .iter()
            .zip(&b.image.pixels)
            .filter(|(p, q)| p != q)
            .count();
        // Edge pixels at least must change: many, not one.
        assert!(differing > 50, "{sampling}: only {differing} pixels differ");
    }
}

#[test]
fn passes_continue_the_sample_sequence() {
    // 8 samples as 2 + 2 + 4 equal 8 in one pass, up to summation order.
    let (scene, camera) = demo();
    let accel = render::prepare(&scene, BackendKind::Bvh, Default::default()).expect("build");
    let s = RenderSettings {
        spp: 8,
        ..settings(PixelSampling::Sobol, FilterKind::Gaussian, 2, 5)
    };
    let whole = render::render(&scene, accel.as_ref(), &camera, &s, None).expect("render");
    let mut passes = TileScheduler::new(&scene, accel.as_ref(), &camera, &s).expect("renderer");
    for spp in [2, 2, 4] {
        passes.render_pass(spp, None);
    }
    assert_eq!(passes.samples_per_pixel(), 8);
    let split = passes.finish();
    for (p, q) in whole.image.pixels.iter().zip(&split.image.pixels) {
        assert!(
            (*p - *q).abs().max_element() <= 1e-5 * p.abs().max_element().max(1.0),
            "{p} vs {q}"
        );
    }
    assert_eq!(whole.stats.rays.traced(), split.stats.rays.traced());
}
