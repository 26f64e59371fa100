#!/usr/bin/env bash
# Issue 41's GPU figures in one run, for a machine with a real GPU: the GPU preview at
# 1920×1080 (SIZE) on the five peer scenes at ½ voxel, resting — drawn offscreen at full quality
# with no window (`voxcast --screenshot --time-frames`) — and, where there is a display,
# orbiting in the window (`--measure-frames --auto-orbit 2 --preview-backend gpu`); the CT
# upsampled to 512³ (nearest neighbour, written once to $TMPDIR); and VTK's GPU mapper on the
# same GPU, views and step (the peer harness, offscreen) where the peer has its venv. Prints a
# markdown table with the adapter and CPU named; with --write it replaces BENCHMARKS.md's
# "gpu" section.
#
#   bash benches/gpu.sh [PEER_DIR] [DATA_DIR] [--write]
#   SIZE=640x360 FRAMES=5 bash benches/gpu.sh      (a quick try, e.g. on lavapipe)
#
# The peer's transfer functions are its own files for the scene (ct_skin_bone, mri_brain,
# brainsmall_volpack, bunny), which are the presets Voxcast's bench compares against; ch2 is
# fetched as benches/ch2.sh does and left out where it cannot be.
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
W=${SIZE%x*}
H=${SIZE#*x}
cargo build --release --quiet
bin=${CARGO_TARGET_DIR:-./target}/release/voxcast
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(mktemp -d)}
# shellcheck source=benches/ch2.sh
source benches/ch2.sh
tmp=${TMPDIR:-/tmp}/voxcast-gpu
mkdir -p "$tmp"

# The CT at 512³: each voxel repeated (x and y twice, z by nearest slice), spacing scaled so
# the head keeps its size. Plain python3, no numpy; about 256 MiB, written once.
ct512="$tmp/ct_cranium_512.nrrd"
if [ ! -f "$ct512" ] && [ -f "$DATA/ct_cranium.nrrd" ]; then
    python3 - "$bin" "$DATA/ct_cranium.nrrd" "$ct512" <<'PY'
import gzip, subprocess, sys
binary, src, dst = sys.argv[1:]
info = subprocess.run([binary, "info", src], capture_output=True, text=True).stdout
dims = [int(x) for x in info.split("dims:")[1].split("=")[0].split("×")]
spacing = [float(x) for x in info.split("spacing:")[1].splitlines()[0].split("×")]
raw = open(src, "rb").read()
header_end = raw.index(b"\n\n") + 2
head = raw[:header_end].decode()
assert "int16" in head.replace("short", "int16"), head
data = raw[header_end:]
if "encoding: gzip" in head or "encoding: gz" in head:
    data = gzip.decompress(data)
nx, ny, nz = dims
row = 2 * nx
doubled = {}
def row_of(z, y):
    key = (z, y)
    if key not in doubled:
        r = data[(z * ny + y) * row:(z * ny + y + 1) * row]
        doubled[key] = b"".join(r[i:i + 2] * 2 for i in range(0, row, 2))
    return doubled[key]
n = 512
with open(dst, "wb") as out:
    out.write((
        "NRRD0004\ntype: int16\ndimension: 3\nsizes: %d %d %d\nendian: little\n"
        "encoding: raw\nspacings: %g %g %g\n\n"
        % (n, n, n, spacing[0] * nx / n, spacing[1] * ny / n, spacing[2] * nz / n)
    ).encode())
    for z in range(n):
        sz = min(nz - 1, z * nz // n)
        out.write(b"".join(row_of(sz, y * ny // n) for y in range(n)))
PY
fi

adapter=""
cpu_model=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
# name file camera peer-tf [extra voxcast arguments]
scenes() {
    echo "ct_cranium $DATA/ct_cranium.nrrd $PEER/cams/ct_cranium.json ct_skin_bone"
    echo "mri_mni152 $DATA/mri_mni152.nii.gz $PEER/cams/mri_mni152.json mri_brain"
    echo "mri_brainsmall $DATA/mri_brainsmall.nrrd $PEER/cams/mri_brainsmall.json brainsmall_volpack"
    echo "bunny_sdf $DATA/bunny_sdf.nrrd $PEER/cams/bunny_sdf.json bunny"
    if ch2_file=$(ch2 2>/dev/null); then
        echo "mri_ch2 $ch2_file benches/cams/mri_ch2.json mri_brain --tf mri_brain"
    fi
    if [ -f "$ct512" ]; then
        echo "ct_cranium_512 $ct512 $PEER/cams/ct_cranium.json ct_skin_bone --tf ct_skin_bone"
    fi
}
# The smallest spacing of a volume, from `voxcast info`.
voxel() {
    "$bin" info "$1" | sed -n 's/^spacing: *//p' | tr -d ' ' | tr '×' '\n' | sort -g | head -1
}
fps() { awk -v ms="$1" 'BEGIN { if (ms > 0) printf "%.0f", 1000 / ms; else print "–" }'; }

table=$(mktemp)
{
    echo "<!-- bench:gpu -->"
    echo "| scene | resting frame (ms) | fps | orbiting frame (ms) | VTK GPU mapper (ms) | VTK / Voxcast |"
    echo "| --- | ---: | ---: | ---: | ---: | ---: |"
    while read -r name file camera tf extra; do
        # shellcheck disable=SC2086
        common=(--volume "$file" --camera "$camera" --step 0.5 $extra)
        log="$tmp/$name.log"
        rest=$("$bin" "${common[@]}" --size "$SIZE" --screenshot "$tmp/$name.png" \
            --time-frames "$FRAMES" 2>"$log" |
            sed -n 's/^preview frame: median \([0-9.]*\) ms.*/\1/p')
        [ -z "$adapter" ] && adapter=$(sed -n 's/.*AdapterInfo { name: "\([^"]*\)".*/\1/p' "$log" | head -1)
        orbit="–"
        if [ -n "${DISPLAY:-}" ]; then
            orbit=$("$bin" "${common[@]}" --size "$SIZE" --no-rays --preview-backend gpu \
                --measure-frames "$FRAMES" --auto-orbit 2 2>>"$log" |
                sed -n 's/.*median \([0-9.]*\) ms.*/\1/p')
        fi
        vtk="–"
        if [ -x "$PEER/venv/bin/python" ]; then
            sd=$(awk -v v="$(voxel "$file")" 'BEGIN { print 0.5 * v }')
            "$PEER/venv/bin/python" "$PEER/vtk_render.py" --volume "$file" --tf "$PEER/tf/$tf.json" \
                --camera "$camera" --mapper gpu --blend composite --sample-distance "$sd" \
                --size "$W" "$H" --frames "$FRAMES" --out "$tmp/${name}_vtk.png" \
                --json-out "$tmp/${name}_vtk.json" >>"$log" 2>&1 &&
                vtk=$(python3 -c "import json,sys; print('%.1f' % (1000 * json.load(open(sys.argv[1]))['median_s']))" "$tmp/${name}_vtk.json") || true
        fi
        ratio=$(awk -v a="$vtk" -v b="${rest:-0}" 'BEGIN { if (a + 0 > 0 && b > 0) printf "%.1f×", a / b; else print "–" }')
        echo "| $name | ${rest:-failed} | $(fps "${rest:-0}") | ${orbit:-failed} | $vtk | $ratio |"
    done < <(scenes)
    echo
    echo "$SIZE, step ½ voxel, medians of $FRAMES frames; adapter ${adapter:-unknown}; CPU $cpu_model ($(nproc) cores); $(date -u +%Y-%m-%d)."
    echo "Resting: the preview drawn offscreen at the full size and full quality, no window. Orbiting:"
    echo "the window at that size, its panels beside the volume, adaptive quality on (its default),"
    echo "2° a frame (– without a display). VTK: vtk_render.py --mapper gpu, medians of its frames."
    echo "<!-- /bench:gpu -->"
} >"$table"
cat "$table"
if [ "$WRITE" = 1 ]; then
    source benches/common.sh
    write_section gpu "The preview on a real GPU (benches/gpu.sh)" "$table"
fi
