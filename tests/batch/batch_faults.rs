//! `glint batch` under faults: scenes that fail at load, SIGKILL at random moments, two
//! batches on one job file, `--shard auto`, outputs escaping the job folder, unwritable
//! folders, file modes under the umask, and `glint merge` given parts of different scenes.
//! Every image is tiny (16×12 or so, 1–2 spp): these tests check bookkeeping, not pixels.

use rand::{Rng, SeedableRng};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Instant;

use crate::support::{batch_report as report, demo, glint_command, job_statuses, stderr};

/// Environment variables `--shard auto` reads: cleared for every child, so that a CI runner
/// inside a Slurm or Kubernetes job does not change these tests.
const SHARD_VARS: [&str; 7] = [
    "SLURM_ARRAY_TASK_ID",
    "SLURM_ARRAY_TASK_COUNT",
    "SLURM_ARRAY_TASK_MIN",
    "SLURM_ARRAY_TASK_MAX",
    "SLURM_ARRAY_TASK_STEP",
    "JOB_COMPLETION_INDEX",
    "GLINT_SHARD_COUNT",
];

fn command(args: &[&str], cwd: &Path) -> Command {
    let mut command = glint_command(args, cwd);
    for var in SHARD_VARS {
        command.env_remove(var);
    }
    command
}

fn glint(args: &[&str], cwd: &Path) -> Output {
    command(args, cwd).output().expect("run glint")
}

/// index → status of each job in a report.
fn statuses(report: &serde_json::Value) -> BTreeMap<u64, String> {
    job_statuses(report).into_iter().collect()
}

/// A job file of `n` tiny demo-scene jobs (a seed sweep), PNG and EXR outputs alternating.
fn many_jobs(dir: &Path, n: usize, size: (u32, u32)) -> PathBuf {
    let seeds: Vec<String> = (0..n / 2).map(|s| s.to_string()).collect();
    let text = format!(
        "[defaults]\nscene = \"{}\"\nwidth = {}\nheight = {}\nspp = 1\n\
         [[sweep]]\noutput = \"out/png-{{seed:03}}.png\"\nseed = [{seeds}]\n\
         [[sweep]]\noutput = \"out/exr-{{seed:03}}.exr\"\nseed = [{seeds}]\n",
        demo().display(),
        size.0,
        size.1,
        seeds = seeds.join(", ")
    );
    let path = dir.join("jobs.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// Whether the image at `path` decodes completely.
fn decodes(path: &Path) -> bool {
    match path.extension().and_then(|e| e.to_str()) {
        Some("png") => image::open(path).is_ok(),
        Some("exr") => exr::prelude::read_all_flat_layers_from_file(path).is_ok(),
        _ => false,
    }
}

/// Names in `folder` that are glint's temporary or claim files.
fn leftovers(folder: &Path) -> Vec<String> {
    std::fs::read_dir(folder)
        .map(|entries| {
            entries
                .flatten()
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n.contains(".glint-"))
                .collect()
        })
        .unwrap_or_default()
}

/// The outputs in `out/` (not hidden files).
fn outputs(folder: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(folder)
        .map(|entries| {
            entries
                .flatten()
                .map(|e| e.path())
                .filter(|p| !p.file_name().unwrap().to_string_lossy().starts_with('.'))
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    files
}

#[test]
fn a_first_scene_that_fails_at_load_fails_alone() {
    let dir = tempfile::tempdir().unwrap();
    // Malformed glTF (a buffer view past its buffer) and a file that is not glTF at all.
    std::fs::write(
        dir.path().join("broken.gltf"),
        r#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":4,"uri":"data:application/octet-stream;base64,AAAAAA=="}],
            "bufferViews":[{"buffer":0,"byteLength":4000}],
            "accessors":[{"bufferView":0,"componentType":5126,"count":300,"type":"VEC3"}],
            "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]}"#,
    )
    .unwrap();
    std::fs::write(dir.path().join("noise.glb"), b"glTF\x02\x00\x00\x00garbage").unwrap();
    let text = format!(
        "[defaults]\nwidth = 16\nheight = 12\nspp = 1\n\
         [[job]]\nscene = \"broken.gltf\"\noutput = \"a.png\"\n\
         [[job]]\nscene = \"{demo}\"\noutput = \"b.png\"\n\
         [[job]]\nscene = \"noise.glb\"\noutput = \"c.png\"\n\
         [[job]]\nscene = \"{demo}\"\noutput = \"d.png\"\nseed = 2\n",
        demo = demo().display()
    );
    std::fs::write(dir.path().join("jobs.toml"), text).unwrap();
    let out = glint(
        &["batch", "jobs.toml", "--report", "r.json", "-q"],
        dir.path(),
    );
    assert!(!out.status.success());
    let r = report(&dir.path().join("r.json"));
    let status = statuses(&r);
    assert_eq!(
        status.values().collect::<Vec<_>>(),
        ["failed", "rendered", "failed", "rendered"]
    );
    for (index, file) in [(0, "broken.gltf"), (2, "noise.glb")] {
        let error = r["jobs"][index]["error"].as_str().unwrap();
        assert!(error.contains(file), "job {index}: {error}");
        assert!(stderr(&out).contains(file), "{}", stderr(&out));
    }
    assert!(!dir.path().join("a.png").exists() && !dir.path().join("c.png").exists());
    assert!(decodes(&dir.path().join("b.png")) && decodes(&dir.path().join("d.png")));
    assert!(
        leftovers(dir.path()).is_empty(),
        "{:?}",
        leftovers(dir.path())
    );
}

/// SIGKILL at random moments (seeded): afterwards every output present decodes, and a rerun
/// renders exactly the missing jobs, removes the stray temporary and claim files, and leaves
/// every output decodable.
#[test]
fn a_batch_killed_at_random_moments_resumes_exactly_the_missing_jobs() {
    const JOBS: usize = 24;
    let mut rng = rand_pcg::Pcg64::seed_from_u64(0x5161_4b11);
    // One uninterrupted run gives the time scale the kills are drawn from.
    let probe = tempfile::tempdir().unwrap();
    many_jobs(probe.path(), JOBS, (24, 16));
    let start = Instant::now();
    let full = glint(
        &["batch", "jobs.toml", "-q", "--threads", "1"],
        probe.path(),
    );
    assert!(full.status.success(), "{}", stderr(&full));
    let full_time = start.elapsed();
    let mut partial_trials = 0;
    for trial in 0..6 {
        let dir = tempfile::tempdir().unwrap();
        many_jobs(dir.path(), JOBS, (24, 16));
        let mut child = command(&["batch", "jobs.toml", "-q", "--threads", "1"], dir.path())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let delay = full_time.mul_f64(rng.random_range(0.02..0.75));
        std::thread::sleep(delay);
        child.kill().unwrap(); // SIGKILL on Unix
        child.wait().unwrap();
        let out = dir.path().join("out");
        let present = outputs(&out);
        for file in &present {
            assert!(decodes(file), "trial {trial}: truncated {}", file.display());
        }
        if present.len() < JOBS {
            partial_trials += 1;
        }
        eprintln!(
            "trial {trial}: killed after {delay:?} of ~{full_time:?}, {} of {JOBS} outputs \
             present, {} leftover files",
            present.len(),
            leftovers(&out).len()
        );
        let rerun = glint(
            &["batch", "jobs.toml", "--report", "r.json", "-q"],
            dir.path(),
        );
        assert!(rerun.status.success(), "{}", stderr(&rerun));
        let r = report(&dir.path().join("r.json"));
        assert_eq!(
            r["rendered"].as_u64().unwrap() as usize,
            JOBS - present.len(),
            "trial {trial} (killed after {delay:?}): {} outputs were present",
            present.len()
        );
        assert_eq!(r["skipped"].as_u64().unwrap() as usize, present.len());
        let status = statuses(&r);
        let jobs = glint::batch::jobs::load(
            &dir.path().join("jobs.toml"),
            &glint::cli::job_options::RenderOptions,
        )
        .unwrap();
        for job in &jobs {
            let was_present = present.iter().any(|p| p.ends_with(job.output()));
            let expected = if was_present { "skipped" } else { "rendered" };
            assert_eq!(status[&(job.index as u64)], expected, "trial {trial}");
            assert!(decodes(job.output()));
        }
        assert_eq!(outputs(&out).len(), JOBS);
        assert!(
            leftovers(&out).is_empty(),
            "trial {trial}: {:?}",
            leftovers(&out)
        );
    }
    // The kills must have interrupted some runs, or the test shows nothing.
    assert!(
        partial_trials >= 2,
        "only {partial_trials} trials were interrupted"
    );
}

#[test]
fn two_batches_on_one_job_file_render_each_job_once() {
    const JOBS: usize = 30;
    let dir = tempfile::tempdir().unwrap();
    many_jobs(dir.path(), JOBS, (64, 48));
    let spawn = |report: &str| {
        command(
            &[
                "batch",
                "jobs.toml",
                "--report",
                report,
                "-q",
                "--threads",
                "1",
            ],
            dir.path(),
        )
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
    };
    let (a, b) = (spawn("a.json"), spawn("b.json"));
    let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
    assert!(a.status.success(), "{}", stderr(&a));
    assert!(b.status.success(), "{}", stderr(&b));
    let (ra, rb) = (
        report(&dir.path().join("a.json")),
        report(&dir.path().join("b.json")),
    );
    let (sa, sb) = (statuses(&ra), statuses(&rb));
    for index in 0..JOBS as u64 {
        let rendered = [&sa, &sb]
            .iter()
            .filter(|s| s[&index] == "rendered")
            .count();
        assert_eq!(
            rendered, 1,
            "job {index}: {} and {}",
            sa[&index], sb[&index]
        );
    }
    // Both processes did work, so they really ran side by side.
    assert!(
        ra["rendered"].as_u64().unwrap() > 0 && rb["rendered"].as_u64().unwrap() > 0,
        "a rendered {}, b {}",
        ra["rendered"],
        rb["rendered"]
    );
    let out = dir.path().join("out");
    assert!(outputs(&out).iter().all(|p| decodes(p)));
    assert!(leftovers(&out).is_empty(), "{:?}", leftovers(&out));
}

#[test]
fn shard_auto_covers_every_job_once_for_each_scheduler() {
    let dir = tempfile::tempdir().unwrap();
    many_jobs(dir.path(), 10, (8, 6));
    fn var(k: &str, v: String) -> (String, String) {
        (k.to_string(), v)
    }
    type Setting = (
        &'static str,
        fn(u32) -> Vec<(String, String)>,
        Vec<&'static str>,
    );
    let settings: Vec<Setting> = vec![
        (
            "SLURM_ARRAY_TASK_ID",
            |i| {
                vec![
                    var("SLURM_ARRAY_TASK_ID", i.to_string()),
                    var("SLURM_ARRAY_TASK_COUNT", "3".into()),
                ]
            },
            vec![],
        ),
        (
            "SLURM_ARRAY_TASK_MAX",
            // --array=1-3: ids from 1, no COUNT.
            |i| {
                vec![
                    var("SLURM_ARRAY_TASK_ID", (i + 1).to_string()),
                    var("SLURM_ARRAY_TASK_MIN", "1".into()),
                    var("SLURM_ARRAY_TASK_MAX", "3".into()),
                ]
            },
            vec![],
        ),
        (
            "--shard-count 3",
            |i| vec![var("JOB_COMPLETION_INDEX", i.to_string())],
            vec!["--shard-count", "3"],
        ),
        (
            "GLINT_SHARD_COUNT=3",
            |i| {
                vec![
                    var("JOB_COMPLETION_INDEX", i.to_string()),
                    var("GLINT_SHARD_COUNT", "3".into()),
                ]
            },
            vec![],
        ),
    ];
    for (named, vars, extra) in &settings {
        let mut seen = Vec::new();
        for i in 0..3 {
            let mut args = vec!["batch", "jobs.toml", "--shard", "auto", "--list"];
            args.extend(extra);
            let out = command(&args, dir.path()).envs(vars(i)).output().unwrap();
            assert!(out.status.success(), "{named}: {}", stderr(&out));
            let said = stderr(&out);
            assert!(
                said.contains(named) && said.contains(&format!("shard {i}/3")),
                "{said}"
            );
            for line in String::from_utf8_lossy(&out.stdout).lines() {
                seen.push(line.split('\t').next().unwrap().parse::<usize>().unwrap());
            }
        }
        seen.sort();
        assert_eq!(seen, (0..10).collect::<Vec<_>>(), "{named}");
    }
    let none = glint(
        &["batch", "jobs.toml", "--shard", "auto", "--list"],
        dir.path(),
    );
    assert!(!none.status.success());
    let said = stderr(&none);
    assert!(
        said.contains("SLURM_ARRAY_TASK_ID") && said.contains("JOB_COMPLETION_INDEX"),
        "{said}"
    );
    let no_count = command(
        &["batch", "jobs.toml", "--shard", "auto", "--list"],
        dir.path(),
    )
    .env("JOB_COMPLETION_INDEX", "1")
    .output()
    .unwrap();
    assert!(!no_count.status.success());
    assert!(
        stderr(&no_count).contains("--shard-count"),
        "{}",
        stderr(&no_count)
    );
}

#[test]
fn outputs_escaping_the_job_folder_are_refused_unless_an_output_root_allows_them() {
    let base = tempfile::tempdir().unwrap();
    let jobs_dir = base.path().join("jobs");
    std::fs::create_dir_all(&jobs_dir).unwrap();
    let outside = base.path().join("outside");
    let text = format!(
        "[defaults]\nscene = \"{demo}\"\nwidth = 8\nheight = 6\nspp = 1\n\
         [[job]]\noutput = \"inside.png\"\n\
         [[job]]\noutput = \"../outside/up.png\"\n\
         [[job]]\noutput = \"{abs}\"\n",
        demo = demo().display(),
        abs = outside.join("absolute.png").display()
    );
    std::fs::write(jobs_dir.join("jobs.toml"), &text).unwrap();
    let out = glint(
        &["batch", "jobs.toml", "--report", "r.json", "-q"],
        &jobs_dir,
    );
    assert!(!out.status.success());
    let r = report(&jobs_dir.join("r.json"));
    assert_eq!(
        statuses(&r).values().collect::<Vec<_>>(),
        ["rendered", "failed", "failed"]
    );
    for index in [1, 2] {
        let error = r["jobs"][index]["error"].as_str().unwrap();
        assert!(error.contains("outside the output root"), "{error}");
        assert!(
            stderr(&out).contains(&format!("job {index} ([[job]] {index}) failed")),
            "{}",
            stderr(&out)
        );
    }
    assert!(!outside.exists(), "nothing is created outside");

    // Allowed by the flag, and by the job file's key.
    let allowed = glint(
        &["batch", "jobs.toml", "-q", "--output-root", ".."],
        &jobs_dir,
    );
    assert!(allowed.status.success(), "{}", stderr(&allowed));
    assert!(outside.join("up.png").is_file() && outside.join("absolute.png").is_file());
    std::fs::remove_dir_all(&outside).unwrap();
    std::fs::write(
        jobs_dir.join("jobs.toml"),
        format!("output_root = \"..\"\n{text}"),
    )
    .unwrap();
    let keyed = glint(&["batch", "jobs.toml", "-q"], &jobs_dir);
    assert!(keyed.status.success(), "{}", stderr(&keyed));
    assert!(outside.join("up.png").is_file());
}

#[test]
fn an_unwritable_output_folder_fails_before_anything_renders() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("blocker"), b"a file, not a folder").unwrap();
    let readonly = dir.path().join("readonly");
    std::fs::create_dir(&readonly).unwrap();
    let text = format!(
        "[defaults]\nscene = \"{demo}\"\nwidth = 8\nheight = 6\nspp = 1\n\
         [[job]]\noutput = \"ok.png\"\n\
         [[job]]\noutput = \"blocker/x.png\"\n\
         [[job]]\noutput = \"readonly/y.png\"\n",
        demo = demo().display()
    );
    std::fs::write(dir.path().join("jobs.toml"), text).unwrap();
    #[cfg(unix)]
    let privileged = {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&readonly, std::fs::Permissions::from_mode(0o555)).unwrap();
        // Root ignores permission bits: then only the blocked folder can be tested.
        std::fs::write(readonly.join("t"), b"x")
            .map(|()| std::fs::remove_file(readonly.join("t")))
            .is_ok()
    };
    #[cfg(not(unix))]
    let privileged = true;
    // Without -q, each rendered job prints "wrote"; the probe failures must come first.
    let out = glint(&["batch", "jobs.toml", "--report", "r.json"], dir.path());
    assert!(!out.status.success());
    let r = report(&dir.path().join("r.json"));
    let said = stderr(&out);
    let wrote = said.find("wrote").expect("job 0 is written");
    let blocked = said.find("job 1 ([[job]] 1) failed").expect("job 1 fails");
    assert!(blocked < wrote, "{said}");
    assert!(r["jobs"][1]["error"].as_str().unwrap().contains("blocker"));
    assert_eq!(r["jobs"][1]["rays"], 0);
    if !privileged {
        let error = r["jobs"][2]["error"].as_str().unwrap();
        assert!(
            error.contains("not writable") && error.contains("readonly"),
            "{error}"
        );
        assert!(said.find("job 2 ([[job]] 2) failed").unwrap() < wrote);
    } else {
        eprintln!("running as root: the permission-bit case is not testable here");
    }
    assert_eq!(r["jobs"][0]["status"], "rendered");
}

#[cfg(unix)]
#[test]
fn outputs_and_reports_get_the_umask_mode() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    many_jobs(dir.path(), 2, (8, 6));
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    for (umask, expected) in [("027", 0o640), ("002", 0o664)] {
        let out = Command::new("sh")
            .arg("-c")
            .arg(format!(
                "umask {umask} && exec \"$0\" batch jobs.toml --force --report r.json -q"
            ))
            .arg(env!("CARGO_BIN_EXE_glint"))
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", stderr(&out));
        for file in outputs(&dir.path().join("out"))
            .iter()
            .chain([&dir.path().join("r.json")])
        {
            assert_eq!(
                mode(file),
                expected,
                "umask {umask}: {} is {:o}",
                file.display(),
                mode(file)
            );
        }
    }
}

#[test]
fn merge_refuses_parts_of_different_scenes_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let part = |scene: &Path, shard: &str, out: &str, extra: &[&str]| {
        let scene = scene.display().to_string();
        let mut args = vec![
            "render", &scene, "--width", "8", "--height", "6", "--spp", "2", "--shard", shard,
            "-o", out, "-q",
        ];
        args.extend(extra);
        let result = glint(&args, dir.path());
        assert!(result.status.success(), "{}", stderr(&result));
    };
    let other = scenes.join("checker-plane.gltf");
    part(&demo(), "0/2", "a0.exr", &[]);
    part(&demo(), "1/2", "a1.exr", &[]);
    part(&other, "1/2", "b1.exr", &[]);
    part(&demo(), "1/2", "c1.exr", &["--time", "0.5"]);
    let good = glint(
        &["merge", "a0.exr", "a1.exr", "-o", "m.exr", "-q"],
        dir.path(),
    );
    assert!(good.status.success(), "{}", stderr(&good));
    let bad = glint(
        &["merge", "a0.exr", "b1.exr", "-o", "x.exr", "-q"],
        dir.path(),
    );
    assert!(!bad.status.success());
    let said = stderr(&bad);
    for name in [
        "a0.exr",
        "b1.exr",
        "demo.glb",
        "checker-plane.gltf",
        "different scenes",
    ] {
        assert!(said.contains(name), "{name} missing from: {said}");
    }
    // Same file, another animation time: refused too.
    let timed = glint(
        &["merge", "a0.exr", "c1.exr", "-o", "x.exr", "-q"],
        dir.path(),
    );
    assert!(!timed.status.success());
    assert!(stderr(&timed).contains("fingerprint"), "{}", stderr(&timed));
    assert!(!dir.path().join("x.exr").exists());
}

/// A `.gltf` whose external texture changes between two parts of its render: the parts'
/// fingerprints differ (they hash every file the scene reads), so `glint merge` refuses them,
/// naming both; parts rendered before the change still merge.
#[test]
fn merge_refuses_parts_rendered_before_and_after_a_texture_changed() {
    use base64::Engine as _;
    let dir = tempfile::tempdir().unwrap();
    // checker-plane.gltf with its embedded texture moved out to checker.png.
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let text = std::fs::read_to_string(scenes.join("checker-plane.gltf")).unwrap();
    let mut gltf: serde_json::Value = serde_json::from_str(&text).unwrap();
    let uri = gltf["images"][0]["uri"].as_str().unwrap().to_string();
    let (_, payload) = uri.split_once(";base64,").unwrap();
    let png = base64::engine::general_purpose::STANDARD
        .decode(payload)
        .unwrap();
    std::fs::write(dir.path().join("checker.png"), png).unwrap();
    gltf["images"][0]["uri"] = "checker.png".into();
    std::fs::write(dir.path().join("plane.gltf"), gltf.to_string()).unwrap();
    let part = |shard: &str, out: &str| {
        let result = glint(
            &[
                "render",
                "plane.gltf",
                "--width",
                "8",
                "--height",
                "6",
                "--spp",
                "2",
                "--shard",
                shard,
                "-o",
                out,
                "-q",
            ],
            dir.path(),
        );
        assert!(result.status.success(), "{}", stderr(&result));
    };
    part("0/2", "before0.exr");
    part("1/2", "before1.exr");
    // Another valid texture under the same name.
    image::RgbImage::from_pixel(4, 4, image::Rgb([200, 30, 30]))
        .save(dir.path().join("checker.png"))
        .unwrap();
    part("1/2", "after1.exr");
    let good = glint(
        &["merge", "before0.exr", "before1.exr", "-o", "m.exr", "-q"],
        dir.path(),
    );
    assert!(good.status.success(), "{}", stderr(&good));
    let bad = glint(
        &["merge", "before0.exr", "after1.exr", "-o", "x.exr", "-q"],
        dir.path(),
    );
    assert!(!bad.status.success());
    let said = stderr(&bad);
    for name in ["before0.exr", "after1.exr", "plane.gltf", "fingerprint"] {
        assert!(said.contains(name), "{name} missing from: {said}");
    }
    assert!(!dir.path().join("x.exr").exists());
}

#[test]
fn a_frame_sweep_renders_an_animation_at_each_frames_time() {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/khronos");
    let scene = shared.join("BoxAnimated/glTF-Binary/BoxAnimated.glb");
    if !scene.is_file() {
        eprintln!("skipped: {} is missing", scene.display());
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "[[sweep]]\nscene = \"{}\"\nwidth = 64\nheight = 48\nspp = 1\nbackend = \"bvh\"\n\
         output = \"anim_{{frame:04}}.png\"\nframes = \"0..3\"\nfps = 1\n",
        scene.display()
    );
    std::fs::write(dir.path().join("jobs.toml"), text).unwrap();
    let out = glint(
        &["batch", "jobs.toml", "--report", "r.json", "-q"],
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let frames: Vec<Vec<u8>> = (0..3)
        .map(|k| {
            image::open(dir.path().join(format!("anim_{k:04}.png")))
                .unwrap()
                .to_rgb8()
                .into_raw()
        })
        .collect();
    // BoxAnimated moves over its 3.7 s animation: frames 1 s apart differ (under one camera:
    // the default camera frames the rest pose for every frame; at 24×18 the moving part is
    // too small to change a pixel between 1 s and 2 s).
    assert_ne!(frames[0], frames[1]);
    assert_ne!(frames[1], frames[2]);
    let r = report(&dir.path().join("r.json"));
    assert_eq!(r["jobs"][2]["origin"], "[[sweep]] 0, frame=2");
}

/// `asset_root` as a job key (relative to the job file), and `--asset-root` for converge and
/// both benchmarks: a buffer `../elsewhere.bin` outside the root is refused, naming the URI.
#[test]
fn the_asset_root_binds_batch_converge_and_bench() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("root")).unwrap();
    let plane = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/checker-plane.gltf");
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(plane).unwrap()).unwrap();
    let uri = doc["buffers"][0]["uri"].as_str().unwrap().to_string();
    let bytes = base64::Engine::decode(
        &base64::engine::general_purpose::STANDARD,
        uri.split_once(";base64,").unwrap().1,
    )
    .unwrap();
    std::fs::write(dir.path().join("elsewhere.bin"), bytes).unwrap();
    doc["buffers"][0]["uri"] = "../elsewhere.bin".into();
    std::fs::write(dir.path().join("root/escape.gltf"), doc.to_string()).unwrap();
    let text = "[defaults]\nscene = \"root/escape.gltf\"\nwidth = 8\nheight = 6\nspp = 1\n\
                [[job]]\noutput = \"free.png\"\n\
                [[job]]\noutput = \"bound.png\"\nasset_root = \"root\"\n";
    std::fs::write(dir.path().join("jobs.toml"), text).unwrap();
    // Run from another folder: the key resolves against the job file, not the cwd.
    let elsewhere = tempfile::tempdir().unwrap();
    let job_file = dir.path().join("jobs.toml").display().to_string();
    let out = glint(
        &["batch", &job_file, "--report", "r.json", "-q"],
        elsewhere.path(),
    );
    assert!(!out.status.success());
    let r = report(&elsewhere.path().join("r.json"));
    assert_eq!(r["jobs"][0]["status"], "rendered", "{}", stderr(&out));
    let error = r["jobs"][1]["error"].as_str().unwrap();
    assert!(
        error.contains("outside the asset root") && error.contains("../elsewhere.bin"),
        "{error}"
    );
    for args in [
        &[
            "converge",
            "root/escape.gltf",
            "--out",
            "c",
            "--max-spp",
            "1",
            "--reference-spp",
            "1",
            "--width",
            "8",
            "--height",
            "6",
            "--asset-root",
            "root",
        ][..],
        &[
            "bench",
            "render",
            "root/escape.gltf",
            "--asset-root",
            "root",
            "--runs",
            "1",
        ][..],
        &[
            "bench",
            "rays",
            "root/escape.gltf",
            "--quick",
            "--asset-root",
            "root",
        ][..],
    ] {
        let out = glint(args, dir.path());
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(
            stderr(&out).contains("outside the asset root"),
            "{args:?}: {}",
            stderr(&out)
        );
    }
}

/// The address space a capped batch may use: 4 GiB, in KiB for `ulimit -v`. An allocation of
/// gigabytes fails (an abort) instead of exhausting the machine.
const CAP_KIB: u64 = 4 << 20;

/// Most seconds refusing a hostile job file may take (a debug build, a busy machine).
const QUICK_SECONDS: u64 = 60;

/// Runs `glint batch JOBS.toml --list` on `toml` under a 4 GiB address-space cap, killed after
/// [`QUICK_SECONDS`], and checks that it is refused: exit code 1 (no signal, no panic), one
/// line on stderr naming the job file and containing each of `expected`.
fn list_is_refused(toml: &str, expected: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("jobs.toml"), toml).unwrap();
    std::fs::copy(demo(), dir.path().join("demo.glb")).unwrap();
    let started = Instant::now();
    let out = Command::new("bash")
        .arg("-c")
        .arg(format!(
            "ulimit -v {CAP_KIB} && exec timeout -s KILL {QUICK_SECONDS} \"$0\" \"$@\""
        ))
        .arg(env!("CARGO_BIN_EXE_glint"))
        .args(["batch", "jobs.toml", "--list"])
        .env("MALLOC_ARENA_MAX", "2")
        .current_dir(dir.path())
        .output()
        .expect("run glint under ulimit");
    let seconds = started.elapsed().as_secs();
    let err = stderr(&out);
    assert!(seconds < QUICK_SECONDS, "took {seconds} s: {err}");
    assert_eq!(out.status.code(), Some(1), "{:?}: {err}", out.status);
    assert!(!err.contains("panicked"), "{err}");
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "expected one line: {err}");
    assert!(lines[0].contains("jobs.toml"), "{err}");
    for e in expected {
        assert!(lines[0].contains(e), "lacks \"{e}\": {err}");
    }
    assert!(out.stdout.is_empty(), "listed jobs of a refused file");
}

/// A zero padding wider than Rust's formatter accepts (65,535) panicked in the sweep
/// expander, even with `--list`; it is refused naming the key and the width.
#[test]
fn an_output_padding_beyond_the_formatter_is_refused() {
    list_is_refused(
        "[[sweep]]\nscene = \"demo.glb\"\noutput = \"o-{spp:0999999}.png\"\nspp = [1, 2]\n",
        &["[[sweep]] 0", "\"spp\"", "999999"],
    );
}

/// A sweep whose keys multiply to 10⁹ jobs reserved them all at once; it is refused by its
/// count, computed before anything is expanded.
#[test]
fn a_sweep_of_a_billion_jobs_is_refused_by_its_count() {
    let thousand = (0..1000)
        .map(|i| i.to_string())
        .collect::<Vec<_>>()
        .join(", ");
    let toml = format!(
        "[[sweep]]\nscene = \"demo.glb\"\noutput = \"o-{{seed}}-{{spp}}-{{frame}}.png\"\n\
         frames = \"0..1000\"\nfps = 24\nseed = [{thousand}]\nspp = [{thousand}]\n"
    );
    list_is_refused(
        &toml,
        &[
            "[[sweep]] 0",
            "1000000000 jobs",
            "seed (1000) × spp (1000) × frame (1000)",
        ],
    );
}

/// A sweep of the maximum frame count (10⁶) in a file whose output is taken twice: found
/// before any job is expanded, not after minutes of expanding and gigabytes of jobs. With a
/// `[[job]]` beside the full sweep, the file is over the job limit, refused by its count;
/// one frame fewer, the duplicate is found from the output templates.
#[test]
fn a_duplicate_output_is_found_before_a_million_frames_are_expanded() {
    let file = |frames: u32| {
        format!(
            "[[job]]\nscene = \"demo.glb\"\noutput = \"f/0999998.png\"\n\n\
             [[sweep]]\nscene = \"demo.glb\"\noutput = \"f/{{frame:07}}.png\"\n\
             frames = \"0..{frames}\"\nfps = 24\n"
        )
    };
    list_is_refused(
        &file(1_000_000),
        &["the file", "more than the 1000000 jobs"],
    );
    list_is_refused(
        &file(999_999),
        &["[[sweep]] 0, frame=999998", "0999998.png", "[[job]] 0"],
    );
}

/// A file without a camera keeps one default camera through a sequence: it frames the rest
/// pose, not each time's bounds (which would move the camera from frame to frame and make the
/// flow to the next frame disagree with it).
#[test]
fn the_default_camera_is_the_same_at_every_time() {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/khronos");
    let scene = shared.join("InterpolationTest/glTF-Binary/InterpolationTest.glb");
    if !scene.is_file() {
        eprintln!("skipped: {} is missing", scene.display());
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut poses = Vec::new();
    for (k, time) in ["0.4", "1.7"].iter().enumerate() {
        let out = format!("t{k}.png");
        let run = glint(
            &[
                "render",
                scene.to_str().unwrap(),
                "-o",
                &out,
                "--time",
                time,
                "--width",
                "16",
                "--height",
                "9",
                "--spp",
                "1",
                "--backend",
                "bvh",
                "--sidecar",
                "-q",
            ],
            dir.path(),
        );
        assert!(run.status.success(), "{}", stderr(&run));
        let said = stderr(&run);
        assert!(
            !said.contains("not applied"),
            "rest-pose load warned: {said}"
        );
        let sidecar: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.path().join(format!("t{k}.json"))).unwrap(),
        )
        .unwrap();
        poses.push(sidecar["camera"]["world_to_camera_opencv"].clone());
    }
    assert!(poses[0].is_array());
    assert_eq!(poses[0], poses[1]);
}

/// `glint check-gt --next` on two frames of rotating, scaling and translating cubes (shared
/// InterpolationTest): consistent. Before the check left out cells whose backward flow bends
/// inside them (a cube's crease), bilinear interpolation across a crease reported 0.28 px here.
#[test]
fn check_gt_finds_two_frames_of_rotating_cubes_consistent() {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/khronos");
    let scene = shared.join("InterpolationTest/glTF-Binary/InterpolationTest.glb");
    if !scene.is_file() {
        eprintln!("skipped: {} is missing", scene.display());
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for (out, time) in [("a.exr", "1.2"), ("b.exr", "1.3")] {
        let run = glint(
            &[
                "render",
                scene.to_str().unwrap(),
                "-o",
                out,
                "--time",
                time,
                "--width",
                "480",
                "--height",
                "270",
                "--spp",
                "1",
                "--backend",
                "bvh",
                "--sidecar",
                "--aov",
                "z,position,flow,flow_backward,instance_id",
                "--flow-dt",
                "0.1",
                "-q",
            ],
            dir.path(),
        );
        assert!(run.status.success(), "{}", stderr(&run));
    }
    let check = glint(&["check-gt", "a.exr", "--next", "b.exr"], dir.path());
    let said = format!(
        "{}{}",
        String::from_utf8_lossy(&check.stdout),
        stderr(&check)
    );
    assert!(check.status.success(), "{said}");
    // The flow check compared thousands of pixels, not a handful left after the exclusions.
    let compared: usize = said
        .lines()
        .find(|l| l.starts_with("flow:"))
        .and_then(|l| l.split("; ").nth(1))
        .and_then(|l| l.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or(0);
    assert!(compared > 5000, "{said}");
}
