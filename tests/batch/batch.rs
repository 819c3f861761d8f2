//! `glint batch` and `glint merge`: sharding, resume, failure isolation, job-file errors, and
//! partial renders merging into the single-machine image.

use glam::Vec3;
use glint::accel::{BackendKind, BuildOptions};
use glint::batch::jobs;
use glint::cli::job_options::RenderOptions;
use glint::job::LightSource;
use glint::render::partial::{merge, render_partial};
use glint::render::{AovSelection, RenderInputs, RenderSettings, render};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use crate::support::{batch_report as report, demo, glint, job_statuses, stderr};

/// A job file of `2 + 3·2` tiny jobs on the demo scene: two plain jobs and a sweep.
fn job_file(dir: &Path) -> PathBuf {
    let text = format!(
        r#"[defaults]
scene = "{}"
width = 16
height = 12
spp = 1

[[job]]
output = "out/plain.png"

[[job]]
output = "out/placed.exr"
camera = {{ position = [0, 1, 5], look_at = [0, 0, 0] }}

[[sweep]]
output = "out/turn-{{frame:02}}-{{spp}}.png"
spp = [1, 2]
orbit = {{ frames = 3, center = [0, 0.5, 0], radius = 4, height = 1 }}
"#,
        demo().display()
    );
    let path = dir.join("jobs.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// (index, status) of each job in a report.
fn statuses(report: &serde_json::Value) -> Vec<(u64, String)> {
    job_statuses(report)
}

#[test]
fn shards_together_take_every_job_exactly_once() {
    let dir = tempfile::tempdir().unwrap();
    let all = jobs::load(&job_file(dir.path()), &RenderOptions).unwrap();
    assert_eq!(all.len(), 8);
    for count in 1..=9u32 {
        let mut seen = vec![0; all.len()];
        for index in 0..count {
            let shard = glint::batch::Shard { index, count };
            for job in all.iter().filter(|j| shard.takes(j.index)) {
                seen[job.index] += 1;
            }
        }
        assert!(seen.iter().all(|&n| n == 1), "{count} shards: {seen:?}");
    }
}

#[test]
fn shard_runs_render_every_output_once() {
    let dir = tempfile::tempdir().unwrap();
    let file = job_file(dir.path());
    let total = jobs::load(&file, &RenderOptions).unwrap().len();
    let mut rendered = Vec::new();
    for i in 0..3 {
        let name = format!("r{i}.json");
        let out = glint(
            &[
                "batch",
                "jobs.toml",
                "--shard",
                &format!("{i}/3"),
                "--report",
                &name,
                "-q",
            ],
            dir.path(),
        );
        assert!(out.status.success(), "{}", stderr(&out));
        for (index, status) in statuses(&report(&dir.path().join(&name))) {
            assert_eq!(status, "rendered");
            assert_eq!(index % 3, i, "job {index} in shard {i}/3");
            rendered.push(index);
        }
    }
    rendered.sort();
    assert_eq!(rendered, (0..total as u64).collect::<Vec<_>>());
    for job in jobs::load(&file, &RenderOptions).unwrap() {
        assert!(job.output().is_file(), "{} missing", job.output().display());
    }
}

#[test]
fn resume_skips_complete_outputs_and_renders_the_rest() {
    let dir = tempfile::tempdir().unwrap();
    let file = job_file(dir.path());
    let first = glint(&["batch", "jobs.toml", "-q"], dir.path());
    assert!(first.status.success(), "{}", stderr(&first));
    let all = jobs::load(&file, &RenderOptions).unwrap();
    let bytes = |p: &Path| std::fs::read(p).unwrap();
    let before: Vec<Vec<u8>> = all.iter().map(|j| bytes(j.output())).collect();

    // What a batch killed midway leaves: job 1's output not yet written and the temporary
    // file of its unfinished write; plus job 2's output replaced by a foreign, truncated file.
    std::fs::remove_file(all[1].output()).unwrap();
    let out_dir = all[1].output().parent().unwrap();
    std::fs::write(out_dir.join(".placed.exr.abc123.tmp"), b"half").unwrap();
    std::fs::write(all[2].output(), &before[2][..before[2].len() / 2]).unwrap();

    let second = glint(
        &["batch", "jobs.toml", "--report", "r.json", "-q"],
        dir.path(),
    );
    assert!(second.status.success(), "{}", stderr(&second));
    let status = statuses(&report(&dir.path().join("r.json")));
    for (index, s) in &status {
        let expected = if [1, 2].contains(index) {
            "rendered"
        } else {
            "skipped"
        };
        assert_eq!(s, expected, "job {index}");
    }
    for (job, old) in all.iter().zip(&before) {
        // Renders are deterministic, so re-rendered outputs equal the first run's too.
        assert_eq!(&bytes(job.output()), old, "{}", job.output().display());
    }

    let forced = glint(
        &["batch", "jobs.toml", "--force", "--report", "f.json", "-q"],
        dir.path(),
    );
    assert!(forced.status.success());
    let status = statuses(&report(&dir.path().join("f.json")));
    assert!(status.iter().all(|(_, s)| s == "rendered"), "{status:?}");
}

/// The metallic-roughness model is part of what a finished output must match: an EXR names
/// its model in its header (`glint.brdf`), so a batch whose job asks for another model
/// renders it again instead of skipping it (a PNG cannot say and is skipped, as documented);
/// and partial EXRs of different models refuse to merge.
#[test]
fn resume_and_merge_check_the_brdf_model() {
    let dir = tempfile::tempdir().unwrap();
    let file = job_file(dir.path());
    let first = glint(&["batch", "jobs.toml", "-q"], dir.path());
    assert!(first.status.success(), "{}", stderr(&first));
    let text = std::fs::read_to_string(&file).unwrap();
    std::fs::write(
        &file,
        text.replace("spp = 1\n", "spp = 1\nbrdf = \"spec\"\n"),
    )
    .unwrap();
    let second = glint(
        &["batch", "jobs.toml", "--report", "r.json", "-q"],
        dir.path(),
    );
    assert!(second.status.success(), "{}", stderr(&second));
    for (index, s) in statuses(&report(&dir.path().join("r.json"))) {
        // Job 1 is the only EXR.
        let expected = if index == 1 { "rendered" } else { "skipped" };
        assert_eq!(s, expected, "job {index}");
    }
    let third = glint(
        &["batch", "jobs.toml", "--report", "t.json", "-q"],
        dir.path(),
    );
    assert!(third.status.success(), "{}", stderr(&third));
    let status = statuses(&report(&dir.path().join("t.json")));
    assert!(status.iter().all(|(_, s)| s == "skipped"), "{status:?}");

    let scene = demo().display().to_string();
    let part = |brdf: &str, shard: &str, out: &str| {
        let args = [
            "render", &scene, "--width", "16", "--height", "12", "--spp", "2", "-q", "--shard",
            shard, "-o", out, "--brdf", brdf,
        ];
        let run = glint(&args, dir.path());
        assert!(run.status.success(), "{}", stderr(&run));
    };
    part("spec", "0/2", "s0.exr");
    part("spec", "1/2", "s1.exr");
    part("compensated", "1/2", "c1.exr");
    let mixed = glint(&["merge", "s0.exr", "c1.exr", "-o", "m.exr"], dir.path());
    assert!(!mixed.status.success());
    assert!(stderr(&mixed).contains("--brdf"), "{}", stderr(&mixed));
    let same = glint(&["merge", "s0.exr", "s1.exr", "-o", "m.exr"], dir.path());
    assert!(same.status.success(), "{}", stderr(&same));
    let merged = exr::prelude::read_all_flat_layers_from_file(dir.path().join("m.exr")).unwrap();
    let brdf = merged.layer_data[0]
        .attributes
        .other
        .iter()
        .find(|(k, _)| **k == *"glint.brdf")
        .map(|(_, v)| format!("{v:?}"));
    assert!(
        brdf.is_some_and(|v| v.contains("spec")),
        "merged EXR header"
    );
}

#[test]
fn a_broken_job_fails_alone_and_the_exit_status_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        r#"[defaults]
width = 16
height = 12
spp = 1
[[job]]
scene = "{demo}"
output = "good-1.png"
[[job]]
scene = "no-such-scene.glb"
output = "bad.png"
[[job]]
scene = "{demo}"
output = "good-2.png"
"#,
        demo = demo().display()
    );
    std::fs::write(dir.path().join("jobs.toml"), text).unwrap();
    let out = glint(
        &["batch", "jobs.toml", "--report", "r.json", "-q"],
        dir.path(),
    );
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("no-such-scene.glb"),
        "{}",
        stderr(&out)
    );
    let report = report(&dir.path().join("r.json"));
    assert_eq!(
        statuses(&report),
        [
            (0, "rendered".to_string()),
            (1, "failed".to_string()),
            (2, "rendered".to_string())
        ]
    );
    let error = report["jobs"][1]["error"].as_str().unwrap();
    assert!(error.contains("no-such-scene.glb"), "{error}");
    assert_eq!(report["failed"], 1);
    assert!(report["jobs"][0]["rays"].as_u64().unwrap() > 0);
    assert!(dir.path().join("good-1.png").is_file() && dir.path().join("good-2.png").is_file());
    assert!(!dir.path().join("bad.png").exists());
}

/// The error for a job file, which must name the file, the job and the key.
fn job_file_error(body: &str) -> String {
    let path = Path::new("/somewhere/jobs.toml");
    jobs::parse(body, path, &RenderOptions)
        .unwrap_err()
        .to_string()
}

#[test]
fn bad_job_files_name_the_file_the_job_and_the_key() {
    let cases = [
        (
            "[[job]]\nscene = \"a.glb\"\noutput = \"a.png\"\n[[job]]\nscene = \"a.glb\"\noutput = \"b.png\"\nspeed = 3",
            ["[[job]] 1", "\"speed\"", "unknown key"],
        ),
        (
            "[[job]]\nscene = \"a.glb\"\noutput = \"a.png\"\nspp = \"many\"",
            ["[[job]] 0", "\"spp\"", "many"],
        ),
        (
            "[[job]]\nscene = \"a.glb\"\noutput = \"a.png\"\nphotometric = 1",
            ["[[job]] 0", "\"photometric\"", "true or false"],
        ),
        (
            "[defaults]\nspp = 2\n[[job]]\noutput = \"a.png\"",
            ["[[job]] 0", "\"scene\"", "missing"],
        ),
        (
            "[[job]]\nscene = 4\noutput = \"a.png\"",
            ["[[job]] 0", "\"scene\"", "integer"],
        ),
        (
            "[[job]]\nscene = \"a.glb\"\noutput = \"a.png\"\ncamera = { position = [0, 0, 1] }",
            ["[[job]] 0", "\"camera\"", "look_at"],
        ),
        (
            "[[job]]\nscene = \"a.glb\"\noutput = \"a.png\"\n[[job]]\nscene = \"b.glb\"\noutput = \"a.png\"",
            ["[[job]] 1", "a.png", "[[job]] 0"],
        ),
        (
            "[[sweep]]\nscene = \"a.glb\"\noutput = \"a.png\"\nseed = [1, 2]",
            ["[[sweep]] 0", "{seed}", "a.png"],
        ),
        (
            "[[job]]\nscene = \"a.glb\"\noutput = ",
            ["TOML", "line", ""],
        ),
        // Values glint render refuses before rendering refuse the file, blamed on the key.
        (
            "[[job]]\nscene = \"a.glb\"\noutput = \"a.png\"\nbackground = [1, 2]",
            ["[[job]] 0", "\"background\"", "R,G,B"],
        ),
        (
            "[[job]]\nscene = \"a.glb\"\noutput = \"a.png\"\ntime_budget = 0",
            ["[[job]] 0", "\"time_budget\"", "positive number of seconds"],
        ),
        (
            "[[job]]\nscene = \"a.glb\"\noutput = \"a.png\"\nintegrator = \"bidirectional\"",
            ["[[job]] 0", "\"integrator\"", "bidirectional"],
        ),
    ];
    for (body, needles) in cases {
        let message = job_file_error(body);
        assert!(message.contains("/somewhere/jobs.toml"), "{message}");
        for needle in needles {
            assert!(message.contains(needle), "'{needle}' not in: {message}");
        }
    }
    // Relative paths are taken from the job file's folder.
    let ok = jobs::parse(
        "[[job]]\nscene = \"s/a.glb\"\noutput = \"o/a.png\"\nlights = \"l.txt\"",
        Path::new("/somewhere/jobs.toml"),
        &RenderOptions,
    )
    .unwrap();
    assert_eq!(ok[0].scene(), Path::new("/somewhere/s/a.glb"));
    assert_eq!(ok[0].output(), Path::new("/somewhere/o/a.png"));
    assert_eq!(
        ok[0].render.lights,
        [LightSource::File("/somewhere/l.txt".into())]
    );
}

#[test]
fn an_unusable_job_file_fails_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("jobs.toml"),
        format!(
            "[[job]]\nscene = \"{}\"\noutput = \"a.png\"\n[[job]]\nscene = \"x.glb\"\noutput = \"b.png\"\nspp = -1",
            demo().display()
        ),
    )
    .unwrap();
    let out = glint(&["batch", "jobs.toml"], dir.path());
    assert!(!out.status.success());
    assert!(stderr(&out).contains("[[job]] 1"), "{}", stderr(&out));
    assert!(!dir.path().join("a.png").exists(), "nothing renders");
}

/// Largest |a − b| / (|b| + 1e-6) over all components.
fn max_relative_difference(a: &[Vec3], b: &[Vec3]) -> f32 {
    a.iter()
        .zip(b)
        .flat_map(|(a, b)| (0..3).map(move |i| (a[i] - b[i]).abs() / (b[i].abs() + 1e-6)))
        .fold(0.0, f32::max)
}

/// The stated tolerance: the full render adds each pixel's contributions one at a time in
/// f32, the merge adds per-part f32 sums in f64, so they differ by rounding only: at most
/// γ(n)·Σ for n additions (n ≤ spp · (1 + lights · (1 + bounces)) here, well under 100), a
/// relative 100 · 2⁻²⁴ ≈ 6e-6. We allow 1e-5.
const MERGE_TOLERANCE: f32 = 1e-5;

#[test]
fn merged_parts_equal_the_single_render_with_the_same_seed() {
    let mut scene = glint::scene::gltf::load(&demo()).unwrap();
    let camera = glint::scene::defaults::default_camera(&scene);
    if scene.lights.is_empty() {
        scene.lights = glint::scene::defaults::default_lights(&scene, &camera);
    }
    let accel =
        glint::render::prepare(&scene, BackendKind::default(), BuildOptions::default()).unwrap();
    let settings = RenderSettings {
        integrator: glint::render::Integrator::Direct,
        width: 40,
        height: 30,
        spp: 6,
        seed: 11,
        aovs: AovSelection {
            albedo: true,
            normal: false,
            depth: true,
            ..AovSelection::default()
        },
        ..RenderSettings::default()
    };
    let single = render(&scene, accel.as_ref(), &camera, &settings, None).unwrap();
    let inputs = RenderInputs {
        scene: &scene,
        lights: &scene.lights,
        accel: accel.as_ref(),
        camera: &camera,
        pool: None,
        mipmaps: None,
        environment: None,
        area_lights: None,
        cancel: None,
    };
    let part = |r: std::ops::Range<u32>| render_partial(&inputs, &settings, r, None).unwrap().0;
    // Given out of order: the merge sorts by sample range.
    let parts = [part(5..6), part(0..2), part(2..5)];
    let (image, aovs) = merge(&parts).unwrap();
    let diff = max_relative_difference(&image.pixels, &single.image.pixels);
    assert!(diff <= MERGE_TOLERANCE, "radiance differs by {diff}");
    let albedo = max_relative_difference(
        &aovs.albedo.unwrap().pixels,
        &single.aovs.albedo.unwrap().pixels,
    );
    assert!(albedo <= MERGE_TOLERANCE, "albedo differs by {albedo}");
    let depth_single = single.aovs.depth.unwrap().pixels;
    for (m, s) in aovs.depth.unwrap().pixels.iter().zip(&depth_single) {
        assert!(
            (m - s).abs() <= MERGE_TOLERANCE * (s.abs() + 1e-6),
            "{m} vs {s}"
        );
    }
    // The parts are not interchangeable with another seed's: the test can fail.
    let other = render(
        &scene,
        accel.as_ref(),
        &camera,
        &RenderSettings {
            seed: 12,
            ..settings
        },
        None,
    )
    .unwrap();
    assert!(max_relative_difference(&image.pixels, &other.image.pixels) > 1e-3);
    // Missing samples are an error, not a darker image.
    assert!(merge(&parts[..2]).is_err());
}

#[test]
fn render_shards_merge_through_files_into_the_full_render() {
    let dir = tempfile::tempdir().unwrap();
    let scene = demo().display().to_string();
    let common = [
        "render", &scene, "--width", "24", "--height", "16", "--spp", "5", "--seed", "3", "-q",
    ];
    let run = |extra: &[&str]| {
        let args: Vec<&str> = common.iter().chain(extra).copied().collect();
        let out = glint(&args, dir.path());
        assert!(out.status.success(), "{}", stderr(&out));
    };
    run(&["-o", "full.exr"]);
    run(&["--shard", "0/2", "-o", "p0.exr"]);
    run(&["--shard", "1/2", "-o", "p1.exr"]);
    let png_part = glint(
        &[common.as_slice(), &["--shard", "0/2", "-o", "p.png"]].concat(),
        dir.path(),
    );
    assert!(!png_part.status.success(), "a partial render needs EXR");
    let merged = glint(
        &["merge", "p1.exr", "p0.exr", "-o", "merged.exr", "-q"],
        dir.path(),
    );
    assert!(merged.status.success(), "{}", stderr(&merged));
    let read = |name: &str| -> Vec<Vec3> {
        let image = exr::prelude::read_first_rgba_layer_from_file(
            dir.path().join(name),
            |size, _| vec![Vec3::ZERO; size.width() * size.height()],
            |pixels, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
                pixels[pos.y() * 24 + pos.x()] = Vec3::new(r, g, b);
            },
        )
        .unwrap();
        image.layer_data.channel_data.pixels
    };
    let diff = max_relative_difference(&read("merged.exr"), &read("full.exr"));
    assert!(diff <= MERGE_TOLERANCE, "merged differs by {diff}");
    let incomplete = glint(&["merge", "p1.exr", "-o", "bad.exr"], dir.path());
    assert!(!incomplete.status.success());
    assert!(
        stderr(&incomplete).contains("--sample-range 0..2"),
        "{}",
        stderr(&incomplete)
    );
    assert!(!dir.path().join("bad.exr").exists());
}

/// Parts rendered by different Embree kernels (here SSE2 and SSE4.2 pinned through
/// `--embree-isa`, as two farm nodes with different CPUs would run) record them in the EXR, and
/// `glint merge` says that the merged image is not bit for bit a one-machine render; parts of
/// one kernel merge without the note.
#[cfg(feature = "embree")]
#[test]
fn merge_notes_parts_rendered_by_different_kernels() {
    let dir = tempfile::tempdir().unwrap();
    let scene = demo().display().to_string();
    let part = |isa: &str, shard: &str, out: &str| {
        let args = [
            "render",
            &scene,
            "--width",
            "16",
            "--height",
            "12",
            "--spp",
            "2",
            "-q",
            "--shard",
            shard,
            "-o",
            out,
            "--embree-isa",
            isa,
        ];
        let run = glint(&args, dir.path());
        assert!(run.status.success(), "{}", stderr(&run));
    };
    part("sse2", "0/2", "a0.exr");
    part("sse2", "1/2", "a1.exr");
    part("sse4.2", "1/2", "b1.exr");
    let same = glint(&["merge", "a0.exr", "a1.exr", "-o", "same.exr"], dir.path());
    assert!(same.status.success(), "{}", stderr(&same));
    assert!(!stderr(&same).contains("kernels"), "{}", stderr(&same));
    let mixed = glint(
        &["merge", "a0.exr", "b1.exr", "-o", "mixed.exr"],
        dir.path(),
    );
    assert!(mixed.status.success(), "{}", stderr(&mixed));
    let note = stderr(&mixed);
    assert!(
        note.contains("different ray-query kernels")
            && note.contains("sse2 (a0.exr)")
            && note.contains("sse4.2 (b1.exr)"),
        "{note}"
    );
    // An instruction set this CPU lacks, or an unknown name, is an error, not another kernel.
    let bad = glint(
        &["render", &scene, "-o", "x.png", "--embree-isa", "avx3"],
        dir.path(),
    );
    assert!(!bad.status.success());
    assert!(stderr(&bad).contains("avx3"), "{}", stderr(&bad));
}

#[test]
fn jobs_sharing_a_scene_match_separate_renders() {
    // One batch job and the same settings through `glint render` give the same file: the
    // shared load, pool and lights change nothing.
    let dir = tempfile::tempdir().unwrap();
    job_file(dir.path());
    let out = glint(&["batch", "jobs.toml", "-q"], dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let scene = demo().display().to_string();
    let single = glint(
        &[
            "render",
            &scene,
            "--width",
            "16",
            "--height",
            "12",
            "--spp",
            "1",
            "-o",
            "single.png",
            "-q",
        ],
        dir.path(),
    );
    assert!(single.status.success());
    let a = std::fs::read(dir.path().join("single.png")).unwrap();
    let b = std::fs::read(dir.path().join("out/plain.png")).unwrap();
    assert_eq!(a, b);
    let names: BTreeSet<String> = std::fs::read_dir(dir.path().join("out"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.ends_with(".tmp")), "{names:?}");
    assert_eq!(names.len(), 8);
}
