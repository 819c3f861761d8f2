#!/usr/bin/env bash
# The Python tools' environment: target/tools-venv from tools/requirements.txt. Run: tools/python-venv.sh
# PYTHON picks the interpreter (default python3; the Cycles tools need 3.11 for bpy). Re-running
# it installs only what is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/tools-venv
if [ ! -x "$venv/bin/python" ]; then
    "${PYTHON:-python3}" -m venv "$venv"
fi
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r tools/requirements.txt
echo "tools environment ready: $venv/bin/python" >&2
