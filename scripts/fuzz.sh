#!/usr/bin/env bash
# Runs the stable-toolchain fuzz loop (examples/fuzz_loader.rs) for SECONDS seconds and
# reports the executions; crashing mutants are saved under fuzz-crashes/.
# Usage: scripts/fuzz.sh SECONDS [RNG_SEED]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:?usage: scripts/fuzz.sh SECONDS [RNG_SEED]}"
seed="${2:-$(date +%s)}"
cargo build --release --locked --example fuzz_loader
exec target/release/examples/fuzz_loader "$seconds" "$seed" fuzz-crashes
