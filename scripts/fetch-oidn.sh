#!/usr/bin/env bash
# Makes Intel Open Image Denoise 2.x (the library behind `glint render --denoise`) available to
# the build, without installing anything system-wide when the system has no package for it:
#   - a system install found by pkg-config (`OpenImageDenoise`, e.g. Debian 13 / Ubuntu 24.04's
#     libopenimagedenoise-dev, which scripts/setup.sh installs where the distribution has it)
#     is used as it is;
#   - otherwise (Debian 12) the official Linux x86_64 build of OIDN 2.5.1 that the PyPI wheel
#     pyoidn 2.5.1.0 ships (pip download, pinned by its sha256) is unpacked into .oidn/lib/ of
#     this checkout: libOpenImageDenoise.so.2, its core and CPU device libraries, and the oneTBB
#     library the CPU device needs; nothing else of the wheel (no GPU devices, no Python code).
#     .cargo/config.toml points the oidn crate's build at it (OIDN_DIR) and build.rs gives
#     glint's binaries and tests an rpath to it.
# Licences: OIDN and oneTBB are Apache-2.0 (Intel); the wheel's own binding code is MIT
# (Copyright 2025 Carbene Hu, its LICENSE file); none of the binding is used.
#
# Usage: scripts/fetch-oidn.sh          fetches if needed; exits 0 when the library is there
#        scripts/fetch-oidn.sh --check  fetches nothing; exits 0 when the library is there
# Prints one line on stderr saying where the library is, or why it is not.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
DEST="$ROOT/.oidn"
PYOIDN_VERSION="${PYOIDN_VERSION:-2.5.1.0}"
PYOIDN_SHA256="${PYOIDN_SHA256:-32ad13368f8de1ef63001942ad05b02a00cd732d1206d97f352d3a3f606d823e}"
WHEEL="pyoidn-$PYOIDN_VERSION-py3-none-manylinux2014_x86_64.whl"

if [ -f "$DEST/lib/libOpenImageDenoise.so" ] && [ "$(cat "$DEST/.unpacked" 2>/dev/null || true)" = "$PYOIDN_SHA256" ]; then
    echo "oidn: $DEST/lib (OIDN from pyoidn $PYOIDN_VERSION)" >&2
    exit 0
fi
if pkg-config --exists 'OpenImageDenoise >= 2' 2>/dev/null; then
    echo "oidn: system OpenImageDenoise $(pkg-config --modversion OpenImageDenoise)" >&2
    exit 0
fi
if [ "${1:-}" = "--check" ]; then
    echo "oidn: not found (scripts/setup.sh or scripts/fetch-oidn.sh gets it)" >&2
    exit 1
fi
if [ "$(uname -s)/$(uname -m)" != Linux/x86_64 ]; then
    echo "oidn: no OpenImageDenoise 2 found by pkg-config, and the pyoidn wheel is for Linux x86_64 only: install OIDN 2 and its pkg-config file" >&2
    exit 1
fi
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
echo "pyoidn==$PYOIDN_VERSION --hash=sha256:$PYOIDN_SHA256" >"$tmp/requirements.txt"
# The wheel is py3-none: any local python downloads the same file; pip refuses another hash.
if ! python3 -m pip download --quiet --no-deps --require-hashes --only-binary=:all: \
    --platform manylinux2014_x86_64 --python-version 3.11 --dest "$tmp" -r "$tmp/requirements.txt" >&2; then
    echo "oidn: pip could not download pyoidn==$PYOIDN_VERSION (sha256 $PYOIDN_SHA256); --denoise needs OIDN 2" >&2
    exit 1
fi
rm -rf "$DEST.part"
mkdir -p "$DEST.part/lib"
python3 - "$tmp/$WHEEL" "$DEST.part/lib" <<'PY'
import os, shutil, sys, zipfile
wheel, dest = sys.argv[1], sys.argv[2]
wanted = ("libOpenImageDenoise.so.2.5.1", "libOpenImageDenoise_core.so.2.5.1",
          "libOpenImageDenoise_device_cpu.so.2.5.1", "libtbb.so.12")
with zipfile.ZipFile(wheel) as z:
    for name in wanted:
        with z.open("pyoidn/oidn/lib/" + name) as src, open(os.path.join(dest, name), "wb") as out:
            shutil.copyfileobj(src, out)
# The link names, as symbolic links (the wheel stores copies).
os.symlink("libOpenImageDenoise.so.2.5.1", os.path.join(dest, "libOpenImageDenoise.so.2"))
os.symlink("libOpenImageDenoise.so.2", os.path.join(dest, "libOpenImageDenoise.so"))
PY
echo "$PYOIDN_SHA256" >"$DEST.part/.unpacked"
rm -rf "$DEST"
mv "$DEST.part" "$DEST"
if ldd "$DEST/lib/libOpenImageDenoise_device_cpu.so.2.5.1" | grep -q 'not found'; then
    echo "oidn: the CPU device library has unresolved dependencies" >&2
    exit 1
fi
echo "oidn: $DEST/lib (OIDN 2.5.1 from pyoidn $PYOIDN_VERSION)" >&2
