#!/usr/bin/env python3
# measurement: glint against Cycles at equal error, the speed table of docs/speed.md. Run: target/tools-venv/bin/python tools/compare-cycles.py run --out DIR; then ... table --out DIR
"""glint's path tracer against Blender Cycles at equal error (issue 12's speed table).

Renders each model with both renderers at several spp and two seeds, under the studio HDRI with
8 bounces, the same thread count and size, a 1-pixel box filter on both sides, and measures:

* error: each renderer against ITSELF. Two renders a, b of the same spp with independent seeds
  give an unbiased estimate of the variance of one render, (a − b)²/2 per pixel and channel, so no
  reference image is needed. It is normalised as `glint converge` does (relMSE =
  mean of err / (r² + 0.01)), with r the renderer's own highest-spp image (mean of its two seeds).
  For an unbiased renderer this is the expected relMSE of one image against its converged limit.
* time: wall and CPU (user + sys of the whole process, from /usr/bin/time), and the renderer's
  own render time: Cycles' `render_s` (bpy.ops.render.render(): scene sync, BVH build, texture
  load and sampling; Python start-up, `import bpy` and the glTF import excluded) and glint's
  "rendered in" time (sampling only; load, BVH and MIP chains excluded). Both are wall times.
  For Cycles also `render_cpu_s`: the CPU time (user + sys, every thread) of that same render
  call, measured by tools/cycles_timed.py, which runs ../shared/peers/cycles_render.py
  unchanged. glint rows leave `render_cpu_s` empty: issue 23 times glint's whole process
  (`cpu_s`), so no render-call CPU is measured for it.
* issue 23's time: Cycles' render call against glint's whole process, both in CPU time, i.e.
  `render_cpu_s` for Cycles rows and `cpu_s` for glint rows. The equal-error tables use it
  where their headers say so. Rows from runs before `render_cpu_s` existed (an old runs.csv)
  fall back to Cycles' whole-process `cpu_s`, with a warning on stderr and in the table text.
  Fixed costs are separated from sampling by a least-squares line t = a + b·spp over the spp
  levels of each renderer and model: b is the cost per sample per pixel, a the fixed cost
  (load, import, sync, BVH) that that timer includes.
* equal error: the time each renderer needs for the relMSE Cycles reaches at each measured spp.
  glint's spp for Cycles' error is interpolated in log-log between glint's two measured levels
  that bracket it (the nearest two outside the range), its time read from the time line. The
  fitted error slope is printed too, as a check on 1/spp convergence.

Usage (from the repository root; the venv needs bpy, numpy, OpenEXR):

    /work/bpyvenv/bin/python tools/compare-cycles.py run --out /tmp/speed [--models ...]
    /work/bpyvenv/bin/python tools/compare-cycles.py table --out /tmp/speed > table.md

`run` appends one CSV row per render to OUT/runs.csv and skips renders whose row exists, so it
can be interrupted and resumed. `table` prints the Markdown tables of docs/speed.md.

Variants (issue 23): `--variant LABEL=RENDERER:ARGS` adds a renderer row under LABEL, rendered by
`cycles` or `glint` with the extra ARGS (split on spaces), e.g.
`--variant cycles-adaptive=cycles:--adaptive 0.01` (Blender's default adaptive sampling) or
`--variant glint-adaptive=glint:--adaptive 0.01`. Name them in `--renderers`. The equal-error
table compares every glint label with every Cycles label.
"""

import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys

import numpy as np
import OpenEXR

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.normpath(os.path.join(ROOT, "..", "shared"))
KHRONOS = os.path.join(SHARED, "khronos")

MODELS = {
    "MetalRoughSpheresNoTextures": os.path.join(
        KHRONOS, "MetalRoughSpheresNoTextures/glTF-Binary/MetalRoughSpheresNoTextures.glb"),
    "NormalTangentMirrorTest": os.path.join(
        KHRONOS, "NormalTangentMirrorTest/glTF-Binary/NormalTangentMirrorTest.glb"),
    "DamagedHelmet": os.path.join(SHARED, "scenes/DamagedHelmet/glTF/DamagedHelmet.gltf"),
    "GlassVaseFlowers": os.path.join(KHRONOS, "GlassVaseFlowers/glTF-Binary/GlassVaseFlowers.glb"),
    "Duck": os.path.join(KHRONOS, "Duck/glTF-Binary/Duck.glb"),
}
FIELDS = ["model", "renderer", "spp", "seed", "width", "height", "wall_s", "cpu_s", "render_s",
          "image", "render_cpu_s"]
REL_MSE_EPSILON = 1e-2


def read_rgb(path):
    """Linear RGB of an EXR as a float64 H×W×3 array."""
    with OpenEXR.File(path) as f:
        channels = f.channels()
        # OpenEXR's Python API groups R, G, B (and A: glint writes coverage) into one entry.
        for name in ("RGB", "RGBA"):
            if name in channels:
                return np.asarray(channels[name].pixels, dtype=np.float64)[..., :3]
        return np.stack([np.asarray(channels[c].pixels, dtype=np.float64)
                         for c in ("R", "G", "B")], axis=-1)


def timed(cmd):
    """Runs cmd under /usr/bin/time; returns (stdout, stderr, wall s, user + sys CPU s)."""
    tfile = "/tmp/compare-cycles-time.txt"
    p = subprocess.run(["/usr/bin/time", "-f", "%e %U %S", "-o", tfile] + cmd,
                       capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"failed ({p.returncode}): {' '.join(cmd)}\n{p.stderr[-3000:]}")
    with open(tfile) as f:
        wall, user, sys_ = (float(x) for x in f.read().split()[-3:])
    return p.stdout, p.stderr, wall, user + sys_


def render_cycles(args, model, spp, seed, image, extra=()):
    """Renders through tools/cycles_timed.py (cycles_render.py unchanged, plus the render
    call's CPU); returns (wall s, CPU s of the process, render call wall s, render call CPU s)."""
    cmd = [args.python, os.path.join(ROOT, "tools/cycles_timed.py"), MODELS[model], image,
           "--materials", "native", "--env", os.path.join(SHARED, "env/studio.exr"),
           "--env-strength", "1", "--bounces", "8", "--animation", "off",
           "--width", str(args.width), "--height", str(args.width), "--spp", str(spp),
           "--threads", str(args.threads), "--seed", str(seed)] + list(extra)
    out, _, wall, cpu = timed(cmd)
    info = {}
    for line in out.strip().splitlines():  # the peer's JSON line, then the wrapper's
        info.update(json.loads(line))
    return wall, cpu, info["render_s"], info["render_cpu_s"]


def render_glint(args, model, spp, seed, image, width, height, extra=()):
    cmd = [args.glint, "render", MODELS[model], "-o", image, "--threads", str(args.threads),
           "--env", os.path.join(SHARED, "env/studio.exr"), "--max-depth", "8",
           "--integrator", "path", "--filter", "box", "--spp", str(spp), "--seed", str(seed),
           "--width", str(width), "--height", str(height)] + list(extra)
    _, err, wall, cpu = timed(cmd)
    m = re.search(r"rendered in ([0-9.]+) s", err)
    if not m:
        sys.exit(f"no render time in glint's output:\n{err[-2000:]}")
    return wall, cpu, float(m.group(1))


def load_rows(out):
    path = os.path.join(out, "runs.csv")
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return list(csv.DictReader(f))


def run(args):
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, "runs.csv")
    done = {(r["model"], r["renderer"], r["spp"], r["seed"]) for r in load_rows(args.out)}
    new = not os.path.exists(path)
    fields = FIELDS
    if not new:
        with open(path) as f:
            fields = next(csv.reader(f), FIELDS)
        if "render_cpu_s" not in fields:
            print(f"warning: {path} has no render_cpu_s column (an older run): new rows keep its"
                  " columns and Cycles' render-call CPU is not recorded; use a new --out for it",
                  file=sys.stderr)
    with open(path, "a", newline="") as f:
        w = csv.DictWriter(f, fields, extrasaction="ignore")
        if new:
            w.writeheader()
        for model in args.models:
            for renderer in args.renderers:
                spps = (args.cycles_spp if variant(args, renderer)[0] == "cycles"
                        else args.glint_spp)
                for spp in spps:
                    for seed in range(args.seeds):
                        if (model, renderer, str(spp), str(seed)) in done:
                            continue
                        image = os.path.join(args.out, f"{model}-{renderer}-{spp}-{seed}.exr")
                        base, extra = variant(args, renderer)
                        render_cpu = ""  # glint: issue 23 times its whole process (cpu_s)
                        if base == "cycles":
                            wall, cpu, render_s, render_cpu = render_cycles(args, model, spp,
                                                                            seed, image, extra)
                        else:
                            size = cycles_size(args.out, model)
                            if size is None:
                                sys.exit(f"{model}: render Cycles first (its image gives the size)")
                            wall, cpu, render_s = render_glint(args, model, spp, seed, image,
                                                               *size, extra)
                        h, wdt = read_rgb(image).shape[:2]
                        row = dict(model=model, renderer=renderer, spp=spp, seed=seed, width=wdt,
                                   height=h, wall_s=wall, cpu_s=cpu, render_s=render_s,
                                   image=image, render_cpu_s=render_cpu)
                        w.writerow(row)
                        f.flush()
                        print(json.dumps(row), file=sys.stderr)


def variant(args, label):
    """(base renderer, extra arguments) of a renderer label: `cycles`, `glint`, or a --variant."""
    for v in args.variant:
        name, _, rest = v.partition("=")
        base, _, extra = rest.partition(":")
        if name == label:
            return base, extra.split()
    return label, []


def labels_of(res, base):
    """The renderer labels of `res` rendered by `base` (cycles or glint), base first."""
    found = sorted({k[1] for k in res if k[1].startswith(base)})
    return sorted(found, key=lambda x: (x != base, x))


def cycles_size(out, model):
    for r in load_rows(out):
        if r["model"] == model and r["renderer"].startswith("cycles"):
            return int(r["width"]), int(r["height"])
    return None


def line_fit(xs, ys):
    """Least-squares (intercept, slope) of y against x."""
    xs, ys = np.asarray(xs, float), np.asarray(ys, float)
    slope, intercept = np.polyfit(xs, ys, 1)
    return intercept, slope


def issue_time(r):
    """Issue 23's time of one row: (CPU s, whether it fell back). Cycles: its render call's CPU
    (`render_cpu_s`); glint: its whole process's CPU (`cpu_s`). A Cycles row without
    `render_cpu_s` (a run from before the column) falls back to its whole process."""
    if not r["renderer"].startswith("cycles"):
        return float(r["cpu_s"]), False
    if r.get("render_cpu_s"):
        return float(r["render_cpu_s"]), False
    return float(r["cpu_s"]), True


def measure(rows):
    """Per (model, renderer): spp levels with relMSE and median times, and the fitted lines."""
    groups = {}
    for r in rows:
        groups.setdefault((r["model"], r["renderer"]), {}).setdefault(int(r["spp"]), []).append(r)
    result = {}
    for key, by_spp in groups.items():
        levels = sorted(s for s, rs in by_spp.items() if len(rs) >= 2)
        if len(levels) < 2:
            continue
        top = by_spp[levels[-1]]
        ref = (read_rgb(top[0]["image"]) + read_rgb(top[1]["image"])) / 2
        points = []
        for spp in levels:
            rs = sorted(by_spp[spp], key=lambda r: int(r["seed"]))
            a, b = read_rgb(rs[0]["image"]), read_rgb(rs[1]["image"])
            var = (a - b) ** 2 / 2
            rel = float(np.mean(var / (ref ** 2 + REL_MSE_EPSILON)))
            m = (a + b) / 2
            rel_self = float(np.mean(var / (m ** 2 + REL_MSE_EPSILON)))
            med = lambda k: float(np.median([float(r[k]) for r in rs]))  # noqa: E731
            issue = [issue_time(r) for r in rs]
            points.append(dict(spp=spp, rel_mse=rel, rel_mse_self=rel_self, wall=med("wall_s"),
                               cpu=med("cpu_s"),
                               render=med("render_s"),
                               issue=float(np.median([t for t, _ in issue])),
                               fallback=any(fb for _, fb in issue)))
        err_fit = line_fit([math.log(p["spp"]) for p in points],
                           [math.log(p["rel_mse"]) for p in points])
        fits = {k: line_fit([p["spp"] for p in points], [p[k] for p in points])
                for k in ("wall", "cpu", "render", "issue")}
        result[key] = dict(points=points, err_fit=err_fit, fits=fits,
                           size=(top[0]["width"], top[0]["height"]),
                           fallback=any(p["fallback"] for p in points))
    return result


def warn_fallbacks(res):
    """Says on stderr and in the Markdown which Cycles rows lack their render call's CPU."""
    old = sorted(f"{k[0]}/{k[1]}" for k, m in res.items() if m["fallback"])
    if not old:
        return
    text = ("Warning: these Cycles rows have no render_cpu_s (an older runs.csv): their issue-23"
            " time falls back to the whole process's CPU, which includes Python start-up,"
            " `import bpy` and the glTF import: " + ", ".join(old) + ".")
    print(text, file=sys.stderr)
    print(text + "\n")


def spp_for(m, rel):
    """The spp at which renderer m reaches relMSE rel: log-log interpolation between its two
    measured levels that bracket rel (the nearest two outside the range). Piecewise, not one
    fitted line, because a few lamp fireflies can dominate the two-seed estimate at low spp."""
    pts = [(math.log(p["spp"]), math.log(p["rel_mse"])) for p in m["points"]]
    y = math.log(rel)
    segments = list(zip(pts, pts[1:]))
    chosen = segments[0] if y > max(p[1] for p in pts) else segments[-1]
    for seg in segments:
        if min(seg[0][1], seg[1][1]) <= y <= max(seg[0][1], seg[1][1]):
            chosen = seg
            break
    (x0, y0), (x1, y1) = chosen
    if y1 == y0:
        return float("nan")
    return math.exp(x0 + (y - y0) * (x1 - x0) / (y1 - y0))


def table(args):
    res = measure(load_rows(args.out))
    warn_fallbacks(res)
    models = sorted({k[0] for k in res})
    print("Per renderer and model: relMSE of one render against its own converged image (two-seed"
          " estimate), and median times of the two seeds (s). render s: the renderer's own timer"
          " (wall); render CPU s: Cycles' render call in CPU time (user + sys, all threads).\n")
    print("| model | renderer | spp | relMSE | render s | render CPU s | CPU s (process) |"
          " wall s (process) |")
    print("|---|---|---|---|---|---|---|---|")
    renderers = labels_of(res, "cycles") + labels_of(res, "glint")
    for model in models:
        for ren in renderers:
            m = res.get((model, ren))
            if not m:
                continue
            for p in m["points"]:
                render_cpu = ("–" if p["fallback"] or not ren.startswith("cycles")
                              else f"{p['issue']:.2f}")
                print(f"| {model} | {ren} | {p['spp']} | {p['rel_mse']:.4g} | {p['render']:.2f} "
                      f"| {render_cpu} | {p['cpu']:.2f} | {p['wall']:.2f} |")
    print("\nFitted lines: error slope (d ln relMSE / d ln spp), fixed cost a and cost per spp b of"
          " t = a + b·spp (CPU s of the whole process; render s of the renderer's own timer;"
          " issue-23 time: CPU s of Cycles' render call, of glint's whole process).\n")
    print("| model | size | renderer | error slope | CPU a | CPU b (per spp) | render a |"
          " render b (per spp) | issue-23 a | issue-23 b (per spp) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for model in models:
        for ren in renderers:
            m = res.get((model, ren))
            if not m:
                continue
            f = m["fits"]
            print(f"| {model} | {m['size'][0]}×{m['size'][1]} | {ren} | {m['err_fit'][1]:.3f} "
                  f"| {f['cpu'][0]:.2f} | {f['cpu'][1]:.4f} | {f['render'][0]:.2f} "
                  f"| {f['render'][1]:.4f} | {f['issue'][0]:.2f} | {f['issue'][1]:.4f} |")
    print("\nEqual error: for the relMSE Cycles reaches at each spp, the spp glint needs (log-log"
          " interpolation) and each renderer's sampling cost for it (b·spp, fixed costs excluded) and"
          " total (a + b·spp); speed-up = Cycles' time / glint's. Issue 23's column: Cycles' render"
          " call against glint's whole process, CPU time, a + b·spp.\n")
    print("| model | Cycles | Cycles spp | relMSE | glint | glint spp | speed-up, CPU per spp |"
          " speed-up, CPU incl. fixed | speed-up, render timer (wall) per spp |"
          " speed-up, issue 23 (Cycles render call, glint process; CPU) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    pairs = [(c, g) for c in labels_of(res, "cycles") for g in labels_of(res, "glint")]
    for model in models:
        for cl, gl in pairs:
            c, g = res.get((model, cl)), res.get((model, gl))
            if not (c and g):
                continue
            for p in c["points"]:
                n = spp_for(g, p["rel_mse"])
                cells = []
                for k, incl in (("cpu", False), ("cpu", True), ("render", False),
                                ("issue", True)):
                    (ca, cb), (ga, gb) = c["fits"][k], g["fits"][k]
                    tc = cb * p["spp"] + (ca if incl else 0.0)
                    tg = gb * n + (ga if incl else 0.0)
                    cells.append(f"{tc / tg:.2f}×")
                print(f"| {model} | {cl} | {p['spp']} | {p['rel_mse']:.4g} | {gl} | {n:.0f} | "
                      + " | ".join(cells) + " |")
    print("\nAt equal spp (issue 23's measure): relMSE of each renderer from its two seeds a, b with"
          " m = (a + b)/2, relMSE = mean(((a − b)²/2)/(m² + 0.01)); speed-up at equal error ="
          " (CPU_cycles · relMSE_cycles)/(CPU_glint · relMSE_glint), with CPU_cycles the CPU time"
          " of Cycles' render call (bpy.ops.render.render(), all threads) and CPU_glint that of"
          " glint's whole process.\n")
    print("| model | spp | Cycles | relMSE | render-call CPU s | glint | relMSE | process CPU s |"
          " speed-up |")
    print("|---|---|---|---|---|---|---|---|---|")
    for model in models:
        for cl, gl in pairs:
            c, g = res.get((model, cl)), res.get((model, gl))
            if not (c and g):
                continue
            gp = {p["spp"]: p for p in g["points"]}
            for p in c["points"]:
                q = gp.get(p["spp"])
                if q is None:
                    continue
                ec, eg = p["rel_mse_self"], q["rel_mse_self"]
                print(f"| {model} | {p['spp']} | {cl} | {ec:.4g} | {p['issue']:.2f} | {gl} | {eg:.4g} "
                      f"| {q['issue']:.2f} | {equal_spp_speedup(p, q):.2f}× |")
    summary(res, models)


def equal_spp_speedup(p, q):
    """Issue 23's speed-up of glint's point q over Cycles' point p at the same spp: issue-23
    time × relMSE (each from its own two seeds), Cycles' over glint's."""
    return (p["issue"] * p["rel_mse_self"]) / (q["issue"] * q["rel_mse_self"])


def summary(res, models):
    """Issue 23's count: per model, spp and glint label, the equal-spp speed-up against the
    smaller of Cycles' labels (plain and adaptive), and which one it was."""
    cycles, glints = labels_of(res, "cycles"), labels_of(res, "glint")
    spps = sorted({p["spp"] for m in res.values() for p in m["points"]})
    print("\nSummary (issue 23's count): the equal-spp speed-up above against the smaller of"
          f" {', '.join(cycles)} at each spp; the Cycles label that gave it in brackets.\n")
    print("| model | glint | " + " | ".join(f"{s} spp" for s in spps) + " |")
    print("|---|---|" + "---|" * len(spps))
    for model in models:
        for gl in glints:
            g = res.get((model, gl))
            if not g:
                continue
            gp = {p["spp"]: p for p in g["points"]}
            cells = []
            for spp in spps:
                q = gp.get(spp)
                best = None
                for cl in cycles:
                    c = res.get((model, cl))
                    p = c and next((x for x in c["points"] if x["spp"] == spp), None)
                    if not (p and q):
                        continue
                    f = equal_spp_speedup(p, q)
                    if best is None or f < best[0]:
                        best = (f, cl)
                cells.append(f"{best[0]:.2f}× ({best[1]})" if best else "–")
            print(f"| {model} | {gl} | " + " | ".join(cells) + " |")


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("command", choices=["run", "table"])
    ap.add_argument("--out", required=True, help="folder for the renders and runs.csv")
    ap.add_argument("--models", nargs="+", default=list(MODELS)[:4], choices=list(MODELS))
    ap.add_argument("--renderers", nargs="+", default=["cycles", "glint"],
                    help="renderer labels: cycles, glint, or --variant labels")
    ap.add_argument("--variant", action="append", default=[], metavar="LABEL=RENDERER:ARGS",
                    help="a renderer label rendered by cycles or glint with extra arguments")
    ap.add_argument("--cycles-spp", nargs="+", type=int, default=[16, 64, 256])
    ap.add_argument("--glint-spp", nargs="+", type=int, default=[16, 64, 256])
    ap.add_argument("--seeds", type=int, default=2, help="seeds per spp (the first two give the"
                    " error; every one's time enters the median)")
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--glint", default=os.path.join(ROOT, "target/release/glint"))
    ap.add_argument("--python", default="/work/bpyvenv/bin/python",
                    help="Python with bpy for the Cycles side")
    args = ap.parse_args()
    if args.command == "run":
        run(args)
    else:
        table(args)


if __name__ == "__main__":
    main()
