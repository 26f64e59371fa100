#!/usr/bin/env bash
# Issue 41's GPU figures, for a machine with a real GPU: the GPU preview at 1920×1080 (SIZE) on
# the five peer scenes at ½ voxel and the CT upsampled to 512³ — resting and orbiting, drawn
# offscreen at full quality with no window (`voxcast --screenshot --time-frames`, each frame
# waiting for the GPU to finish it), and, where there is a display, orbiting in the window
# (`--measure-frames --auto-orbit 2`) — and VTK's GPU mapper on the same GPU, views and step
# (the peer harness, offscreen through EGL). Prints a markdown table with the adapter, the
# OpenGL renderer and the CPU named; with --write it replaces BENCHMARKS.md's "gpu" section.
#
#   bash benches/gpu.sh [PEER_DIR] [DATA_DIR] [--write]
#   SIZE=640x360 FRAMES=5 bash benches/gpu.sh      (a quick try, e.g. on lavapipe)
#
# Environment:
#   PARTS    what to measure: "voxcast vtk" (default); "" only prints the table of RESULTS
#   RESULTS  the folder of one file per figure (default $TMPDIR/voxcast-gpu/results), so parts
#            measured in separate runs (a machine where both do not fit at once) make one table
#   VOXCAST_BIN  a built voxcast (default: cargo build --release)
#   VTK_PYTHON   a python that imports vtk (default: PEER_DIR/venv/bin/python); each volume is
#                given to it as a raw file and sidecar written by benches/peer_raw.py
#   CH2      the Colin27 ch2.nii.gz (default: DATA_DIR/ch2.nii.gz, else fetched as ch2.sh does)
#
# Both renderers get the same transfer function: the one `voxcast bench --peer` gives VTK (the
# peer's own file for the volume's preset where it has one, else Voxcast's preset written in the
# peer's format: `--write-peer-tf`, kept in RESULTS).
set -euo pipefail
cd "$(dirname "$0")/.."
WRITE=0
ARGS=()
for a in "$@"; do
    if [ "$a" = --write ]; then WRITE=1; else ARGS+=("$a"); fi
done
PEER=$(realpath "${ARGS[0]:-../shared/tools/peer}")
DATA=$(realpath "${ARGS[1]:-../shared/data}")
SIZE=${SIZE:-1920x1080}
FRAMES=${FRAMES:-30}
PARTS=${PARTS-voxcast vtk}
W=${SIZE%x*}
H=${SIZE#*x}
tmp=${TMPDIR:-/tmp}/voxcast-gpu
RESULTS=${RESULTS:-$tmp/results}
mkdir -p "$tmp" "$RESULTS"
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(mktemp -d)}
part() { [[ " $PARTS " == *" $1 "* ]]; }
# shellcheck source=benches/tables.sh
source benches/tables.sh

# The CT at 512³ (nearest neighbour, spacing scaled; about 256 MiB, written once).
ct512="$tmp/ct_cranium_512.nrrd"
if [ -n "$PARTS" ] && [ ! -f "$ct512" ] && [ -f "$DATA/ct_cranium.nrrd" ]; then
    python3 benches/upsample.py "$DATA/ct_cranium.nrrd" "$ct512" 512
fi
if [ -z "${CH2:-}" ]; then
    if [ -f "$DATA/ch2.nii.gz" ]; then
        CH2=$DATA/ch2.nii.gz
    else
        # shellcheck source=benches/ch2.sh
        source benches/ch2.sh
        CH2=$(ch2 2>/dev/null) || CH2=""
    fi
fi

# name file camera peer-tf (where Voxcast did not write one) [extra voxcast arguments]
scenes() {
    echo "ct_cranium $DATA/ct_cranium.nrrd $PEER/cams/ct_cranium.json ct_skin_bone"
    echo "mri_mni152 $DATA/mri_mni152.nii.gz $PEER/cams/mri_mni152.json mri_brain"
    echo "mri_brainsmall $DATA/mri_brainsmall.nrrd $PEER/cams/mri_brainsmall.json brainsmall"
    echo "bunny_sdf $DATA/bunny_sdf.nrrd $PEER/cams/bunny_sdf.json bunny"
    if [ -n "$CH2" ] && [ -f "$CH2" ]; then
        echo "mri_ch2 $CH2 benches/cams/mri_ch2.json mri_brain --tf mri_brain"
    fi
    if [ -f "$ct512" ] || [ -f "$RESULTS/ct_cranium_512.rest" ]; then
        echo "ct_cranium_512 $ct512 $PEER/cams/ct_cranium.json ct_skin_bone --tf ct_skin_bone"
    fi
}
# label and arguments (step, size and the one thing changed) of a probe of the 512³ CT's frame
probes() {
    echo "step_1_voxel --step 1 --size $SIZE"
    echo "step_2_voxels --step 2 --size $SIZE"
    echo "unshaded --step 0.5 --size $SIZE --shading off"
    echo "maximum --step 0.5 --size $SIZE --method maximum"
    echo "quarter_pixels --step 0.5 --size $((W / 2))x$((H / 2))"
}
# The median frame in ms from a `--time-frames` line.
median() { sed -n 's/^preview frame: median \([0-9.]*\) ms.*/\1/p'; }

if part voxcast; then
    if [ -n "${VOXCAST_BIN:-}" ]; then
        bin=$VOXCAST_BIN
    else
        cargo build --release --quiet
        bin=${CARGO_TARGET_DIR:-./target}/release/voxcast
    fi
    lscpu | sed -n 's/^Model name: *//p' | head -1 >"$RESULTS/cpu"
    nproc >"$RESULTS/cores"
    while read -r name file camera _tf extra; do
        # shellcheck disable=SC2086
        common=(--volume "$file" --camera "$camera" --step 0.5 $extra --size "$SIZE")
        log="$tmp/$name.log"
        "$bin" "${common[@]}" --screenshot "$tmp/$name.png" --time-frames "$FRAMES" \
            2>"$log" | median >"$RESULTS/$name.rest" || true
        "$bin" "${common[@]}" --screenshot "$tmp/${name}_orbit.png" --time-frames "$FRAMES" \
            --auto-orbit 2 2>>"$log" | median >"$RESULTS/$name.orbit" || true
        sed -n 's/.*AdapterInfo { name: "\([^"]*\)".*/\1/p' "$log" | head -1 >"$RESULTS/adapter"
        # shellcheck disable=SC2086
        "$bin" bench --volume "$file" $extra --peer "$PEER" --write-peer-tf "$RESULTS/$name.tf.json"
        if [ -n "${DISPLAY:-}" ]; then
            "$bin" "${common[@]}" --no-rays --preview-backend gpu --measure-frames "$FRAMES" \
                --auto-orbit 2 2>>"$log" | sed -n 's/.*median \([0-9.]*\) ms.*/\1/p' \
                >"$RESULTS/$name.window" || true
        fi
    done < <(scenes)
    # What bounds a frame of the 512³ CT: one thing changed at a time from the resting row.
    if [ -f "$ct512" ]; then
        while read -r label args; do
            # shellcheck disable=SC2086
            "$bin" --volume "$ct512" --camera "$PEER/cams/ct_cranium.json" --tf ct_skin_bone \
                $args --screenshot "$tmp/probe_$label.png" \
                --time-frames "$FRAMES" 2>>"$tmp/probes.log" | median >"$RESULTS/probe_$label" || true
        done < <(probes)
    fi
fi

if part vtk; then
    py=${VTK_PYTHON:-$PEER/venv/bin/python}
    while read -r name file camera tf _extra; do
        log="$tmp/${name}_vtk.log"
        sidecar="$tmp/${name}_vtk.json"
        [ -f "$sidecar" ] || python3 benches/peer_raw.py "$file" "$sidecar"
        sd=$(python3 -c "import json,sys; print(0.5 * min(json.load(open(sys.argv[1]))['spacing']))" "$sidecar")
        tf_file=$RESULTS/$name.tf.json
        [ -f "$tf_file" ] || tf_file=$PEER/tf/$tf.json
        if "$py" "$PEER/vtk_render.py" --volume "$sidecar" --tf "$tf_file" \
            --camera "$camera" --mapper gpu --blend composite --sample-distance "$sd" \
            --size "$W" "$H" --frames "$FRAMES" --out "$tmp/${name}_vtk.png" \
            --json-out "$tmp/${name}_vtk.json.out" >"$log" 2>&1; then
            python3 -c "import json,sys; r=json.load(open(sys.argv[1])); print('%.1f' % (1000 * r['median_s']))" \
                "$tmp/${name}_vtk.json.out" >"$RESULTS/$name.vtk"
            sed -n "s/.* gl='\([^']*\)'.*/\1/p" "$log" | head -1 >"$RESULTS/gl"
        else
            echo "VTK failed on $name: $(tail -3 "$log")" >&2
        fi
    done < <(scenes)
fi

# One figure from RESULTS, or – where it was not measured.
figure() { local v; v=$(cat "$RESULTS/$1" 2>/dev/null || true); echo "${v:-–}"; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (a + 0 > 0 && b + 0 > 0) printf "%.1f×", a / b; else print "–" }'; }
table=$(mktemp)
{
    echo "<!-- bench:gpu -->"
    echo "| scene | resting frame (ms) | fps | orbiting frame (ms) | fps | window orbiting (ms) | VTK GPU mapper (ms) | VTK / Voxcast resting |"
    echo "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
    while read -r name _rest; do
        rest=$(figure "$name.rest")
        orbit=$(figure "$name.orbit")
        vtk=$(figure "$name.vtk")
        echo "| $name | $rest | $(fps "$rest") | $orbit | $(fps "$orbit") | $(figure "$name.window") | $vtk | $(ratio "$vtk" "$rest") |"
    done < <(scenes)
    echo
    echo "$SIZE, step ½ voxel, composite, one transfer function for both, medians of $FRAMES frames; Vulkan adapter"
    echo "$(figure adapter), OpenGL renderer (VTK) $(figure gl); CPU $(figure cpu) ($(figure cores)"
    echo "cores); $(date -u +%Y-%m-%d). Resting and orbiting: the preview drawn offscreen at the"
    echo "full size and quality, no window, each frame waiting for the GPU to finish it; orbiting"
    echo "turns the view 2° a frame. Window orbiting: the sandbox's window, its panels beside the"
    echo "volume, adaptive quality on (– without a display). VTK: vtk_render.py --mapper gpu"
    echo "(vtkOpenGLGPUVolumeRayCastMapper), each frame rendered and waited for."
    echo
    echo "What bounds the 512³ CT's resting frame (one thing changed at a time):"
    echo
    echo "| change | frame (ms) | speed against ½ voxel, shaded, full size |"
    echo "| --- | ---: | ---: |"
    base=$(figure ct_cranium_512.rest)
    while read -r label _args; do
        t=$(figure "probe_$label")
        echo "| ${label//_/ } | $t | $(ratio "$base" "$t") |"
    done < <(probes)
    echo "<!-- /bench:gpu -->"
} >"$table"
cat "$table"
if [ "$WRITE" = 1 ]; then
    write_section gpu "The preview on a real GPU (benches/gpu.sh)" "$table"
fi
