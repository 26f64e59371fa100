#!/usr/bin/env bash
# Regenerates the measured tables of BENCHMARKS.md (and its opening table, benches/today.py):
# the speed/accuracy trade on every shared volume, with VTK's CPU ray caster measured in the
# same run.
#
#   bash benches/bench.sh [PEER_DIR] [DATA_DIR]
#
# PEER_DIR (default ../shared/tools/peer) must hold the peer harness with its venv (run its
# setup_env.sh once); DATA_DIR (default ../shared/data) the volumes. Two threads for both
# programs, as on the CI machine.
#
# A fifth scene is an MRI nobody tuned for: ch2, the Colin27 T1 of a whole head (181×217×181,
# Debian's mricron-data, BSD-3), with the peer's mri_brain transfer function and an oblique
# camera chosen once (benches/cams/mri_ch2.json). It is fetched with `apt-get download` into
# ${XDG_CACHE_HOME:-~/.cache}/voxcast the first time (never committed).
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=benches/peer.sh
source benches/peer.sh "$@"
run() { # scene file steps [camera [extra arguments]]
    local v=$1 file=$2 steps=$3 camera=${4:-$PEER/cams/$1.json}
    shift 4 2>/dev/null || shift $#
    "$bin" bench --volume "$file" --camera "$camera" \
        --peer "$PEER" --threads "$THREADS" --repeat 3 --peer-rounds 5 --steps "$steps" \
        --report BENCHMARKS.md --section "$v" --plot "docs/bench/${v}_speed_accuracy.png" "$@"
}
run ct_cranium "$DATA/ct_cranium.nrrd" 4,2,1,0.5,0.25,0.125
run mri_mni152 "$DATA/mri_mni152.nii.gz" 2,1,0.5,0.25
run mri_brainsmall "$DATA/mri_brainsmall.nrrd" 2,1,0.5,0.25
run bunny_sdf "$DATA/bunny_sdf.nrrd" 2,1,0.5,0.25
run mri_ch2 "$(ch2)" 2,1,0.5,0.25 benches/cams/mri_ch2.json --tf mri_brain
# The opening table of BENCHMARKS.md, from the sections just written.
python3 benches/today.py
