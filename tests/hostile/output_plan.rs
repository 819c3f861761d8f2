//! Nothing lost, nothing overwritten (issue 36): the output plan refuses outputs that would
//! replace an input or each other, only regular files are read and written, the size budgets
//! hold before allocation, numbers bound for Embree are refused at load, and a job's outputs
//! are one unit (fault injection between them, then resume). Images are tiny: these tests
//! check bookkeeping, not pixels.

use crate::{engine, targets};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::support::{demo, files_in};

/// `glint ARGS` without the test-only variables a caller's environment may carry.
fn command(args: &[&str], cwd: &Path) -> Command {
    let mut command = crate::support::glint_command(args, cwd);
    command
        .env_remove("GLINT_TEST_FAIL_WRITE")
        .env_remove("GLINT_MAX_MEMORY");
    command
}

fn glint(args: &[&str], cwd: &Path) -> Output {
    command(args, cwd).output().expect("run glint")
}

/// Runs glint with the fault-injection variable set.
fn glint_failing(args: &[&str], cwd: &Path, fail: &str) -> Output {
    command(args, cwd)
        .env("GLINT_TEST_FAIL_WRITE", fail)
        .output()
        .expect("run glint")
}

use crate::support::stderr;

/// Asserts a clean refusal: exit status 1, no panic, the last stderr line naming every
/// `expected` text.
fn refused(out: &Output, expected: &[&str]) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    for e in expected {
        assert!(err.contains(e), "expected {e:?} in: {err}");
    }
}

/// A job file in `dir` with `[defaults]` rendering the demo scene tiny, and `body`.
fn job_file(dir: &Path, name: &str, body: &str) -> PathBuf {
    let text = format!(
        "[defaults]\nscene = \"{}\"\nwidth = 16\nheight = 12\nspp = 1\n{body}",
        demo().display()
    );
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn outputs_that_would_replace_an_input_or_each_other_are_refused_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("sub")).unwrap();
    // The job file is `a.json`: the sidecar of `a.png` would replace it.
    let jobs = job_file(d, "a.json", "[[job]]\noutput = \"a.png\"\nsidecar = true\n");
    let before = std::fs::read(&jobs).unwrap();
    let out = glint(&["batch", "a.json"], d);
    refused(
        &out,
        &["a.json", "the job file", "the sidecar of [[job]] 0"],
    );
    assert_eq!(
        std::fs::read(&jobs).unwrap(),
        before,
        "the job file is intact"
    );
    assert!(!d.join("a.png").exists(), "nothing rendered");

    // Spellings of one output: `./x.png`, `sub/../x.png`, a symbolic link to the folder.
    #[cfg(unix)]
    std::os::unix::fs::symlink(d.join("sub"), d.join("link")).unwrap();
    for (first, second) in [
        ("x.png", "./x.png"),
        ("x.png", "sub/../x.png"),
        ("sub/x.png", "link/x.png"),
    ] {
        if second.starts_with("link") && !cfg!(unix) {
            continue;
        }
        job_file(
            d,
            "j.toml",
            &format!("[[job]]\noutput = \"{first}\"\n[[job]]\noutput = \"{second}\"\n"),
        );
        let out = glint(&["batch", "j.toml"], d);
        refused(&out, &[second, "[[job]] 0", "[[job]] 1", "twice"]);
    }

    // `a.png` and `a.exr` with sidecars share `a.json`: the pair is refused.
    job_file(
        d,
        "pair.toml",
        "[[job]]\noutput = \"p.png\"\nsidecar = true\n[[job]]\noutput = \"p.exr\"\nsidecar = true\n",
    );
    let out = glint(&["batch", "pair.toml"], d);
    refused(
        &out,
        &[
            "p.json",
            "the sidecar of [[job]] 0",
            "the sidecar of [[job]] 1",
        ],
    );
    // Without sidecars they are two files.
    job_file(
        d,
        "pair.toml",
        "[[job]]\noutput = \"p.png\"\n[[job]]\noutput = \"p.exr\"\n",
    );
    let out = glint(&["batch", "pair.toml", "-q"], d);
    assert!(out.status.success(), "{}", stderr(&out));

    // --report and --coco against the job file, an image, a sidecar and each other.
    job_file(d, "c.toml", "[[job]]\noutput = \"c.exr\"\n");
    let jobs_before = std::fs::read(d.join("c.toml")).unwrap();
    for (args, expected) in [
        (
            vec!["--report", "r.json", "--coco", "r.json"],
            vec!["the report (--report)", "the COCO file (--coco)"],
        ),
        (
            vec!["--coco", "c.toml"],
            vec!["the job file", "the COCO file"],
        ),
        (
            vec!["--report", "c.toml"],
            vec!["the job file", "the report"],
        ),
        (
            vec!["--report", "c.exr"],
            vec!["the image of [[job]] 0", "the report"],
        ),
        (
            vec!["--coco", "c.json"],
            vec!["the sidecar of [[job]] 0", "the COCO file"],
        ),
    ] {
        let mut all = vec!["batch", "c.toml"];
        all.extend(args.iter().copied());
        let out = glint(&all, d);
        refused(&out, &expected);
    }
    assert_eq!(std::fs::read(d.join("c.toml")).unwrap(), jobs_before);

    // glint render: the output is the environment map, a lights file, the scene's image.
    std::fs::write(d.join("env.exr"), b"not read").unwrap();
    let out = glint(
        &[
            "render",
            &demo().to_string_lossy(),
            "--env",
            "env.exr",
            "-o",
            "env.exr",
        ],
        d,
    );
    refused(&out, &["env.exr", "the environment map", "the image"]);
    assert_eq!(std::fs::read(d.join("env.exr")).unwrap(), b"not read");
    std::fs::write(d.join("lights.png"), b"[]").unwrap();
    let out = glint(
        &[
            "render",
            &demo().to_string_lossy(),
            "--lights",
            "lights.png",
            "-o",
            "lights.png",
        ],
        d,
    );
    refused(&out, &["lights.png", "a lights file"]);
    let scene = d.join("s.gltf");
    std::fs::write(
        &scene,
        r#"{"asset":{"version":"2.0"},"images":[{"uri":"tex.png"}],"scenes":[{"nodes":[]}],"scene":0}"#,
    )
    .unwrap();
    std::fs::write(d.join("tex.png"), b"texture").unwrap();
    let out = glint(&["render", "s.gltf", "-o", "sub/../tex.png"], d);
    refused(&out, &["image 0 of the scene", "tex.png"]);
    assert_eq!(std::fs::read(d.join("tex.png")).unwrap(), b"texture");
    // A merge whose output is one of its parts.
    let out = glint(&["merge", "c.exr", "-o", "./c.exr"], d);
    refused(&out, &["c.exr", "a part", "the merged image"]);
}

/// Runs glint, killing it after `limit`: a hang is a failure, not a stuck suite.
fn glint_within(args: &[&str], cwd: &Path, limit: Duration) -> Output {
    let mut child = command(args, cwd)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("glint {args:?} hung for {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    child.wait_with_output().unwrap()
}

#[cfg(unix)]
#[test]
fn fifos_as_inputs_or_outputs_fail_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for name in ["scene.glb", "jobs.toml", "out.png", "gt.exr", "part.exr"] {
        let status = Command::new("mkfifo").arg(d.join(name)).status().unwrap();
        assert!(status.success());
    }
    let limit = Duration::from_secs(60);
    let out = glint_within(&["render", "scene.glb", "-o", "x.png"], d, limit);
    refused(&out, &["scene.glb", "FIFO"]);
    let out = glint_within(&["batch", "jobs.toml"], d, limit);
    refused(&out, &["jobs.toml", "FIFO"]);
    let demo = demo();
    let out = glint_within(
        &[
            "render",
            &demo.to_string_lossy(),
            "-o",
            "out.png",
            "--width",
            "8",
        ],
        d,
        limit,
    );
    refused(&out, &["out.png", "FIFO"]);
    let out = glint_within(&["check-gt", "gt.exr"], d, limit);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let out = glint_within(&["merge", "part.exr", "-o", "m.exr"], d, limit);
    refused(&out, &["part.exr", "FIFO"]);
}

/// Rewrites the `dataWindow` of the EXR at `path` to declare `side` × `side` pixels (the
/// file stays a few hundred bytes of pixels).
fn declare_huge(path: &Path, side: i32) {
    let mut bytes = std::fs::read(path).unwrap();
    let key = b"dataWindow\0box2i\0";
    let at = bytes
        .windows(key.len())
        .position(|w| w == key)
        .expect("an EXR names its data window")
        + key.len()
        + 4;
    for (k, v) in [0i32, 0, side - 1, side - 1].iter().enumerate() {
        bytes[at + 4 * k..at + 4 * k + 4].copy_from_slice(&v.to_le_bytes());
    }
    std::fs::write(path, bytes).unwrap();
}

#[test]
fn exr_headers_declaring_a_billion_pixels_are_refused_before_decoding() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let demo = demo().to_string_lossy().into_owned();
    // check-gt.
    let out = glint(
        &[
            "render",
            &demo,
            "--width",
            "8",
            "--height",
            "6",
            "--spp",
            "1",
            "--aov",
            "z",
            "--sidecar",
            "-o",
            "gt.exr",
            "-q",
        ],
        d,
    );
    assert!(out.status.success(), "{}", stderr(&out));
    declare_huge(&d.join("gt.exr"), 40_000);
    let out = glint(&["check-gt", "gt.exr"], d);
    refused(&out, &["gt.exr", "declares", "40000"]);
    // merge.
    let out = glint(
        &[
            "render",
            &demo,
            "--width",
            "8",
            "--height",
            "6",
            "--spp",
            "2",
            "--sample-range",
            "0..2",
            "-o",
            "part.exr",
            "-q",
        ],
        d,
    );
    assert!(out.status.success(), "{}", stderr(&out));
    declare_huge(&d.join("part.exr"), 40_000);
    let out = glint(&["merge", "part.exr", "-o", "m.exr"], d);
    refused(&out, &["part.exr", "declares"]);
    // The batch's resume check: the huge file is not this job's output; it is rendered again.
    job_file(d, "j.toml", "[[job]]\noutput = \"b.exr\"\n");
    assert!(glint(&["batch", "j.toml", "-q"], d).status.success());
    declare_huge(&d.join("b.exr"), 40_000);
    let out = glint(&["batch", "j.toml", "-q", "--report", "r.json"], d);
    assert!(out.status.success(), "{}", stderr(&out));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("r.json")).unwrap()).unwrap();
    assert_eq!(report["rendered"], 1, "{report}");
    // The render's own buffers: a 16384² render with AOVs against a 1 GiB budget.
    let out = glint(
        &[
            "render",
            &demo,
            "--width",
            "16384",
            "--height",
            "16384",
            "--aov",
            "albedo,normal",
            "--max-memory",
            "1G",
            "-o",
            "big.exr",
        ],
        d,
    );
    refused(&out, &["16384×16384", "needs about", "GiB", "--max-memory"]);
    let out = glint(&["render", &demo, "--max-memory", "NaN", "-o", "x.png"], d);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
}

#[test]
fn numbers_bound_for_embree_and_option_values_are_checked_where_parsed() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A job-file camera far beyond the ray queries' range, and an orbit of huge radius.
    job_file(
        d,
        "far.toml",
        "[[job]]\noutput = \"f.png\"\ncamera = { position = [1e15, 0, 0], look_at = [0, 0, 0] }\n",
    );
    let out = glint(&["batch", "far.toml"], d);
    refused(&out, &["camera position", "beyond"]);
    job_file(
        d,
        "orbit.toml",
        "[[sweep]]\noutput = \"o-{frame}.png\"\norbit = { frames = 2, center = [0, 0, 0], radius = 1e15 }\n",
    );
    let out = glint(&["batch", "orbit.toml"], d);
    refused(&out, &["beyond"]);
    let demo = demo().to_string_lossy().into_owned();
    let out = glint(
        &[
            "render",
            &demo,
            "--light",
            "point:position=1e15,0,0:intensity=10",
            "-o",
            "l.png",
            "--width",
            "8",
        ],
        d,
    );
    refused(&out, &["added light", "beyond"]);
    job_file(
        d,
        "light.toml",
        "[[job]]\noutput = \"l.png\"\nlight = [\"point:position=0,0,1e15:intensity=10\"]\n",
    );
    let out = glint(&["batch", "light.toml"], d);
    refused(&out, &["added light", "beyond"]);
    // --threads: bounded, refused before any work.
    let start = Instant::now();
    let out = glint(
        &["render", &demo, "--threads", "100000000", "-o", "t.png"],
        d,
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("1024"), "{}", stderr(&out));
    assert!(start.elapsed() < Duration::from_secs(20));
    // check-gt's tolerances.
    for bad in ["NaN", "inf", "-1"] {
        let out = glint(&["check-gt", "x.exr", "--tolerance", bad], d);
        assert_eq!(
            out.status.code(),
            Some(2),
            "--tolerance {bad}: {}",
            stderr(&out)
        );
        let out = glint(&["check-gt", "x.exr", "--flow-tolerance", bad], d);
        assert_eq!(out.status.code(), Some(2), "--flow-tolerance {bad}");
    }
}

#[test]
fn check_gt_refuses_frames_of_different_sizes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let demo = demo().to_string_lossy().into_owned();
    for (name, w, aov) in [
        ("a.exr", "8", "z,position,flow"),
        ("b.exr", "10", "z,position,flow_backward"),
    ] {
        let out = glint(
            &[
                "render",
                &demo,
                "--width",
                w,
                "--height",
                "6",
                "--spp",
                "1",
                "--aov",
                aov,
                "--time",
                "0",
                "--sidecar",
                "-o",
                name,
                "-q",
            ],
            d,
        );
        assert!(out.status.success(), "{}", stderr(&out));
    }
    let out = glint(&["check-gt", "a.exr", "--next", "b.exr"], d);
    refused(&out, &["b.exr", "10×6", "8×6", "one size"]);
}

#[test]
fn a_jobs_outputs_are_one_unit_under_a_full_disk_and_resume_writes_them_all() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    job_file(d, "j.toml", "[[job]]\noutput = \"a.exr\"\nsidecar = true\n");
    // The image's write fails after the sidecar's: neither is left.
    let out = glint_failing(&["batch", "j.toml", "-q"], d, "a.exr");
    refused(&out, &["a.exr", "no space left"]);
    let err = stderr(&out);
    let lines: Vec<&str> = err
        .lines()
        .filter(|l| l.contains("no space left"))
        .collect();
    assert_eq!(lines.len(), 1, "the error is one line: {err}");
    assert_eq!(files_in(d), ["j.toml"], "no output, no temporary");
    // The image's rename fails after the sidecar's: the sidecar is taken back.
    let out = glint_failing(&["batch", "j.toml", "-q"], d, "rename:a.exr");
    refused(&out, &["a.exr"]);
    assert_eq!(files_in(d), ["j.toml"]);
    // The sidecar's write fails: the image is not written either.
    let out = glint_failing(&["batch", "j.toml", "-q"], d, "a.json");
    refused(&out, &["a.json"]);
    assert_eq!(files_in(d), ["j.toml"]);
    // Resume writes both.
    let out = glint(&["batch", "j.toml", "-q"], d);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(files_in(d), ["a.exr", "a.json", "j.toml"]);
    // An image without its sidecar (an older glint's failure) is not complete: rendered again.
    std::fs::remove_file(d.join("a.json")).unwrap();
    let out = glint(&["batch", "j.toml", "--report", "r.json", "-q"], d);
    assert!(out.status.success(), "{}", stderr(&out));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("r.json")).unwrap()).unwrap();
    assert_eq!(report["rendered"], 1, "{report}");
    assert!(d.join("a.json").is_file());
}

#[cfg(unix)]
#[test]
fn a_batch_killed_at_each_commit_step_resumes_to_complete_jobs() {
    for step in ["kill:a.json", "kill:a.exr"] {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        job_file(d, "j.toml", "[[job]]\noutput = \"a.exr\"\nsidecar = true\n");
        let out = glint_failing(&["batch", "j.toml", "-q"], d, step);
        assert!(out.status.code().is_none(), "{step}: killed by a signal");
        assert!(
            !d.join("a.exr").exists(),
            "{step}: the image is renamed last"
        );
        let out = glint(&["batch", "j.toml", "-q", "--report", "r.json"], d);
        assert!(out.status.success(), "{step}: {}", stderr(&out));
        let report: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.join("r.json")).unwrap()).unwrap();
        assert_eq!(report["rendered"], 1, "{step}: {report}");
        assert_eq!(
            files_in(d),
            ["a.exr", "a.json", "j.toml", "r.json"],
            "{step}: every output, no temporary"
        );
    }
}

#[test]
fn coco_after_a_run_without_annotations_renders_them_and_two_coco_batches_both_succeed() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let body: String = (0..4)
        .map(|i| format!("[[job]]\noutput = \"c{i}.exr\"\nsidecar = true\n"))
        .collect();
    job_file(d, "j.toml", &body);
    assert!(glint(&["batch", "j.toml", "-q"], d).status.success());
    let out = glint(&["batch", "j.toml", "--coco", "coco.json"], d);
    assert!(out.status.success(), "{}", stderr(&out));
    let coco: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("coco.json")).unwrap()).unwrap();
    assert_eq!(coco["images"].as_array().unwrap().len(), 4);
    assert!(
        !coco["annotations"].as_array().unwrap().is_empty(),
        "the demo scene's objects are annotated: {}",
        stderr(&out)
    );
    // Two --coco batches on one fresh job file: both succeed with every image.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let body: String = (0..6)
        .map(|i| format!("[[job]]\noutput = \"c{i}.exr\"\nspp = 4\n"))
        .collect();
    job_file(d, "j.toml", &body);
    let children: Vec<_> = ["one.json", "two.json"]
        .iter()
        .map(|coco| {
            command(
                &["batch", "j.toml", "-q", "--threads", "1", "--coco", coco],
                d,
            )
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
        })
        .collect();
    for child in children {
        let out = child.wait_with_output().unwrap();
        assert!(out.status.success(), "{}", stderr(&out));
    }
    for coco in ["one.json", "two.json"] {
        let coco: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.join(coco)).unwrap()).unwrap();
        assert_eq!(coco["images"].as_array().unwrap().len(), 6);
    }
}

#[test]
fn the_sidecar_names_the_default_scene_and_negative_xmag_gives_a_positive_k() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let demo = demo().to_string_lossy().into_owned();
    let out = glint(
        &[
            "render",
            &demo,
            "--width",
            "8",
            "--spp",
            "1",
            "--sidecar",
            "-o",
            "s.png",
            "-q",
        ],
        d,
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let sidecar: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("s.json")).unwrap()).unwrap();
    assert!(
        sidecar["scene_index"].is_u64(),
        "{}",
        sidecar["scene_index"]
    );
    // A glTF orthographic camera with a negative xmag: read as its magnitude, so K's fx is
    // positive and equals the positive camera's, and the two images are the same.
    let mut bin: Vec<u8> = [[-1.0f32, -1.0, 0.0], [1.0, -1.0, 0.0], [0.2, 1.0, 0.0]]
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    bin.extend([0u16, 1, 2, 0].iter().flat_map(|i| i.to_le_bytes()));
    use base64::Engine;
    let data = base64::engine::general_purpose::STANDARD.encode(&bin);
    let mut fx = Vec::new();
    let mut images = Vec::new();
    for xmag in [2.0, -2.0] {
        let gltf = serde_json::json!({
            "asset": {"version": "2.0"},
            "scene": 0,
            "scenes": [{"nodes": [0, 1]}],
            "nodes": [
                {"mesh": 0},
                {"camera": 0, "translation": [0.0, 0.0, 3.0]}
            ],
            "cameras": [{"type": "orthographic", "orthographic":
                {"xmag": xmag, "ymag": 1.5, "znear": 0.1, "zfar": 10.0}}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
            "accessors": [
                {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [-1.0, -1.0, 0.0], "max": [1.0, 1.0, 0.0]},
                {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}
            ],
            "bufferViews": [
                {"buffer": 0, "byteOffset": 0, "byteLength": 36},
                {"buffer": 0, "byteOffset": 36, "byteLength": 6}
            ],
            "buffers": [{"byteLength": 44,
                "uri": format!("data:application/octet-stream;base64,{data}")}]
        });
        let name = format!("ortho{}.gltf", if xmag > 0.0 { "+" } else { "-" });
        std::fs::write(d.join(&name), gltf.to_string()).unwrap();
        let out_name = name.replace(".gltf", ".png");
        let out = glint(
            &[
                "render",
                &name,
                "--width",
                "16",
                "--height",
                "12",
                "--spp",
                "1",
                "--sidecar",
                "--backend",
                "bvh",
                "-o",
                &out_name,
                "-q",
            ],
            d,
        );
        assert!(out.status.success(), "{}", stderr(&out));
        let sidecar: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(d.join(out_name.replace(".png", ".json"))).unwrap(),
        )
        .unwrap();
        fx.push(sidecar["camera"]["K"][0][0].as_f64().unwrap());
        images.push(std::fs::read(d.join(&out_name)).unwrap());
    }
    assert!(fx[0] > 0.0 && fx[1] == fx[0], "fx {fx:?}");
    assert!(
        images[0] == images[1],
        "a negative xmag does not mirror the image"
    );
}

#[test]
fn merge_refuses_parts_with_samples_beyond_their_spp_or_impossible_weights() {
    use glam::Vec3;
    use glint::output::partial::{read_partial_exr, write_partial_exr};
    use glint::render::partial::PartialImage;
    use glint::render::{Aovs, Image};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("part.exr");
    let part = |spp: u32, samples: std::ops::Range<u32>, weight: f32| PartialImage {
        spp,
        seed: 0,
        samples,
        radiance_sum: Image::filled(2, 2, Vec3::ONE),
        aov_sums: Aovs::default(),
        weight: Image::filled(2, 2, weight),
    };
    // A sound part reads back.
    write_partial_exr(&path, &part(8, 0..8, 8.0)).unwrap();
    assert!(read_partial_exr(&path).is_ok());
    for (bad, expected) in [
        (part(8, 0..16, 16.0), "exceed its 8 samples"),
        (part(8, 0..8, 1e-40), "'weight'"),
        (part(8, 0..8, f32::INFINITY), "'weight'"),
        (part(8, 0..8, 1e9), "'weight'"),
    ] {
        write_partial_exr(&path, &bad).unwrap();
        let err = read_partial_exr(&path).unwrap_err().to_string();
        assert!(err.contains(expected) && !err.contains('\n'), "{err}");
    }
}

/// The `outputs` fuzz target's oracle over every job file of two jobs (each output spelling ×
/// sidecar flag), and 3000 seeded three- to eight-job files: the plan accepts a file exactly
/// when no two planned files are one, and a refusal is one line.
#[test]
fn the_outputs_fuzz_target_finds_the_plan_sound_on_every_small_job_file() {
    use rand::{Rng, SeedableRng};
    let mut inputs: Vec<Vec<u8>> = Vec::new();
    for a in 0..20u8 {
        for b in 0..20u8 {
            inputs.push(vec![a / 2, a % 2, b / 2, b % 2]);
        }
    }
    let mut rng = rand_pcg::Pcg64::seed_from_u64(20261203);
    for _ in 0..3000 {
        let n = rng.random_range(3..=8) * 2;
        inputs.push((0..n).map(|_| rng.random::<u8>()).collect());
    }
    let (mut accepted, mut refused) = (0, 0);
    for input in &inputs {
        match targets::outputs(input) {
            engine::Outcome::Broken(why) => panic!("{input:?}: {why}"),
            engine::Outcome::Accepted(_) => accepted += 1,
            engine::Outcome::Refused(_) => refused += 1,
        }
    }
    assert!(
        accepted > 100 && refused > 100,
        "{accepted} accepted, {refused} refused"
    );
}
