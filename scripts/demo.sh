#!/usr/bin/env bash
# The README's demo command: installs what is missing, builds glint in release mode and renders
# the built-in demo scene to glint-demo.png in the current directory, lit by the studio
# environment map in scenes/demo-env.hdr (CC0, see scenes/demo-env-LICENSE.txt) unless the
# arguments choose an environment themselves (--env or --background), denoised with Open Image
# Denoise (--denoise) when scripts/setup.sh got the library (the summary line then says
# "denoised"). Other arguments go to `glint render` as they are.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
export PATH="$HOME/.cargo/bin:$PATH"
environment=(--env "$root/scenes/demo-env.hdr")
for arg in "$@"; do
    case "$arg" in
    --env | --env=* | --background | --background=*) environment=() ;;
    esac
done
features=()
denoise=()
if "$root/scripts/fetch-oidn.sh" --check 2>/dev/null; then
    features=(--features denoise)
    denoise=(--denoise)
    # cargo reads .cargo/config.toml (which names .oidn) from the current folder upwards, not
    # from the manifest's: the demo runs from any folder, so the library's place is passed here.
    if [ -z "${OIDN_DIR:-}" ] && [ -d "$root/.oidn" ]; then
        export OIDN_DIR="$root/.oidn"
    fi
fi
cargo run --locked --release --manifest-path "$root/Cargo.toml" "${features[@]}" -- render "${environment[@]}" "${denoise[@]}" "$@"
