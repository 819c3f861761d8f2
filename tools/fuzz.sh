#!/usr/bin/env bash
# developer check: the stable-toolchain fuzz loop for a time budget (docs/hostile-input.md). Run: tools/fuzz.sh SECONDS [RNG_SEED]
# Runs the stable-toolchain fuzz loop (examples/fuzz_loader.rs) for SECONDS seconds in all and
# reports the executions and every crash file. A run that dies (an abort inside Embree, a hang
# killed by the watchdog, an out-of-memory kill) keeps its input as a crash and the loop goes
# on with the next RNG seed until the time is spent.
# Usage: tools/fuzz.sh SECONDS [RNG_SEED]
# Exit status: 0 when no crash was found, 1 otherwise.
set -uo pipefail
cd "$(dirname "$0")/.."
seconds="${1:?usage: tools/fuzz.sh SECONDS [RNG_SEED]}"
seed="${2:-$(date +%s)}"
crash_dir=fuzz-crashes
cargo build --release --locked --example fuzz_loader || exit 2
bin="${CARGO_TARGET_DIR:-target}/release/examples/fuzz_loader"
mkdir -p "$crash_dir"
log=$(mktemp)
trap 'rm -f "$log"' EXIT
end=$(( $(date +%s) + seconds ))
total=0 run=0 died=0
while now=$(date +%s); [ "$now" -lt "$end" ]; do
  left=$(( end - now ))
  rng=$(( seed + run ))
  # The watchdog: one execution takes milliseconds, so a minute past the budget is a hang.
  timeout -s KILL $(( left + 60 )) "$bin" "$left" "$rng" "$crash_dir" | tee "$log"
  status=${PIPESTATUS[0]}
  done_here=$(grep -oE '[0-9]+ executions' "$log" | tail -n 1 | grep -oE '^[0-9]+')
  total=$(( total + ${done_here:-0} ))
  if [ "$status" -eq 0 ] || [ "$status" -eq 1 ]; then
    break # the loader finished its time (1: it found and saved crashes)
  fi
  died=$(( died + 1 ))
  case "$status" in
    134) kind=abort ;;
    137) kind=killed ;; # the watchdog (a hang) or the kernel's out-of-memory killer
    139) kind=segfault ;;
    *) kind="exit$status" ;;
  esac
  for ext in gltf glb; do
    if [ -f "$crash_dir/in-progress.$ext" ]; then
      name="$crash_dir/crash-$kind-$rng-$run"
      mv "$crash_dir/in-progress.$ext" "$name.$ext"
      mv "$crash_dir/in-progress.seed" "$name.seed" 2>/dev/null
      echo "fuzz.sh: the loader died ($kind, status $status) after ${done_here:-?} executions; its input is $name.$ext" >&2
    fi
  done
  run=$(( run + 1 ))
done
shopt -s nullglob
crashes=("$crash_dir"/crash-*.gltf "$crash_dir"/crash-*.glb)
echo "fuzz.sh: $total executions in $seconds s (RNG seeds $seed..$(( seed + run ))), ${#crashes[@]} crash files in $crash_dir/ ($died runs died)"
for file in "${crashes[@]}"; do
  from=$(cat "${file%.*}.seed" 2>/dev/null || echo "unknown seed")
  echo "  $file (mutant of $from)"
done
if [ "${#crashes[@]}" -gt 0 ]; then
  echo "fuzz.sh: make each a regression test: cp FILE \"\${FILE%.*}.seed\" tests/fuzz-regressions/ and run cargo test --test hostile -- fuzz_regressions:: (it must fail until the bug is fixed)"
  exit 1
fi
