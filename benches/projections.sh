#!/usr/bin/env bash
# Regenerates BENCHMARKS.md's maximum and minimum intensity projection tables against VTK's
# CPU ray caster (its `mip` and `minip` blends) in the same run: the four shared volumes and
# ch2, the peer's gray transfer functions (as its bench_suite.sh uses them), 512², step ½ voxel.
#
#   bash benches/projections.sh [PEER_DIR] [DATA_DIR]
#
# As benches/bench.sh: PEER_DIR needs the peer's venv (its setup_env.sh), ch2 is fetched once.
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=benches/peer.sh
source benches/peer.sh "$@"
for method in maximum minimum; do
    while read -r v file tf camera; do
        [ -n "$v" ] || continue
        camera=${camera:-$PEER/cams/$v.json}
        "$bin" bench --volume "$file" --camera "$camera" \
            --method "$method" --tf "$PEER/tf/$tf.json" --peer "$PEER" --threads "$THREADS" \
            --repeat 3 --steps 0.5 --reference 0.125 --peer-rounds 3 \
            --report BENCHMARKS.md --section "${method}_$v"
    done <<SCENES
ct_cranium $DATA/ct_cranium.nrrd ct_gray
mri_mni152 $DATA/mri_mni152.nii.gz mri_gray
mri_brainsmall $DATA/mri_brainsmall.nrrd mri_gray
bunny_sdf $DATA/bunny_sdf.nrrd mri_gray
mri_ch2 $(ch2) mri_gray benches/cams/mri_ch2.json
SCENES
done
