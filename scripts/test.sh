#!/usr/bin/env bash
# The README's test command: installs what is missing, runs every test with the Embree backend
# compiled in (the default feature, so both backends are exercised), then proves the Embree 4
# path too (tools/check-embree4.sh: Embree 4 headers from the embree4-sys crate, a real
# libembree4 from the embreex wheel; it reuses target/ and rebuilds glint alone). Set
# GLINT_EMBREE4_CHECK=0 to skip that step on a machine without access to the package
# registries. Before it, tools/check-python.sh builds the Python package into target/pyvenv
# and runs its pytest suite (python/tests/); set GLINT_PYTHON_CHECK=0 to skip that step.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
export PATH="$HOME/.cargo/bin:$PATH"
# --denoise's tests run when scripts/setup.sh got Open Image Denoise (they say they are skipped
# otherwise).
features=()
if scripts/fetch-oidn.sh --check; then
    features=(--features denoise)
fi
# --no-fail-fast: one run reports every failing test binary, not just the first.
cargo test --locked --no-fail-fast "${features[@]}" "$@"
if [ "${GLINT_PYTHON_CHECK:-1}" != "0" ]; then
    tools/check-python.sh
fi
if [ "${GLINT_EMBREE4_CHECK:-1}" != "0" ]; then
    EMBREE4_TARGET_DIR=target tools/check-embree4.sh
fi
