"""The Python package against the command line and against scenes of known layout.

Images are small (at most a few thousand pixels) so that the suite runs in seconds.
"""

import importlib.util
import json
import math
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import OpenEXR
import pytest

import glint

ALL_AOVS = ["albedo", "normal", "depth", "instance_id", "material_id", "coverage",
            "z", "position", "uv"]
# The flows need an animation time (a scene loaded with time=); the demo has none.
FLOW_AOVS = ["flow", "flow_backward"]


def read_exr(path):
    """The EXR's channels by name, each an H×W array (read by the OpenEXR package, not glint)."""
    with OpenEXR.File(str(path), separate_channels=True) as f:
        return {name: np.array(ch.pixels) for name, ch in f.channels().items()}


def bits(a):
    """The array's bit pattern, so that equality is bit identity (NaNs and -0 included)."""
    a = np.ascontiguousarray(a)
    return a.view(np.uint32) if a.dtype == np.float32 else a


# ---------------------------------------------------------------- CLI equality


@pytest.mark.parametrize("integrator", ["path", "direct"])
def test_render_equals_the_cli_exr_bit_for_bit(glint_bin, tmp_path, integrator):
    exr = tmp_path / "cli.exr"
    subprocess.run(
        [str(glint_bin), "render", "-o", str(exr), "--width", "40", "--height", "24",
         "--spp", "4", "--seed", "3", "--integrator", integrator,
         "--aov", ",".join(ALL_AOVS), "--quiet"],
        check=True,
    )
    cli = read_exr(exr)
    img = glint.load().render(width=40, height=24, spp=4, seed=3, integrator=integrator,
                              aovs=ALL_AOVS)
    rgb = np.stack([cli["R"], cli["G"], cli["B"]], axis=-1)
    assert rgb.dtype == np.float32
    assert np.array_equal(bits(img["radiance"]), bits(rgb))
    assert np.array_equal(bits(img["alpha"]), bits(cli["A"]))
    assert np.array_equal(bits(img["albedo"]),
                          bits(np.stack([cli[f"albedo.{c}"] for c in "RGB"], axis=-1)))
    assert np.array_equal(bits(img["normal"]),
                          bits(np.stack([cli[f"normal.{c}"] for c in "XYZ"], axis=-1)))
    assert np.array_equal(bits(img["depth"]), bits(cli["depth.Z"]))
    for name in ["instance_id", "material_id"]:
        assert cli[name].dtype == np.uint32
        assert np.array_equal(img[name], cli[name])
    k = glint.COVERAGE_LAYERS
    ids = np.stack([cli[f"coverage.id{i}"] for i in range(k)], axis=-1)
    fractions = np.stack([cli[f"coverage.fraction{i}"] for i in range(k)], axis=-1)
    assert np.array_equal(img["coverage_ids"], ids)
    assert np.array_equal(bits(img["coverage"]), bits(fractions))


def test_denoised_render_equals_the_cli_exr_bit_for_bit(glint_bin, tmp_path):
    scene = glint.load()
    try:
        scene.render(width=8, height=6, spp=1, denoise=True)
    except glint.GlintError as e:
        if "built without Open Image Denoise" in str(e):
            pytest.skip("glint was built without the `denoise` feature (Open Image Denoise)")
        raise
    exr = tmp_path / "cli.exr"
    subprocess.run(
        [str(glint_bin), "render", "-o", str(exr), "--width", "40", "--height", "24",
         "--spp", "4", "--seed", "3", "--threads", "2", "--denoise", "--quiet"],
        check=True,
    )
    cli = read_exr(exr)
    img = scene.render(width=40, height=24, spp=4, seed=3, threads=2, denoise=True)
    rgb = np.stack([cli[c] for c in "RGB"], axis=-1)
    noisy = np.stack([cli[f"noisy.{c}"] for c in "RGB"], axis=-1)
    assert np.array_equal(bits(img["radiance"]), bits(rgb))
    assert np.array_equal(bits(img["noisy"]), bits(noisy))
    assert not np.array_equal(img["radiance"], img["noisy"])
    assert "albedo" not in img and "normal" not in img


def test_defaults_are_the_cli_defaults(glint_bin, tmp_path):
    # Only the size is given: every other option is each side's default (integrator, spp,
    # seed, depth, sampler, filters), so equal pixels mean equal defaults. The Rust side:
    # tests/render/job_defaults.rs (glint render = Job::default()) and the glint-python crate's
    # no_keyword_arguments_give_the_default_job (Python = Job::default()).
    exr = tmp_path / "cli.exr"
    subprocess.run(
        [str(glint_bin), "render", "-o", str(exr), "--width", "32", "--height", "18",
         "--quiet"],
        check=True,
    )
    cli = read_exr(exr)
    img = glint.load().render(width=32, height=18)
    rgb = np.stack([cli["R"], cli["G"], cli["B"]], axis=-1)
    assert np.array_equal(bits(img["radiance"]), bits(rgb))
    assert np.array_equal(bits(img["alpha"]), bits(cli["A"]))


def test_output_argument_writes_the_same_file_as_the_cli(glint_bin, quads_path, tmp_path):
    cli, py = tmp_path / "cli.exr", tmp_path / "py.exr"
    subprocess.run([str(glint_bin), "render", str(quads_path), "-o", str(cli), "--width", "7",
                    "--height", "2", "--spp", "8", "--aov", "coverage,instance_id", "--quiet"],
                   check=True)
    glint.load(quads_path).render(width=7, height=2, spp=8, aovs=["coverage", "instance_id"],
                                  output=py)
    assert cli.read_bytes() == py.read_bytes()



def test_annotations_equal_the_cli_sidecar(glint_bin, quads_path, tmp_path):
    """annotations=True gives the instances the command line writes into its sidecar, and
    categories= names them as --category does."""
    out = tmp_path / "cli.png"
    subprocess.run([str(glint_bin), "render", str(quads_path), "-o", str(out), "--width", "28",
                    "--height", "8", "--spp", "8", "--annotations", "--category", "A=left",
                    "--quiet"], check=True)
    cli = json.loads(out.with_suffix(".json").read_text())["instances"]
    result = glint.load(quads_path).render(width=28, height=8, spp=8, annotations=True,
                                           categories={"A": "left"})
    assert result["instances"] == cli
    assert result["camera"]["instances"] == cli
    assert "left" in {inst["category"] for inst in cli}
    assert all(inst["amodal"]["area"] >= inst["visible"]["area"] for inst in cli)
    assert "instances" not in glint.load(quads_path).render(width=28, height=8, spp=8)


# ---------------------------------------------------------------- shapes and dtypes


def test_aov_shapes_and_dtypes():
    img = glint.load().render(width=33, height=17, spp=2, aovs=ALL_AOVS)
    k = glint.COVERAGE_LAYERS
    expected = {
        "radiance": ((17, 33, 3), np.float32),
        "alpha": ((17, 33), np.float32),
        "albedo": ((17, 33, 3), np.float32),
        "normal": ((17, 33, 3), np.float32),
        "depth": ((17, 33), np.float32),
        "instance_id": ((17, 33), np.uint32),
        "material_id": ((17, 33), np.uint32),
        "coverage_ids": ((17, 33, k), np.uint32),
        "coverage": ((17, 33, k), np.float32),
        "z": ((17, 33), np.float32),
        "position": ((17, 33, 3), np.float32),
        "uv": ((17, 33, 2), np.float32),
    }
    assert set(img) == set(expected) | {"camera"}
    for name, (shape, dtype) in expected.items():
        assert img[name].shape == shape, name
        assert img[name].dtype == dtype, name
    assert set(glint.AOVS) == set(ALL_AOVS + FLOW_AOVS)
    # The camera sidecar: OpenCV K with pixel centres at integers.
    camera = img["camera"]
    assert (camera["width"], camera["height"]) == (33, 17)
    assert camera["camera"]["K"][0][2] == pytest.approx(16.0)
    assert camera["camera"]["K"][1][2] == pytest.approx(8.0)
    # Without AOVs: radiance, its coverage and the camera record alone.
    assert set(glint.load().render(width=8, height=4, spp=1)) == {"radiance", "alpha", "camera"}


def test_aovs_do_not_change_the_radiance():
    scene = glint.load()
    plain = scene.render(width=32, height=18, spp=4)["radiance"]
    with_ids = scene.render(width=32, height=18, spp=4, aovs=ALL_AOVS)["radiance"]
    assert np.array_equal(bits(plain), bits(with_ids))


# ---------------------------------------------------------------- IDs of a known layout


def test_ids_of_two_quads(quads_path):
    scene = glint.load(quads_path)
    assert [m["node"] for m in scene.meshes] == [0, 1]
    assert scene.materials == ["red", "green"]
    spp = 256
    img = scene.render(width=7, height=2, spp=spp, aovs=["instance_id", "material_id",
                                                         "coverage"])
    inst, mat = img["instance_id"], img["material_id"]
    # Left of the edge column: node A (0), material 0; right: node B (1), material 1.
    assert (inst[:, :3] == 0).all() and (inst[:, 4:] == 1).all()
    assert (mat[:, :3] == 0).all() and (mat[:, 4:] == 1).all()
    # The edge column's centre ray runs along x = 0 and hits one of the two.
    assert set(inst[:, 3].tolist()) <= {0, 1}
    ids, fractions = img["coverage_ids"], img["coverage"]
    # Whole pixels: one object, all samples.
    for col, node in [(0, 0), (2, 0), (4, 1), (6, 1)]:
        assert (ids[:, col, 0] == node).all()
        assert (fractions[:, col, 0] == 1.0).all()
        assert (ids[:, col, 1:] == glint.NO_ID).all()
        assert (fractions[:, col, 1:] == 0.0).all()
    # The straddling pixel: A and B half each. Tolerance: 4 standard deviations of the
    # fraction of `spp` independent uniform samples, 4·sqrt(0.25/spp) = 0.125 (Sobol points
    # stratify x, so the real error is far smaller); the two still add up to 1 exactly.
    for row in range(2):
        layers = dict(zip(ids[row, 3, :2].tolist(), fractions[row, 3, :2].tolist()))
        assert set(layers) == {0, 1}
        tolerance = 4 * math.sqrt(0.25 / spp)
        assert abs(layers[0] - 0.5) <= tolerance and abs(layers[1] - 0.5) <= tolerance
        assert layers[0] + layers[1] == 1.0
        assert ids[row, 3, 2] == glint.NO_ID


def test_coverage_sees_the_background_and_counts_exactly(quads_path):
    # A camera that sees past the quads' right edge (x = 2): pixels there are part background.
    scene = glint.load(quads_path)
    img = scene.render(width=16, height=8, spp=16, aovs=["coverage", "instance_id"],
                       camera={"position": (2.0, 0.0, 4.0), "target": (2.0, 0.0, 0.0)})
    fractions = img["coverage"]
    total = fractions.sum(axis=-1)
    assert (total <= 1.0 + 1e-6).all()
    assert (total[:, -1] == 0.0).all()  # the right edge sees only background
    assert (img["instance_id"][:, -1] == glint.NO_ID).all()
    # Fractions are whole numbers of samples out of 16.
    assert np.array_equal(fractions * 16, np.round(fractions * 16))


def test_ids_do_not_depend_on_the_thread_count(quads_path):
    scene = glint.load(quads_path)
    args = dict(width=21, height=6, spp=8, aovs=["instance_id", "material_id", "coverage"])
    one, two = scene.render(threads=1, **args), scene.render(threads=2, **args)
    for name in one:
        assert np.array_equal(bits(one[name]), bits(two[name])), name


# ---------------------------------------------------------------- scene information


def test_scene_cameras_and_bounds(quads_path):
    scene = glint.load(quads_path)
    (camera,) = scene.cameras
    assert camera.projection == "orthographic"
    assert camera.position == pytest.approx([0.0, 0.0, 5.0])
    assert (camera.xmag, camera.ymag) == (1.75, 0.5)
    lo, hi = scene.bounds
    assert lo == pytest.approx([-2.0, -1.0, 0.0]) and hi == pytest.approx([2.0, 1.0, 0.0])
    assert scene.triangles == 4


# ---------------------------------------------------------------- bad input


def test_missing_file_raises_with_glints_message(tmp_path):
    missing = tmp_path / "nope.glb"
    with pytest.raises(glint.GlintError, match="nope.glb"):
        glint.load(missing)


def test_the_loader_budgets_are_keyword_arguments(quads_path):
    """max_texture_pixels and max_geometry_bytes bound what a load may allocate; a scene over
    the geometry budget is refused before its vertices are built, naming the budget."""
    glint.load(quads_path, max_geometry_bytes=1 << 20, max_texture_pixels=1 << 10)
    with pytest.raises(glint.GlintError, match="geometry") as err:
        glint.load(quads_path, max_geometry_bytes=100)
    assert "two_quads.gltf" in str(err.value) and "\n" not in str(err.value)


def test_bad_camera_index_raises_with_glints_message(quads_path):
    with pytest.raises(glint.GlintError, match=r"camera.*5|5.*camera") as err:
        glint.load(quads_path).render(width=4, height=2, spp=1, camera=5)
    assert "two_quads.gltf" in str(err.value)


def test_a_panic_inside_a_render_raises_glint_error_in_one_line(quads_path, monkeypatch, capfd):
    """A bug in glint (a panic forced by the test-only GLINT_TEST_PANIC, which the dev-profile
    build of tools/check-python.sh reads) raises GlintError naming the scene, not pyo3's
    PanicException, and prints none of Rust's panic text."""
    scene = glint.load(quads_path)
    monkeypatch.setenv("GLINT_TEST_PANIC", "render")
    with pytest.raises(glint.GlintError, match="internal error while rendering") as err:
        scene.render(width=4, height=2, spp=1)
    message = str(err.value)
    assert "two_quads.gltf" in message and "please report" in message
    assert "\n" not in message
    assert "panicked at" not in capfd.readouterr().err
    monkeypatch.delenv("GLINT_TEST_PANIC")
    assert scene.render(width=4, height=2, spp=1)["radiance"].shape[:2] == (2, 4)


def test_bad_arguments_raise_python_errors():
    scene = glint.load()
    with pytest.raises(ValueError, match="unknown AOV"):
        scene.render(width=4, height=2, aovs=["colour"])
    with pytest.raises(TypeError, match="unexpected keyword argument 'sp'"):
        scene.render(sp=4)
    with pytest.raises(ValueError, match="integrator"):
        scene.render(integrator="bidirectional")
    with pytest.raises(glint.GlintError, match="spp"):
        scene.render(width=4, height=2, spp=0)
    with pytest.raises(glint.GlintError, match="light"):
        scene.render(width=4, height=2, lights=["not a light"])
    with pytest.raises(ValueError, match="backend"):
        glint.load(backend="optix")


# ---------------------------------------------------------------- GIL and Ctrl-C


def test_the_gil_is_released_while_rendering():
    scene = glint.load()
    stamps = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            stamps.append(time.perf_counter())
            time.sleep(0.001)

    ticker = threading.Thread(target=tick)
    ticker.start()
    try:
        start = time.perf_counter()
        scene.render(width=160, height=90, spp=16, threads=1)
        end = time.perf_counter()
    finally:
        stop.set()
        ticker.join()
    # Ticks strictly inside the render (its first and last tenth left out): with the GIL held
    # for the whole call there would be none.
    margin = (end - start) / 10
    inside = [t for t in stamps if start + margin < t < end - margin]
    assert end - start > 0.05, "render too short to tell"
    assert len(inside) >= 5, (len(inside), end - start)


@pytest.mark.skipif(os.name != "posix", reason="sends SIGINT to itself")
def test_ctrl_c_stops_a_render():
    scene = glint.load()
    # A process started in the background by a non-interactive shell inherits SIGINT ignored,
    # and Python then installs no handler: Ctrl-C's own handler is put in place for the test.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    start = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            # Minutes of work if it ran to the end.
            scene.render(width=640, height=360, spp=4096)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    assert time.perf_counter() - start < 30


# ---------------------------------------------------------------- batches


def test_render_batch_equals_single_renders(quads_path):
    demo = glint.load()
    jobs = [
        {"scene": demo, "width": 24, "height": 12, "spp": 2, "seed": 1},
        {"scene": str(quads_path), "width": 7, "height": 2, "spp": 8, "aovs": ["coverage"]},
        {"scene": demo, "width": 16, "height": 9, "spp": 3, "integrator": "direct"},
    ]
    batch = glint.render_batch(jobs, threads=2)
    assert len(batch) == 3
    for job, got in zip(jobs, batch):
        args = {k: v for k, v in job.items() if k != "scene"}
        scene = job["scene"] if isinstance(job["scene"], glint.Scene) else glint.load(job["scene"])
        want = scene.render(**args)
        assert set(got) == set(want)
        for name in want:
            assert np.array_equal(bits(got[name]), bits(want[name])), name


def test_render_batch_names_the_failing_job():
    with pytest.raises(glint.GlintError, match="job 1"):
        glint.render_batch([{"scene": glint.load(), "width": 4, "height": 2, "spp": 1},
                            {"scene": glint.load(), "width": 4, "height": 2, "camera": 9}])


# ---------------------------------------------------------------- the cluster example


def test_dask_example_runs_on_a_local_cluster(tmp_path):
    pytest.importorskip("distributed")
    example = os.path.join(os.path.dirname(__file__), "..", "examples", "dask_batch.py")
    out = tmp_path / "frames"
    run = subprocess.run(
        [sys.executable, example, "--jobs", "4", "--chunk", "2", "--workers", "2",
         "--width", "32", "--height", "18", "--spp", "2", "--out", str(out)],
        capture_output=True, text=True, timeout=300,
    )
    assert run.returncode == 0, run.stderr[-2000:]
    assert "4 jobs in 2 tasks on 2 workers" in run.stdout
    frames = sorted(out.glob("frame_*.exr"))
    assert len(frames) == 4
    # The first frame equals the same job rendered in this process.
    spec = importlib.util.spec_from_file_location("dask_batch", example)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    job = module.turntable(None, 4, out, 32, 18, 2)[0]
    assert job["output"] == str(frames[0])
    del job["output"]
    local = glint.load().render(**job)
    first = read_exr(frames[0])
    rgb = np.stack([first["R"], first["G"], first["B"]], axis=-1)
    assert np.array_equal(bits(local["radiance"]), bits(rgb))
    assert np.array_equal(local["instance_id"], first["instance_id"])
