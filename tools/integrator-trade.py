#!/usr/bin/env python3
# measurement: error against time of the path and direct integrators (docs/render.md). Run: target/tools-venv/bin/python tools/integrator-trade.py --out DIR [--model MODEL]
"""Error against time of glint's two integrators, `--integrator path` and `--integrator direct`.

Both render the same model under the same light (default: the studio HDRI) at several spp, two
seeds each. The error of each render is its relMSE (mean over pixels and channels of
(x − r)² / (r² + 0.01), as `glint converge`) against the PATH TRACER's converged image r (the
mean of two path renders at --ref-spp with seeds 100 and 101): the full solution of the
rendering equation, so the direct integrator's missing indirect light shows as an error floor.
"noise" is the two-seed estimate of one render's own variance (mean of (a − b)²/2 over the same
denominator), the part that more samples remove. Seconds are glint's own "rendered in" time
(sampling only; scene load, BVH and MIP chains excluded) and the process CPU time (user + sys,
/usr/bin/time), medians of the seeds.

    python3 tools/integrator-trade.py --out /tmp/trade --model ../shared/scenes/DamagedHelmet/glTF/DamagedHelmet.gltf

Needs numpy and OpenEXR (e.g. the bpy venv's Python). Prints a Markdown table.
"""

import argparse
import os
import re
import subprocess
import sys

import numpy as np
import OpenEXR

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.normpath(os.path.join(ROOT, "..", "shared"))
EPS = 1e-2


def read_rgb(path):
    with OpenEXR.File(path) as f:
        ch = f.channels()
        # OpenEXR's Python API groups R, G, B (and A: glint writes coverage) into one entry.
        for name in ("RGB", "RGBA"):
            if name in ch:
                return np.asarray(ch[name].pixels, dtype=np.float64)[..., :3]
        return np.stack([np.asarray(ch[c].pixels, dtype=np.float64) for c in "RGB"], axis=-1)


def render(args, integrator, spp, seed, image):
    """Renders unless `image` exists; returns (render s, CPU s) or None when skipped."""
    times = image + ".time"
    if os.path.exists(image) and os.path.exists(times):
        with open(times) as f:
            return tuple(float(x) for x in f.read().split())
    tfile = image + ".cpu"
    cmd = ["/usr/bin/time", "-f", "%U %S", "-o", tfile, args.glint, "render", args.model,
           "-o", image, "--threads", str(args.threads), "--integrator", integrator,
           "--max-depth", str(args.max_depth), "--spp", str(spp), "--seed", str(seed),
           "--width", str(args.width), "--height", str(args.height)] + args.light
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"failed: {' '.join(cmd)}\n{p.stderr[-2000:]}")
    m = re.search(r"rendered in ([0-9.]+) s", p.stderr)
    if not m:
        sys.exit(f"no render time in:\n{p.stderr[-2000:]}")
    with open(tfile) as f:
        cpu = sum(float(x) for x in f.read().split()[-2:])
    with open(times, "w") as f:
        f.write(f"{float(m.group(1))} {cpu}\n")
    return float(m.group(1)), cpu


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--model", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--glint", default=os.path.join(ROOT, "target/release/glint"))
    ap.add_argument("--spp", nargs="+", type=int, default=[1, 4, 16, 64])
    ap.add_argument("--ref-spp", type=int, default=1024)
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=320)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--max-depth", type=int, default=8)
    ap.add_argument("--light", nargs="*",
                    default=["--env", os.path.join(SHARED, "env/studio.exr")],
                    help="light options passed to glint render (default: --env studio.exr)")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    name = os.path.splitext(os.path.basename(args.model))[0]
    refs = []
    for seed in (100, 101):
        image = os.path.join(args.out, f"{name}-ref-{seed}.exr")
        render(args, "path", args.ref_spp, seed, image)
        refs.append(read_rgb(image))
    ref = (refs[0] + refs[1]) / 2
    den = ref ** 2 + EPS
    # The reference's own noise, as relMSE of the mean of its two renders (variance / 2).
    ref_noise = float(np.mean((refs[0] - refs[1]) ** 2 / 4 / den))
    print(f"{name}, {args.width}×{args.height}, {' '.join(args.light)}, max depth "
          f"{args.max_depth}; reference: path, 2 × {args.ref_spp} spp (its own noise: relMSE "
          f"{ref_noise:.2g}, included in every error below)\n")
    print("| integrator | spp | render s | CPU s | relMSE vs path reference | noise (two-seed) |")
    print("|---|---|---|---|---|---|")
    for integrator in ("direct", "path"):
        for spp in args.spp:
            imgs, times = [], []
            for seed in (0, 1):
                image = os.path.join(args.out, f"{name}-{integrator}-{spp}-{seed}.exr")
                times.append(render(args, integrator, spp, seed, image))
                imgs.append(read_rgb(image))
            err = float(np.mean([np.mean((im - ref) ** 2 / den) for im in imgs]))
            noise = float(np.mean((imgs[0] - imgs[1]) ** 2 / 2 / den))
            rs = float(np.median([t[0] for t in times]))
            cpu = float(np.median([t[1] for t in times]))
            print(f"| {integrator} | {spp} | {rs:.3f} | {cpu:.2f} | {err:.4g} | {noise:.4g} |")


if __name__ == "__main__":
    main()
