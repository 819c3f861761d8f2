#!/usr/bin/env bash
# The README's demo command: installs what is missing, builds glint in release mode and renders
# the built-in demo scene to glint-demo.png in the current directory.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
export PATH="$HOME/.cargo/bin:$PATH"
cargo run --locked --release --manifest-path "$root/Cargo.toml" -- render "$@"
