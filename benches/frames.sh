#!/usr/bin/env bash
# Regenerates BENCHMARKS.md's preview section: the sandbox's frame time per method at 640×360
# and 1280×720 — resting at full quality, orbiting at full quality, orbiting with adaptive
# quality — next to the exact CPU render of the same view with the same settings. The virtual
# camera's rays are hidden (--no-rays): benches/rays.sh measures what they add.
#
#   bash benches/frames.sh [VOLUME]        (default builtin:bunny)
#
# Needs a display: without $DISPLAY it starts Xvfb on :78. On a machine without a GPU the
# preview runs on Mesa's lavapipe, on the same cores as the CPU render.
set -euo pipefail
cd "$(dirname "$0")/.."
VOLUME=${1:-builtin:bunny}
FRAMES=${FRAMES:-12}
source benches/common.sh

# Median frame time in ms of one sandbox run.
frame_ms() {
    "$bin" --volume "$VOLUME" --no-rays "$@" 2>/tmp/voxcast_frames.log | sed -n 's/.*median \([0-9.]*\) ms.*/\1/p'
}
# Median CPU render time in ms.
render_ms() {
    "$bin" render --volume "$VOLUME" "$@" --repeat 5 --out /tmp/voxcast_frames.png 2>/dev/null |
        sed -n 's/.* in \([0-9.]*\) s (median.*/\1/p' | awk '{ printf "%.0f", $1 * 1000 }'
}
fps() { awk -v ms="$1" 'BEGIN { if (ms > 0) printf "%.1f", 1000 / ms; else print "–" }'; }

frame_ms --size 64x64 --measure-frames 1 >/dev/null
adapter=$(sed -n 's/.*AdapterInfo { name: "\([^"]*\)".*/\1/p' /tmp/voxcast_frames.log | head -1)
table=$(mktemp)
{
    echo "<!-- bench:preview -->"
    echo "$VOLUME, default view, step ½ voxel, $(nproc) cores, preview on ${adapter:-an unknown adapter}."
    echo "Frame times are medians over $FRAMES frames after a warm-up (\`voxcast --no-rays --measure-frames\`);"
    echo "the CPU render is \`voxcast render\` of the same view, median of 5."
    echo
    echo "| size | method | resting, full (ms) | orbiting, full (ms) | orbiting, adaptive (ms) | adaptive fps | CPU render (ms) |"
    echo "| --- | --- | ---: | ---: | ---: | ---: | ---: |"
    for size in 640x360 1280x720; do
        for method in accumulate first average maximum minimum; do
            common=(--size "$size" --method "$method")
            rest=$(frame_ms "${common[@]}" --measure-frames "$FRAMES")
            full=$(frame_ms "${common[@]}" --measure-frames "$FRAMES" --auto-orbit 2 --no-adaptive)
            adaptive=$(frame_ms "${common[@]}" --measure-frames "$FRAMES" --auto-orbit 2)
            cpu=$(render_ms "${common[@]}")
            echo "| ${size/x/×} | $method | $rest | $full | $adaptive | $(fps "$adaptive") | $cpu |"
        done
    done
    echo "<!-- /bench:preview -->"
} >"$table"
cat "$table"
write_section preview "Sandbox preview" "$table"
