#!/usr/bin/env bash
# Regenerates BENCHMARKS.md's ray-inspection section: the sandbox's frame time at 640×360 with
# the virtual camera's rays and every sample sphere shown (animation skipped), for 4×4 to
# 32×32 rays, resting and orbiting with adaptive quality.
#
#   bash benches/rays.sh [VOLUME]        (default builtin:bunny)
#
# Needs a display: without $DISPLAY it starts Xvfb on :78.
set -euo pipefail
cd "$(dirname "$0")/.."
VOLUME=${1:-builtin:bunny}
FRAMES=${FRAMES:-8}
STEP=${STEP:-1}
source benches/common.sh
frame_ms() {
    "$bin" --volume "$VOLUME" --step "$STEP" --size 640x360 --sample-budget 1000000 "$@" \
        2>/dev/null | sed -n 's/.*median \([0-9.]*\) ms.*/\1/p'
}
table=$(mktemp)
{
    echo "<!-- bench:rays -->"
    echo "$VOLUME at step $STEP voxel, 640×360 window, $(nproc) cores, lavapipe; every sample a sphere"
    echo "(animation skipped), medians over $FRAMES frames (\`voxcast --rays N --measure-frames\`)."
    echo
    echo "| rays | resting (ms) | orbiting, adaptive (ms) | orbiting fps |"
    echo "| --- | ---: | ---: | ---: |"
    for n in 1 4 8 16 32; do
        rest=$(frame_ms --rays "$n" --measure-frames "$FRAMES")
        orbit=$(frame_ms --rays "$n" --measure-frames "$FRAMES" --auto-orbit 2)
        fps=$(awk -v ms="$orbit" 'BEGIN { if (ms > 0) printf "%.1f", 1000 / ms; else print "–" }')
        echo "| ${n}×${n} | $rest | $orbit | $fps |"
    done
    echo "<!-- /bench:rays -->"
} >"$table"
cat "$table"
write_section rays "Ray inspection" "$table"
