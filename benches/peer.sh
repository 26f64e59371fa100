# Sourced (from the repository root, with the script's arguments) by the benchmarks that meet
# VTK: benches/bench.sh, lanes.sh and projections.sh. Sets PEER and DATA from [PEER_DIR]
# [DATA_DIR] (defaults ../shared/tools/peer and ../shared/data), THREADS (default 2, as on
# the CI machine), ch2() (benches/ch2.sh), and bin, the release binary, built. Stops the script
# where the peer has no venv: every table would be rewritten with "VTK peer: not measured".

PEER=$(realpath "${1:-../shared/tools/peer}")
DATA=$(realpath "${2:-../shared/data}")
THREADS=${THREADS:-2}
if [ ! -x "$PEER/venv/bin/python" ]; then
    echo "no $PEER/venv/bin/python: run $PEER/setup_env.sh first (BENCHMARKS.md is left as it is)" >&2
    exit 1
fi
# shellcheck source=benches/ch2.sh
source benches/ch2.sh
cargo build --release --quiet
bin=${CARGO_TARGET_DIR:-./target}/release/voxcast
