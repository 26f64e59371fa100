#!/usr/bin/env bash
# Issue 41's cameras nobody tuned for: each peer scene seen from two more cameras — one oblique
# (from below, left and behind, the box just framed) and one close-up from inside the volume's
# box (three quarters of the way from the centre to a corner, looking back across it, 60°) —
# written once by one rule for every scene (benches/cams/*_oblique.json, *_inside.json), with
# VTK's fixed-point mapper in the same run: composite shaded at ½ voxel, 512², 2 threads,
# medians of 5 alternating rounds. Replaces BENCHMARKS.md's "cameras" section.
#
#   bash benches/cameras.sh [PEER_DIR] [DATA_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=benches/peer.sh
source benches/peer.sh "$@"
# shellcheck source=benches/tables.sh
source benches/tables.sh
table=$(mktemp)
cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
family=$(lscpu | sed -n 's/^CPU family: *//p' | head -1)
model=$(lscpu | sed -n 's/^Model: *//p' | head -1)
{
    echo "<!-- bench:cameras -->"
    echo "| scene | camera | VTK fixed-point (s) | Voxcast (s) | VTK / Voxcast | over the rounds | image RMSE vs VTK |"
    echo "| --- | --- | ---: | ---: | ---: | ---: | ---: |"
    while read -r scene file extra; do
        for camera in oblique inside; do
            # shellcheck disable=SC2086
            out=$("$bin" bench --volume "$file" --camera "benches/cams/${scene}_$camera.json" \
                --peer "$PEER" --threads "$THREADS" --repeat 1 --peer-rounds 5 --steps 0.5 \
                --reference 0.25 $extra 2>/dev/null)
            echo "$out" | python3 benches/peer_line.py "$scene" "$camera"
        done
    done <<SCENES
ct_cranium $DATA/ct_cranium.nrrd
mri_mni152 $DATA/mri_mni152.nii.gz
mri_brainsmall $DATA/mri_brainsmall.nrrd
bunny_sdf $DATA/bunny_sdf.nrrd
mri_ch2 $(ch2) --tf mri_brain
SCENES
    echo
    echo "$(date -u +%Y-%m-%d), $cpu (family $family, model $model), $THREADS threads for both, 512×512, step ½ voxel, composite, shaded; medians of 5 alternating rounds (\`bash benches/cameras.sh\`)."
    echo "<!-- /bench:cameras -->"
} >"$table"
cat "$table"
write_section cameras "Cameras nobody tuned for (benches/cameras.sh)" "$table"
