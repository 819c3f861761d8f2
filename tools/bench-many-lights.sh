#!/usr/bin/env bash
# measurement: time per sample with 64 point lights against 1 (docs/lights.md). Run: tools/bench-many-lights.sh [GLINT_BINARY] [RUNS]
# Time per sample with 64 point lights against 1 (issue 21): renders a shared scene under
# lights given with --lights (64 random point lights of total intensity 32 W/sr, or one of
# 32 W/sr), path tracer, alternating the two, and prints the median render-call time of each
# (the "rendered in" of the summary line, load excluded) and their ratio.
# Usage: tools/bench-many-lights.sh [GLINT_BINARY] [RUNS]
set -euo pipefail
glint=${1:-target/release/glint}
runs=${2:-5}
scene=${SCENE:-../shared/scenes/Suzanne/glTF/Suzanne.gltf}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 - "$dir" <<'PY'
import random, sys
random.seed(3)
d = sys.argv[1]
with open(f"{d}/l64.toml", "w") as f:
    for _ in range(64):
        x, y, z = random.uniform(-3, 3), random.uniform(1, 4), random.uniform(-3, 3)
        f.write(f'[[light]]\ntype = "point"\nposition = [{x:.3f}, {y:.3f}, {z:.3f}]\nintensity = 0.5\n\n')
with open(f"{d}/l1.toml", "w") as f:
    f.write('[[light]]\ntype = "point"\nposition = [1.0, 3.0, 1.0]\nintensity = 32.0\n')
PY
time_of() {
  "$glint" render "$scene" --lights "$dir/$1.toml" -o "$dir/out.exr" --width 320 --height 240 \
    --spp 16 --threads "${THREADS:-1}" 2>&1 | sed -n 's/.*rendered in \([0-9.]*\) s.*/\1/p'
}
: > "$dir/t1"; : > "$dir/t64"
for _ in $(seq "$runs"); do
  time_of l1 >> "$dir/t1"
  time_of l64 >> "$dir/t64"
done
python3 - "$dir" <<'PY'
import statistics, sys
d = sys.argv[1]
one = [float(x) for x in open(f"{d}/t1")]
many = [float(x) for x in open(f"{d}/t64")]
m1, m64 = statistics.median(one), statistics.median(many)
print(f"1 light: {m1:.3f} s, 64 lights: {m64:.3f} s (render call, median of {len(one)}): {m64 / m1:.2f}x")
PY
