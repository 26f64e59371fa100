# Shared by benches/frames.sh and benches/rays.sh (sourced from the repository root): builds
# the release binary, makes sure there is a display (Xvfb on :78 when $DISPLAY is unset), and
# writes a measured table into BENCHMARKS.md between its markers (benches/tables.sh).

cargo build --release --quiet
if [ -z "${DISPLAY:-}" ]; then
    Xvfb :78 -screen 0 1400x900x24 >/dev/null 2>&1 &
    XVFB=$!
    trap 'kill $XVFB 2>/dev/null || true' EXIT
    export DISPLAY=:78
    sleep 2
fi
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(mktemp -d)}
bin=${CARGO_TARGET_DIR:-./target}/release/voxcast

# shellcheck source=benches/tables.sh
source benches/tables.sh
