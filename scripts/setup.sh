#!/usr/bin/env bash
# Installs what glint needs to build on Debian/Ubuntu, only what is missing:
#   libembree-dev  Embree (3.13 on Debian 12, 4.x on Debian 13 / Ubuntu 24.04)
#   libclang-dev   libclang for bindgen
#   libfontconfig1-dev, fonts-dejavu-core   fonts for the plots of `glint converge`
#   Open Image Denoise 2 (optional, for --denoise): libopenimagedenoise-dev where the distribution
#   has it, else scripts/fetch-oidn.sh (the official build from the pyoidn wheel, into .oidn/)
#   pkg-config, a C and a C++ compiler (the KTX2 tests' reference encoder), python3-pip (the Embree 4 check), python3-venv (the Python
#   package's tests), curl (for rustup, if Rust is
#   missing)
# and a Rust toolchain through rustup when cargo is not on PATH.
set -euo pipefail

need=()
dpkg -s libembree-dev >/dev/null 2>&1 || need+=(libembree-dev)
dpkg -s libclang-dev >/dev/null 2>&1 || need+=(libclang-dev)
dpkg -s pkg-config >/dev/null 2>&1 || command -v pkg-config >/dev/null || need+=(pkg-config)
command -v cc >/dev/null 2>&1 || need+=(build-essential)
# The KTX2 tests build Binomial's reference Basis Universal encoder (C++, a dev-dependency).
command -v c++ >/dev/null 2>&1 || need+=(g++)
# glint converge draws its plots with plotters, which finds fonts through fontconfig.
dpkg -s libfontconfig1-dev >/dev/null 2>&1 || need+=(libfontconfig1-dev)
dpkg -s fonts-dejavu-core >/dev/null 2>&1 || need+=(fonts-dejavu-core)
# The Embree 4 check in scripts/test.sh fetches a wheel with pip.
python3 -m pip --version >/dev/null 2>&1 || need+=(python3-pip)
# The Python package's tests (tools/check-python.sh) build it in a venv.
python3 -c "import venv, ensurepip" >/dev/null 2>&1 || need+=(python3-venv)
if ! command -v cargo >/dev/null 2>&1 && [ ! -x "$HOME/.cargo/bin/cargo" ]; then
    command -v curl >/dev/null 2>&1 || need+=(curl ca-certificates)
fi

if [ ${#need[@]} -gt 0 ]; then
    echo "setup: installing ${need[*]}" >&2
    sudo=""
    if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
    export DEBIAN_FRONTEND=noninteractive
    $sudo apt-get update -qq
    $sudo apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi

if ! command -v cargo >/dev/null 2>&1; then
    if [ ! -x "$HOME/.cargo/bin/cargo" ]; then
        echo "setup: installing the stable Rust toolchain with rustup" >&2
        curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh -s -- -y --profile minimal >&2
    fi
fi
# Open Image Denoise 2 for `--denoise` (feature `denoise`): the distribution's package where it
# has one (Debian 13, Ubuntu 24.04), else the official build from the pyoidn wheel, unpacked into
# .oidn/ (scripts/fetch-oidn.sh). Without it glint still builds and runs; only --denoise fails.
if ! pkg-config --exists 'OpenImageDenoise >= 2' 2>/dev/null &&
    apt-cache policy libopenimagedenoise-dev 2>/dev/null | grep -q 'Candidate: [0-9]'; then
    echo "setup: installing libopenimagedenoise-dev" >&2
    sudo=""
    if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends libopenimagedenoise-dev >/dev/null ||
        echo "setup: libopenimagedenoise-dev did not install; trying the pyoidn wheel" >&2
fi
"$(dirname "$0")/fetch-oidn.sh" || echo "setup: continuing without Open Image Denoise (--denoise will not be available)" >&2
echo "setup: ready ($(dpkg-query -W -f='${Package} ${Version}' libembree-dev 2>/dev/null || echo 'embree: ?'))" >&2
