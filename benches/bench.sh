#!/usr/bin/env bash
# Regenerates the measured tables of BENCHMARKS.md: the speed/accuracy trade on every shared
# volume, with VTK's CPU ray caster measured in the same run.
#
#   bash benches/bench.sh [PEER_DIR] [DATA_DIR]
#
# PEER_DIR (default ../shared/tools/peer) must hold the peer harness with its venv (run its
# setup_env.sh once); DATA_DIR (default ../shared/data) the volumes. Two threads for both
# programs, as on the CI machine.
set -euo pipefail
cd "$(dirname "$0")/.."
PEER=$(realpath "${1:-../shared/tools/peer}")
DATA=$(realpath "${2:-../shared/data}")
THREADS=${THREADS:-2}
cargo build --release --quiet
run() { # volume preset steps
    local v=$1 file=$2 steps=$3
    ${CARGO_TARGET_DIR:-./target}/release/voxcast bench --volume "$DATA/$file" --camera "$PEER/cams/$v.json" \
        --peer "$PEER" --threads "$THREADS" --repeat 3 --steps "$steps" \
        --report BENCHMARKS.md --section "$v" --plot "docs/bench/${v}_speed_accuracy.png"
}
run ct_cranium ct_cranium.nrrd 4,2,1,0.5,0.25,0.125
run mri_mni152 mri_mni152.nii.gz 2,1,0.5,0.25
run mri_brainsmall mri_brainsmall.nrrd 2,1,0.5,0.25
run bunny_sdf bunny_sdf.nrrd 2,1,0.5,0.25
