#!/usr/bin/env python3
# measurement: renders the Khronos models and scores them against their Cycles goldens (docs/materials.md). Run: target/tools-venv/bin/python tools/fidelity.py [--spp 256] [MODEL ...]
"""Fidelity in one command: renders every Khronos model that has a Cycles golden and scores the renders.

    tools/python-venv.sh                    # once: target/tools-venv (tools/requirements.txt)
    target/tools-venv/bin/python tools/fidelity.py [--spp 256] [--glint target/release/glint] \\
        [--out DIR] [MODEL ...]

Each model is rendered at its golden's size with the goldens' settings (../shared/khronos/README.md):
    glint render MODEL --integrator path --env ../shared/env/studio.exr --env-strength 1 \\
        --max-depth 8 --spp SPP --seed 1 --threads 2 --width W --height H -o OUT/MODEL.exr
Prints one Markdown row per model against `cycles.exr` on the whole image (mean ratio and mean
8×8 block error), then runs ../shared/fidelity/score.py on the renders: the project's measure
(object pixels, mean within 5 %, 8×8 block relative RMSE <= 0.10), which is what the fidelity
table in docs/materials.md reports. Exits non-zero when a render fails or score.py does.
The renders go to --out (kept) or to a temporary folder (removed).
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
import OpenEXR
import Imath

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
KHRONOS = os.path.join(ROOT, "..", "shared", "khronos")
ENV = os.path.join(ROOT, "..", "shared", "env", "studio.exr")
SCORE = os.path.join(ROOT, "..", "shared", "fidelity", "score.py")


def read_rgb(path):
    f = OpenEXR.InputFile(path)
    dw = f.header()["dataWindow"]
    w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
    pt = Imath.PixelType(Imath.PixelType.FLOAT)
    return np.stack(
        [np.frombuffer(f.channel(c, pt), np.float32).reshape(h, w) for c in "RGB"], -1
    ).astype(np.float64)


def block_means(img, b=8):
    h, w = img.shape[0] // b * b, img.shape[1] // b * b
    return img[:h, :w].reshape(h // b, b, w // b, b, 3).mean(axis=(1, 3))


def model_file(name):
    for sub, ext in (("glTF-Binary", ".glb"), ("glTF", ".gltf")):
        d = os.path.join(KHRONOS, name, sub)
        if os.path.isdir(d):
            files = sorted(f for f in os.listdir(d) if f.endswith(ext))
            if files:
                return os.path.join(d, files[0])
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--glint", default=os.path.join(ROOT, "target", "release", "glint"))
    ap.add_argument("--out", default=None, help="keep the renders in this folder")
    ap.add_argument("--golden", default=None,
                    help="compare against this EXR instead of cycles.exr; {model} is replaced "
                         "by the model's name (e.g. a Cycles variant rendered for a check)")
    ap.add_argument("models", nargs="*")
    args = ap.parse_args()
    names = args.models or sorted(
        n for n in os.listdir(KHRONOS) if os.path.isfile(os.path.join(KHRONOS, n, "cycles.exr"))
    )
    print("| model | mean | block error |")
    print("|---|---|---|")
    failed = False
    with tempfile.TemporaryDirectory(prefix="glint-fidelity-") as tmp:
        if args.out:
            os.makedirs(args.out, exist_ok=True)
            tmp = args.out
        for name in names:
            model = model_file(name)
            golden_path = (args.golden.replace("{model}", name) if args.golden
                           else os.path.join(KHRONOS, name, "cycles.exr"))
            golden = read_rgb(golden_path)
            h, w = golden.shape[:2]
            out = os.path.join(tmp, name + ".exr")
            cmd = [args.glint, "render", model, "--integrator", "path", "--env", ENV,
                   # --max-depth 8 as the goldens' 8 bounces; glint's transmission bounces
                   # (default 64) are counted apart, where Cycles counts them in its 8 too
                   # (docs/materials.md): glass goes deeper here than in the goldens.
                   "--env-strength", "1", "--max-depth", "8",
                   "--spp", str(args.spp), "--seed", "1", "--threads", "2",
                   "--width", str(w), "--height", str(h), "-q", "-o", out]
            t = time.time()
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode != 0:
                print(f"| {name} | failed | {r.stderr.strip().splitlines()[-1:]} |", flush=True)
                failed = True
                continue
            img = read_rgb(out)
            if img.shape != golden.shape:
                print(f"| {name} | size {img.shape[1]}×{img.shape[0]} ≠ golden {w}×{h} | |", flush=True)
                continue
            cm = golden.mean()
            ratio = img.mean() / cm
            err = np.abs(block_means(img) - block_means(golden)).mean() / cm
            print(f"| {name} | {ratio:.3f} | {100 * err:.1f} % |", flush=True)
            print(f"{name}: {time.time() - t:.0f} s", file=sys.stderr, flush=True)
        print(flush=True)
        scored = subprocess.run([sys.executable, SCORE, tmp]).returncode
    sys.exit(1 if failed or scored != 0 else 0)


if __name__ == "__main__":
    main()
