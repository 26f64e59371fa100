#!/usr/bin/env bash
# Builds Voxcast's web page into a static folder (default: dist/) that any static file server
# can host: index.html, the loader voxcast.js, and the sandbox twice, webgl2/ and webgpu/ (each
# its .wasm and the JS glue wasm-bindgen writes for it); the page loads the one the browser can
# run. Usage: bash web/build.sh [OUT] [webgl2|webgpu …]
#
# Needs cargo with rustup (the wasm32-unknown-unknown target is added here) and installs the
# wasm-bindgen CLI of the version Cargo.lock holds (the glue and the module must match) into
# $VOXCAST_TOOLS (default ~/.cache/voxcast-tools), once.
set -euo pipefail
cd "$(dirname "$0")/.."

OUT=${1:-dist}
shift || true
GRAPHICS=("$@")
if [ ${#GRAPHICS[@]} -eq 0 ]; then GRAPHICS=(webgl2 webgpu); fi

TARGET=wasm32-unknown-unknown
if command -v rustup > /dev/null && ! rustup target list --installed | grep -qx "$TARGET"; then
    rustup target add "$TARGET"
fi

VERSION=$(grep -A1 '^name = "wasm-bindgen"$' Cargo.lock | sed -n 's/^version = "\(.*\)"$/\1/p')
TOOLS=${VOXCAST_TOOLS:-$HOME/.cache/voxcast-tools}
BINDGEN="$TOOLS/bin/wasm-bindgen"
if ! "$BINDGEN" --version 2> /dev/null | grep -qF "$VERSION"; then
    echo "== installing wasm-bindgen-cli $VERSION into $TOOLS"
    # Not through a workspace wrapper (.ci/run lints our crates with one): it is not ours.
    env -u RUSTC_WORKSPACE_WRAPPER -u CLIPPY_ARGS \
        cargo install wasm-bindgen-cli --version "=$VERSION" --root "$TOOLS" --force
fi

# The module's panic and log messages name source files: by their place in a crate, not by the
# build machine's folders (.cargo/config.toml adds WebAssembly's SIMD to these flags). Where two
# prefixes match, rustc applies the one given last: each registry's after the home folder's.
# (The crates fetched first: each build of a run then has the same flags, and reuses the last.)
cargo fetch --locked --target "$TARGET" > /dev/null
shopt -s nullglob
REMAP="--remap-path-prefix=$HOME="
for registry in "${CARGO_HOME:-$HOME/.cargo}"/registry/src/*/; do
    REMAP="$REMAP --remap-path-prefix=${registry%/}="
done
shopt -u nullglob # (a missing file below stays an error)
export CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_RUSTFLAGS="$REMAP --remap-path-prefix=$PWD=voxcast"

TARGET_DIR=${CARGO_TARGET_DIR:-target}
# The `web` profile (Cargo.toml): small and fast, its link some 6 minutes a build on 2 cores;
# VOXCAST_WEB_PROFILE=release for a quicker, larger build (CI's).
PROFILE=${VOXCAST_WEB_PROFILE:-web}
mkdir -p "$OUT"
for gpu in "${GRAPHICS[@]}"; do
    echo "== building the page for $gpu"
    start=$(date +%s)
    cargo build --locked --profile "$PROFILE" --target "$TARGET" --features "$gpu" --bin voxcast
    rm -rf "${OUT:?}/$gpu"
    "$BINDGEN" --target web --no-typescript --remove-name-section --remove-producers-section \
        --out-dir "$OUT/$gpu" "$TARGET_DIR/$TARGET/$PROFILE/voxcast.wasm"
    echo "== $gpu built in $(($(date +%s) - start)) s"
done
cp web/index.html web/voxcast.js "$OUT/"
# The real embedded datasets, which the page's module leaves out (the loader fetches them).
mkdir -p "$OUT/volumes"
cp assets/volumes/*.nrrd assets/volumes/NOTICE.md "$OUT/volumes/"
echo "== the page is in $OUT/ ($(du -sh "$OUT" | cut -f1)): serve it with"
echo "   python3 -m http.server 8000 --bind 127.0.0.1 --directory $OUT"
