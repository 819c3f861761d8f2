#!/bin/bash
# measurement: one `glint batch` against K `glint render` processes (docs/batch.md). Run: tools/batch-vs-render.sh SCENE K WIDTH HEIGHT SPP
# K small jobs on one scene: one `glint batch` against K `glint render` processes doing the
# same renders (default camera, seeds 1..K). Prints wall time and peak RSS (/usr/bin/time).
# Usage: tools/batch-vs-render.sh SCENE K WIDTH HEIGHT SPP   (GLINT=path picks the binary)
set -e
G=$(realpath "${GLINT:-target/release/glint}")
SCENE=$(realpath "$1"); K=$2; W=$3; H=$4; SPP=$5
D=$(mktemp -d); cd "$D"
{ echo "[defaults]"; echo "scene = \"$SCENE\""; echo "width = $W"; echo "height = $H"
  echo "spp = $SPP"; echo "[[sweep]]"; echo "output = \"b/f{seed:03}.png\""
  echo "seed = [$(seq -s, 1 "$K")]"; } > jobs.toml
mkdir -p s
/usr/bin/time -f "%e %M" -o batch.time "$G" batch jobs.toml -q > /dev/null
start=$(date +%s.%N); maxrss=0
for i in $(seq 1 "$K"); do
  /usr/bin/time -f "%e %M" -o one.time "$G" render "$SCENE" --width "$W" --height "$H" \
    --spp "$SPP" --seed "$i" -o "s/f$i.png" -q
  rss=$(cut -d' ' -f2 one.time); [ "$rss" -gt "$maxrss" ] && maxrss=$rss
done
end=$(date +%s.%N)
read -r bt brss < batch.time
st=$(echo "$end - $start" | bc)
echo "$(basename "$SCENE") K=$K ${W}x${H} spp=$SPP: batch ${bt} s, ${brss} KiB;" \
  "separate ${st} s, peak ${maxrss} KiB; separate/batch time $(echo "scale=2; $st / $bt" | bc)," \
  "batch/one-render peak RSS $(echo "scale=2; $brss / $maxrss" | bc)"
cd /; rm -rf "$D"
