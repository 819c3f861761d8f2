#!/usr/bin/env bash
# developer check, run by scripts/test.sh: glint builds and passes its tests on Embree 4. Run: tools/check-embree4.sh (GLINT_EMBREE4_CHECK=0 scripts/test.sh skips it)
# Proves glint's Embree 4 path on a machine whose system Embree is 3 (Debian 12), with nothing
# installed system-wide, on headers and a library of ONE Embree 4 release and build
# configuration (4.3.3 with instance arrays, one instance level), each pinned by its sha256 so
# a new upload cannot change what is checked:
#   1. Embree 4 headers: Debian 13's libembree-dev (a .deb, fetched with apt-get into a private
#      state under .embree4/ that leaves the system's apt configuration alone, or straight from
#      the Debian pool where apt-get or Debian's keyring is missing; never installed).
#   2. ffi/shim.c and ffi/shim_test.c compile against them (-Wall -Wextra -Wpedantic -Werror).
#   3. A real libembree4 of the same release (and the libtbb it needs) from the PyPI wheel
#      raybender (pip download of its cp311 manylinux wheel, whatever the local python).
#      Debian's own libembree4-4 is not used: it needs glibc 2.38.
#   4. ffi/shim_test.c, the shim's C-level contract (headers and library of one release, no byte
#      written past our hit structs, hits, occlusion convention, errors, lifetimes; the kernel-
#      dependent checks once per instruction set the CPU supports), runs against that library,
#      and against the system Embree 3 as a control when there is one.
#   5. glint builds against those headers and that library (its own CARGO_TARGET_DIR), and its
#      Embree tests run on it: embree_version (expects major 4), embree_shim, embree_lifetimes,
#      backend_agreement and the library's unit tests. The test binaries find libembree4
#      through their rpath: LD_LIBRARY_PATH is cleared.
#
# Usage: tools/check-embree4.sh [ARGS...]   ARGS go to every test binary, e.g.
#        tools/check-embree4.sh --skip shared_assets_agree
#        EMBREE4_CHECK_C_ONLY=1 tools/check-embree4.sh   stops after step 4: the C-level
#        checks alone, without cargo (glint itself is then neither built nor tested).
# Downloads are cached in .embree4/ (git-ignored) and checked against their pinned sha256 on
# every run, and the build goes to target/embree4 (or EMBREE4_TARGET_DIR), so a rerun is fast
# and offline. Exits non-zero, naming the failed step, on any failure.
# Versions (override through the environment, each with its sha256, after checking the pair
# still matches): EMBREE4_DEB_VERSION and EMBREE4_DEB_SHA256 (with EMBREE4_DEB_SUITE, the
# Debian suite that carries it), RAYBENDER_VERSION and RAYBENDER_SHA256 (RAYBENDER_PYTHON, the
# CPython version its wheel is for).
set -euo pipefail

ROOT="$(cd "$(dirname "$0")/.." && pwd)"
CACHE="$ROOT/.embree4"
# Its own target dir by default, so the everyday build keeps linking the system Embree. CI may
# pass EMBREE4_TARGET_DIR=target to reuse the compiled dependencies (glint alone is rebuilt,
# here and again by the next plain cargo command) instead of building them all a second time.
TARGET_DIR="${EMBREE4_TARGET_DIR:-$ROOT/target/embree4}"
case "$TARGET_DIR" in /*) ;; *) TARGET_DIR="$ROOT/$TARGET_DIR" ;; esac
# Headers: Debian 13 (trixie) libembree-dev, Embree 4.3.3 (sha256 of the .deb, as in the
# suite's signed Packages index).
EMBREE4_DEB_VERSION="${EMBREE4_DEB_VERSION:-4.3.3+dfsg-1}"
EMBREE4_DEB_SHA256="${EMBREE4_DEB_SHA256:-674a8b3d1a00612f46730da29f4cc146267b4917bbf0242113d0568429e78726}"
EMBREE4_DEB_SUITE="${EMBREE4_DEB_SUITE:-trixie}"
# Library: raybender's wheel bundles libembree4-92ec4c98.so.4, Embree 4.3.3 (sha256 of
# raybender-4.0.3-cp311-cp311-manylinux_2_27_x86_64.manylinux_2_28_x86_64.whl).
RAYBENDER_VERSION="${RAYBENDER_VERSION:-4.0.3}"
RAYBENDER_SHA256="${RAYBENDER_SHA256:-1308889d8a1b913d93c8afb9288e26d685b5060e4c66e03e3bc5de645d29a037}"
RAYBENDER_PYTHON="${RAYBENDER_PYTHON:-3.11}"
C_ONLY="${EMBREE4_CHECK_C_ONLY:-0}"
# Warnings the shim must be free of, on both APIs.
CFLAGS_STRICT=(-std=c11 -Wall -Wextra -Wpedantic -Wshadow -Werror)

step=""
started=$SECONDS
step() {
    step="$1"
    printf '\n== %s\n' "$step"
}
die() {
    trap - EXIT
    printf '\ncheck-embree4: FAILED at "%s": %s\n' "$step" "$*" >&2
    exit 1
}
# Any other failing command (set -e) still names the step it stopped in.
trap 'rc=$?; [ $rc -eq 0 ] || printf "\ncheck-embree4: FAILED at \"%s\" (exit %d)\n" "$step" "$rc" >&2' EXIT

tools=(cc python3 sha256sum dpkg-deb)
[ "$C_ONLY" = 1 ] || tools+=(cargo)
for tool in "${tools[@]}"; do
    command -v "$tool" >/dev/null || die "$tool is not installed (scripts/setup.sh installs what glint needs)"
done
[ "$(uname -s)/$(uname -m)" = Linux/x86_64 ] || die "this check uses an x86_64 .deb and manylinux wheel: Linux x86_64 only"
mkdir -p "$CACHE"

# Checks FILE against its pinned sha256 (EXPECTED, from the variable NAME); a file that does
# not match is moved aside (FILE.rejected) so the next run downloads it again.
check_sha256() {
    local file="$1" expected="$2" name="$3" got
    got="$(sha256sum "$file" | cut -d' ' -f1)"
    if [ "$got" != "$expected" ]; then
        mv -f "$file" "$file.rejected"
        die "$(basename "$file") has sha256 $got, but $name pins $expected (moved aside to $file.rejected)"
    fi
    echo "sha256 ok: $(basename "$file")"
}

# Prints the first of its arguments that is a file (a glob that matched), nothing if none.
first_file() {
    local f
    for f in "$@"; do
        if [ -f "$f" ]; then
            echo "$f"
            break
        fi
    done
}

# unpack_once DIR SHA COMMAND...: runs COMMAND (which unpacks the archive whose sha256 is SHA
# into DIR) unless DIR already holds that archive.
unpack_once() {
    local dir="$1" sha="$2"
    shift 2
    if [ "$(cat "$dir/.unpacked" 2>/dev/null || true)" != "$sha" ]; then
        rm -rf "$dir"
        mkdir -p "$dir"
        "$@" || die "could not unpack into $dir"
        echo "$sha" >"$dir/.unpacked"
    fi
}

# ---- 1. headers -------------------------------------------------------------------------------
step "Embree 4 headers from Debian's libembree-dev $EMBREE4_DEB_VERSION ($EMBREE4_DEB_SUITE)"
DEBS="$CACHE/debs/$EMBREE4_DEB_VERSION"
mkdir -p "$DEBS"
deb="$(first_file "$DEBS"/libembree-dev_*_amd64.deb)"
if [ -z "$deb" ]; then
    keyring=/usr/share/keyrings/debian-archive-keyring.gpg
    if command -v apt-get >/dev/null && [ -f "$keyring" ]; then
        # apt-get on a private state and sources list (the system's stay untouched); the index
        # is thrown away once the .deb is here.
        APT="$CACHE/apt"
        rm -rf "$APT"
        mkdir -p "$APT/lists/partial" "$APT/cache/archives/partial" "$APT/etc"
        printf 'Types: deb\nURIs: http://deb.debian.org/debian\nSuites: %s\nComponents: main\nSigned-By: %s\n' \
            "$EMBREE4_DEB_SUITE" "$keyring" >"$APT/etc/embree4.sources"
        apt_opts=(-o Dir::Etc::SourceList=/dev/null -o Dir::Etc::SourceParts="$APT/etc"
            -o Dir::State::Lists="$APT/lists" -o Dir::Cache="$APT/cache"
            -o Debug::NoLocking=1 -o APT::Sandbox::User=root)
        apt-get "${apt_opts[@]}" -qq update || die "apt-get could not read Debian $EMBREE4_DEB_SUITE's index"
        (cd "$DEBS" && apt-get "${apt_opts[@]}" -qq download "libembree-dev=$EMBREE4_DEB_VERSION") ||
            die "apt-get could not download libembree-dev=$EMBREE4_DEB_VERSION from $EMBREE4_DEB_SUITE"
        rm -rf "$APT"
    else
        # No apt-get or no Debian keyring (Ubuntu): the pool file itself; the pinned sha256
        # below is what vouches for it either way.
        url="https://deb.debian.org/debian/pool/main/e/embree/libembree-dev_${EMBREE4_DEB_VERSION}_amd64.deb"
        echo "downloading $url"
        python3 -c 'import sys, urllib.request; urllib.request.urlretrieve(sys.argv[1], sys.argv[2])' \
            "$url" "$DEBS/libembree-dev_${EMBREE4_DEB_VERSION}_amd64.deb.part" ||
            die "could not download $url"
        mv "$DEBS/libembree-dev_${EMBREE4_DEB_VERSION}_amd64.deb.part" \
            "$DEBS/libembree-dev_${EMBREE4_DEB_VERSION}_amd64.deb"
    fi
    deb="$(first_file "$DEBS"/libembree-dev_*_amd64.deb)"
    [ -n "$deb" ] || die "no libembree-dev .deb in $DEBS after the download"
fi
check_sha256 "$deb" "$EMBREE4_DEB_SHA256" EMBREE4_DEB_SHA256
DEB_DIR="$CACHE/libembree-dev-$EMBREE4_DEB_VERSION"
unpack_once "$DEB_DIR" "$EMBREE4_DEB_SHA256" dpkg-deb -x "$deb" "$DEB_DIR"
INCLUDE="$DEB_DIR/usr/include"
[ -f "$INCLUDE/embree4/rtcore.h" ] || die "no embree4/rtcore.h under $INCLUDE"
HEADER_VERSION="$(sed -n 's/^#define RTC_VERSION_STRING "\(.*\)"/\1/p' "$INCLUDE/embree4/rtcore_config.h")"
echo "headers: $INCLUDE/embree4 (Embree $HEADER_VERSION)"
grep -E '^#define (RTC_MAX_INSTANCE_LEVEL_COUNT|EMBREE_MIN_WIDTH|EMBREE_GEOMETRY_INSTANCE_ARRAY)' \
    "$INCLUDE/embree4/rtcore_config.h" | sed 's/^/  /' || true

# ---- 2. compile check -------------------------------------------------------------------------
step "compile-check ffi/shim.c and ffi/shim_test.c with GLINT_EMBREE_MAJOR=4"
for src in ffi/shim.c ffi/shim_test.c; do
    cc "${CFLAGS_STRICT[@]}" -fsyntax-only -DGLINT_EMBREE_MAJOR=4 -I"$ROOT/ffi" \
        -isystem "$INCLUDE" "$ROOT/$src" || die "$src does not compile against Embree $HEADER_VERSION"
    echo "ok: $src"
done

# ---- 3. library -------------------------------------------------------------------------------
step "libembree4 from the wheel raybender $RAYBENDER_VERSION"
WHEELS="$CACHE/wheels"
mkdir -p "$WHEELS"
RAYBENDER_ABI="cp${RAYBENDER_PYTHON//./}"
WHEEL_GLOB="raybender-$RAYBENDER_VERSION-$RAYBENDER_ABI-$RAYBENDER_ABI-*manylinux*x86_64.whl"
# shellcheck disable=SC2086 # WHEEL_GLOB is a glob: expanded unquoted, on purpose
wheel="$(first_file "$WHEELS"/$WHEEL_GLOB)"
if [ -z "$wheel" ]; then
    # The CPython and manylinux tags are pinned, so the same wheel comes down whatever the
    # local python; pip itself refuses a file whose hash is not the pinned one.
    REQ="$CACHE/raybender-$RAYBENDER_VERSION.requirements"
    echo "raybender==$RAYBENDER_VERSION --hash=sha256:$RAYBENDER_SHA256" >"$REQ"
    python3 -m pip download --quiet --no-deps --require-hashes --only-binary=:all: \
        --python-version "$RAYBENDER_PYTHON" --implementation cp --abi "$RAYBENDER_ABI" \
        --platform manylinux_2_28_x86_64 --dest "$WHEELS" -r "$REQ" ||
        die "pip could not download raybender==$RAYBENDER_VERSION ($RAYBENDER_ABI, sha256 $RAYBENDER_SHA256)"
    # shellcheck disable=SC2086
    wheel="$(first_file "$WHEELS"/$WHEEL_GLOB)"
    [ -n "$wheel" ] || die "no raybender $RAYBENDER_VERSION $RAYBENDER_ABI wheel in $WHEELS after the download"
fi
check_sha256 "$wheel" "$RAYBENDER_SHA256" RAYBENDER_SHA256
UNPACKED="$CACHE/raybender-$RAYBENDER_VERSION"
unpack_once "$UNPACKED" "$RAYBENDER_SHA256" python3 -m zipfile -e "$wheel" "$UNPACKED"
LIB_DIR="$UNPACKED/raybender.libs"
# auditwheel renames bundled libraries with a hash (libembree4-92ec4c98.so.4): take the name as
# it is and link it verbatim (EMBREE_LIB), rather than inventing symlinks.
LIB_FILE="$(cd "$LIB_DIR" 2>/dev/null && ls libembree4*.so* | head -n 1 || true)"
[ -n "$LIB_FILE" ] || die "no libembree4*.so* in $LIB_DIR"
echo "library: $LIB_DIR/$LIB_FILE"
# Its libtbb sits beside it and is found through the library's own RPATH ($ORIGIN).
if ldd "$LIB_DIR/$LIB_FILE" | grep -q 'not found'; then
    ldd "$LIB_DIR/$LIB_FILE" >&2
    die "$LIB_FILE has unresolved dependencies"
fi
ldd "$LIB_DIR/$LIB_FILE" | grep -E 'tbb' | sed 's/^[[:space:]]*/  /'

# ---- 4. the shim's C-level contract ---------------------------------------------------------
step "ffi/shim_test.c against Embree 4 (raybender's library, libembree-dev's headers)"
# AddressSanitizer and UBSan watch the shim's own memory use (the library is not instrumented:
# its writes past our structs are measured by the test itself).
SAN=(-g -O1 -fsanitize=address,undefined -fno-sanitize-recover=undefined)
cc "${CFLAGS_STRICT[@]}" "${SAN[@]}" -DGLINT_EMBREE_MAJOR=4 -I"$ROOT/ffi" -isystem "$INCLUDE" \
    "$ROOT/ffi/shim_test.c" -o "$CACHE/shim_test4" \
    -L"$LIB_DIR" -l:"$LIB_FILE" -Wl,-rpath,"$LIB_DIR" -lpthread -lm ||
    die "ffi/shim_test.c does not build against $LIB_FILE"
env -u LD_LIBRARY_PATH "$CACHE/shim_test4" || die "ffi/shim_test.c failed on Embree 4"
if [ -f /usr/include/embree3/rtcore.h ]; then
    step "ffi/shim_test.c against the system Embree 3 (control)"
    cc "${CFLAGS_STRICT[@]}" "${SAN[@]}" -DGLINT_EMBREE_MAJOR=3 -I"$ROOT/ffi" \
        "$ROOT/ffi/shim_test.c" -o "$CACHE/shim_test3" -lembree3 -lpthread -lm ||
        die "ffi/shim_test.c does not build against the system Embree 3"
    "$CACHE/shim_test3" || die "ffi/shim_test.c failed on Embree 3"
fi
if [ "$C_ONLY" = 1 ]; then
    step "summary"
    echo "EMBREE4_CHECK_C_ONLY=1: stopped after step 4. The C-level checks passed on headers $HEADER_VERSION (libembree-dev $EMBREE4_DEB_VERSION) and library $LIB_FILE (raybender $RAYBENDER_VERSION), in $((SECONDS - started)) s; glint itself was NOT built or tested on Embree 4 (run without EMBREE4_CHECK_C_ONLY for that)."
    exit 0
fi

# ---- 5. glint on Embree 4 -----------------------------------------------------------------------
step "glint built against Embree 4 (CARGO_TARGET_DIR=${TARGET_DIR#"$ROOT"/})"
export CARGO_TARGET_DIR="$TARGET_DIR"
export EMBREE_INCLUDE_DIR="$INCLUDE" EMBREE_LIB_DIR="$LIB_DIR" EMBREE_LIB="$LIB_FILE"
export GLINT_EXPECT_EMBREE_MAJOR=4
unset EMBREE_DIR LD_LIBRARY_PATH
# The Embree tests: tests/embree_lifetimes.rs (a binary of its own: it counts process-wide
# handles) and three modules of the accel test binary (tests/accel/).
modules=()
for t in embree_version embree_shim backend_agreement; do
    if [ -f "$ROOT/tests/accel/$t.rs" ]; then
        modules+=("$t::")
    else
        echo "note: tests/accel/$t.rs is not in this branch; skipped"
    fi
done
cd "$ROOT"
cargo test --locked --no-run --lib --test accel --test embree_lifetimes || die "glint does not build against Embree 4"
# The binary really links the wheel's library, found through the rpath build.rs set. (Not
# embree_version's: it calls only the shim's compile-time constants, so the linker drops
# libembree from it; embree_shim builds scenes, in the same accel binary.)
bin="$(cargo test --locked --no-run --test accel --message-format=json 2>/dev/null |
    python3 -c 'import json, sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m.get("executable") and m["target"]["name"] == "accel":
        print(m["executable"])')"
[ -n "$bin" ] || die "could not locate the accel test binary"
resolved="$(ldd "$bin" | grep -E 'libembree' || true)"
echo "accel (embree_shim) links: ${resolved#"${resolved%%[![:space:]]*}"}"
case "$resolved" in
*"$LIB_DIR/$LIB_FILE"*) ;;
*) die "the test binary does not resolve libembree4 to $LIB_DIR/$LIB_FILE" ;;
esac
step "glint's tests on Embree 4"
# One test at a time: embree_lifetimes compares a process-wide handle count, which concurrent
# builds in sibling tests would disturb.
cargo test --locked --no-fail-fast --lib --test embree_lifetimes -- --test-threads=1 "$@" ||
    die "glint's unit tests or embree_lifetimes failed on Embree 4"
cargo test --locked --no-fail-fast --test accel -- "${modules[@]}" --test-threads=1 "$@" ||
    die "glint's Embree tests failed on Embree 4"

step "summary"
echo "Embree 4 path verified: headers $HEADER_VERSION (libembree-dev $EMBREE4_DEB_VERSION), library $LIB_FILE (raybender $RAYBENDER_VERSION), in $((SECONDS - started)) s"
