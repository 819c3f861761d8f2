//! Denoising with Open Image Denoise (`--denoise`, feature `denoise`): that it helps (denoised
//! 16 spp against undenoised 64 spp, both against a 4,096-spp reference), that it does not
//! shift energy, that the auxiliary images are what OIDN expects and help it, that a build
//! without the library fails cleanly, and that the command line, batch jobs and the library
//! give the same denoised image.
//!
//! Tests that need the library print why they are skipped in a build without the feature
//! (`scripts/test.sh` turns it on when `scripts/setup.sh` got the library).

use glam::Vec3;
use glint::accel::BackendKind;
use glint::denoise::{self, Auxiliary};
use glint::job::{self, EnvironmentSource, Job, JobImages, PreparedScene, RunOptions};
use glint::render::{AovSelection, Image, RenderSettings};
use std::path::{Path, PathBuf};

use crate::support::{glint, lambert, look_at, quad, scene};

/// True (after saying why) when this build cannot denoise.
fn skipped(test: &str) -> bool {
    if !denoise::AVAILABLE {
        eprintln!(
            "{test}: skipped: glint was built without the `denoise` feature (Open Image \
             Denoise); scripts/test.sh turns it on once scripts/setup.sh has the library"
        );
    }
    !denoise::AVAILABLE
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn studio() -> PathBuf {
    root().join("scenes/demo-env.hdr")
}

/// The demo scene (a checker-textured floor, rough and smooth spheres, a normal-mapped wall)
/// under the studio environment, small.
fn demo_job(spp: u32, seed: u64, denoise: bool) -> Job {
    Job {
        width: Some(128),
        height: Some(72),
        backend: BackendKind::Bvh,
        environment: Some(EnvironmentSource::File {
            path: studio(),
            strength: 1.0,
            rotation_deg: 0.0,
        }),
        settings: RenderSettings {
            spp,
            seed,
            threads: 2,
            ..Job::default().settings
        },
        denoise,
        ..Job::default()
    }
}

fn render(prepared: &PreparedScene, job: &Job) -> JobImages {
    job::run(job, prepared, RunOptions::default())
        .expect("render")
        .images
        .expect("a whole render keeps its images")
}

fn prepare(job: &Job) -> PreparedScene {
    PreparedScene::load(&job.scene, &job.selection, &job.load_options, job.backend).unwrap()
}

/// Relative MSE against `reference`: mean over pixels and channels of (x − r)² / (r² + 0.01).
fn rel_mse(image: &Image<Vec3>, reference: &Image<Vec3>) -> f64 {
    let mut sum = 0.0;
    for (x, r) in image.pixels.iter().zip(&reference.pixels) {
        for c in 0..3 {
            let (x, r) = (f64::from(x[c]), f64::from(r[c]));
            sum += (x - r) * (x - r) / (r * r + 0.01);
        }
    }
    sum / (3 * reference.pixels.len()) as f64
}

fn mean(image: &Image<Vec3>) -> f64 {
    let total: f64 = image
        .pixels
        .iter()
        .map(|p| f64::from(p.x + p.y + p.z))
        .sum();
    total / (3 * image.pixels.len()) as f64
}

#[test]
fn denoised_16_spp_beats_undenoised_64_spp_and_keeps_the_mean() {
    if skipped("denoised_16_spp_beats_undenoised_64_spp_and_keeps_the_mean") {
        return;
    }
    let prepared = prepare(&demo_job(1, 0, false));
    let reference = render(&prepared, &demo_job(4096, 1, false)).image;
    let noisy_64 = render(&prepared, &demo_job(64, 0, false)).image;
    let denoised_16 = render(&prepared, &demo_job(16, 0, true));
    let noisy_16 = denoised_16.noisy.as_ref().expect("the noisy image is kept");
    let (e_denoised, e_64, e_16) = (
        rel_mse(&denoised_16.image, &reference),
        rel_mse(&noisy_64, &reference),
        rel_mse(noisy_16, &reference),
    );
    eprintln!("relMSE: denoised 16 spp {e_denoised:.5}, 16 spp {e_16:.5}, 64 spp {e_64:.5}");
    assert!(e_denoised < e_64, "{e_denoised} vs {e_64}");
    // The denoiser must not shift energy.
    let (m_denoised, m_noisy) = (mean(&denoised_16.image), mean(noisy_16));
    eprintln!("mean: denoised {m_denoised:.5}, noisy {m_noisy:.5}");
    assert!(
        (m_denoised / m_noisy - 1.0).abs() < 0.02,
        "{m_denoised} vs {m_noisy}"
    );
    // The AOVs the job did not ask for are not returned.
    assert!(denoised_16.aovs.albedo.is_none() && denoised_16.aovs.normal.is_none());
}

#[test]
fn auxiliary_images_are_what_oidn_expects() {
    // Albedo in [0, 1]; normals of length at most 1, and unit length where a pixel's samples
    // all see one flat or gently curved surface (most covered pixels: 68 % at 64×36). Needs
    // no library.
    let mut job = demo_job(16, 0, false);
    job.settings.aovs = AovSelection {
        albedo: true,
        normal: true,
        ..AovSelection::default()
    };
    let images = render(&prepare(&job), &job);
    let albedo = images.aovs.albedo.unwrap();
    let normal = images.aovs.normal.unwrap();
    let alpha = images.aovs.alpha.unwrap();
    for a in &albedo.pixels {
        assert!(a.to_array().iter().all(|c| (0.0..=1.0).contains(c)), "{a}");
    }
    let mut covered = 0;
    let mut unit = 0;
    for (n, a) in normal.pixels.iter().zip(&alpha.pixels) {
        assert!(n.length() <= 1.0 + 1e-4, "{n}");
        if *a == 1.0 {
            covered += 1;
            unit += usize::from((n.length() - 1.0).abs() < 1e-2);
        }
    }
    assert!(covered > 100, "{covered}");
    // Pixels over the normal-mapped wall, silhouettes and the small spheres average several
    // normals; the floor, the walls' flat parts and the large spheres do not.
    assert!(unit * 10 >= covered * 6, "{unit} of {covered} unit normals");
    // What glint hands OIDN is clamped into its ranges whatever the AOVs hold.
    assert!(
        denoise::albedo_input(&albedo)
            .iter()
            .all(|v| (0.0..=1.0).contains(v))
    );
    assert!(
        denoise::normal_input(&normal)
            .iter()
            .all(|v| (-1.0..=1.0).contains(v))
    );
}

#[test]
fn auxiliaries_do_not_hurt_on_a_constant_albedo_scene() {
    if skipped("auxiliaries_do_not_hurt_on_a_constant_albedo_scene") {
        return;
    }
    // Grey Lambertian quads (a floor, a back wall and two tilted panels), one material, lit
    // by the studio. With a constant albedo the albedo image tells OIDN nothing the normal
    // image does not: the result must be no worse than the colour alone.
    let grey = lambert(Vec3::splat(0.5), true);
    let meshes = vec![
        quad(Vec3::ZERO, Vec3::X * 2.0, Vec3::Z * 2.0, 0),
        quad(Vec3::new(0.0, 1.0, -2.0), Vec3::X * 2.0, Vec3::Y, 0),
        quad(
            Vec3::new(-0.8, 0.5, 0.0),
            Vec3::new(0.3, 0.0, 0.3),
            Vec3::Y * 0.5,
            0,
        ),
        quad(
            Vec3::new(0.8, 0.4, 0.3),
            Vec3::new(0.3, 0.0, -0.3),
            Vec3::new(0.0, 0.4, 0.1),
            0,
        ),
    ];
    let mut scene = scene(meshes, vec![grey], Vec::new());
    scene.cameras.push(look_at(
        Vec3::new(0.0, 1.5, 3.5),
        Vec3::new(0.0, 0.4, 0.0),
        Vec3::Y,
        0.8,
    ));
    let prepared = PreparedScene::new(scene, "grey quads".into(), BackendKind::Bvh).unwrap();
    let job = |spp: u32, seed: u64| {
        let mut job = demo_job(spp, seed, false);
        job.settings.aovs = AovSelection {
            albedo: true,
            normal: true,
            ..AovSelection::default()
        };
        job
    };
    let reference = render(&prepared, &job(4096, 1)).image;
    let noisy = render(&prepared, &job(8, 0));
    let albedo = noisy.aovs.albedo.as_ref().unwrap();
    let spread = albedo
        .pixels
        .iter()
        .filter(|a| a.max_element() > 0.0)
        .fold((f32::INFINITY, 0.0f32), |(lo, hi), a| {
            (lo.min(a.x), hi.max(a.x))
        });
    eprintln!("albedo range over covered pixels: {spread:?}");
    let with_aux = denoise::denoise(
        &noisy.image,
        Some(Auxiliary {
            albedo,
            normal: noisy.aovs.normal.as_ref().unwrap(),
        }),
        2,
    )
    .unwrap();
    let colour_only = denoise::denoise(&noisy.image, None, 2).unwrap();
    let (e_aux, e_colour, e_noisy) = (
        rel_mse(&with_aux, &reference),
        rel_mse(&colour_only, &reference),
        rel_mse(&noisy.image, &reference),
    );
    eprintln!("relMSE: with aux {e_aux:.5}, colour only {e_colour:.5}, noisy {e_noisy:.5}");
    assert!(e_aux <= e_colour * 1.05, "{e_aux} vs {e_colour}");
    assert!(e_aux < e_noisy, "{e_aux} vs {e_noisy}");
}

#[test]
fn the_command_line_denoises_or_fails_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let env = studio().display().to_string();
    let out = glint(
        &[
            "render",
            "--width",
            "32",
            "--height",
            "18",
            "--spp",
            "2",
            "--env",
            &env,
            "--denoise",
            "-o",
            "d.png",
        ],
        dir.path(),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    if denoise::AVAILABLE {
        assert!(out.status.success(), "{stderr}");
        assert!(dir.path().join("d.png").exists());
        assert!(stderr.contains("denoised"), "{stderr}");
    } else {
        // Without the library: non-zero, one line naming the fix, no file.
        assert!(!out.status.success());
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
        assert!(stderr.contains("--features denoise"), "{stderr}");
        assert!(!dir.path().join("d.png").exists());
    }
}

#[test]
fn batch_and_library_denoise_as_the_command_line_does() {
    if skipped("batch_and_library_denoise_as_the_command_line_does") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let demo_glb = root().join("scenes/demo.glb").display().to_string();
    let env = studio().display().to_string();
    let cli = glint(
        &[
            "render",
            &demo_glb,
            "--width",
            "40",
            "--height",
            "24",
            "--spp",
            "4",
            "--seed",
            "3",
            "--env",
            &env,
            "--threads",
            "2",
            "--denoise",
            "-o",
            "cli.exr",
            "-q",
        ],
        dir.path(),
    );
    assert!(
        cli.status.success(),
        "{}",
        String::from_utf8_lossy(&cli.stderr)
    );
    std::fs::write(
        dir.path().join("jobs.toml"),
        format!(
            "[[job]]\nscene = \"{demo_glb}\"\nwidth = 40\nheight = 24\nspp = 4\nseed = 3\nenv = \"{env}\"\n\
             denoise = true\noutput = \"batch.exr\"\n"
        ),
    )
    .unwrap();
    let batch = glint(&["batch", "jobs.toml", "--threads", "2", "-q"], dir.path());
    assert!(
        batch.status.success(),
        "{}",
        String::from_utf8_lossy(&batch.stderr)
    );
    let a = std::fs::read(dir.path().join("cli.exr")).unwrap();
    let b = std::fs::read(dir.path().join("batch.exr")).unwrap();
    assert!(
        a == b,
        "the batch job's EXR differs from the command line's"
    );
    // The library job: the same denoised radiance, the noisy one as the EXR's layer.
    let mut job = demo_job(4, 3, true);
    job.scene = glint::job::SceneSource::File(root().join("scenes/demo.glb"));
    job.width = Some(40);
    job.height = Some(24);
    job.backend = BackendKind::default();
    let images = render(&prepare(&job), &job);
    let exr = exr::prelude::read_all_flat_layers_from_file(dir.path().join("cli.exr")).unwrap();
    let channel = |name: &str| -> Vec<f32> {
        let layer = &exr.layer_data[0];
        let ch = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == name)
            .unwrap_or_else(|| panic!("no channel {name}"));
        ch.sample_data.values_as_f32().collect()
    };
    let (r, noisy_r) = (channel("R"), channel("noisy.R"));
    let lib_r: Vec<f32> = images.image.pixels.iter().map(|p| p.x).collect();
    let lib_noisy_r: Vec<f32> = images.noisy.unwrap().pixels.iter().map(|p| p.x).collect();
    assert!(
        r.iter()
            .zip(&lib_r)
            .all(|(a, b)| a.to_bits() == b.to_bits())
    );
    assert!(
        noisy_r
            .iter()
            .zip(&lib_noisy_r)
            .all(|(a, b)| a.to_bits() == b.to_bits())
    );
    assert!(
        r != noisy_r,
        "the denoised and the noisy radiance are the same"
    );
}
