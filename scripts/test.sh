#!/usr/bin/env bash
# The README's test command: installs what is missing, then runs every test with the Embree
# backend compiled in (the default feature), so both backends are exercised.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
export PATH="$HOME/.cargo/bin:$PATH"
cargo test --locked "$@"
