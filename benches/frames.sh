#!/usr/bin/env bash
# Regenerates BENCHMARKS.md's preview section: how fast the window answers, per method, at
# 640×360 and 1280×720 — resting and orbiting — with the CPU live view (the core on background
# threads) and, for Accumulate, the GPU preview on the same adapter; beside them the exact CPU
# render of the same view. The virtual camera's rays are hidden (--no-rays): benches/rays.sh
# measures what they add.
#
#   bash benches/frames.sh [VOLUME]        (default builtin:bunny)
#
# Needs a display: without $DISPLAY it starts Xvfb on :78. On a machine without a GPU the
# preview runs on Mesa's lavapipe, on the same cores as the CPU render.
set -euo pipefail
cd "$(dirname "$0")/.."
VOLUME=${1:-builtin:bunny}
FRAMES=${FRAMES:-30}
source benches/common.sh

# One sandbox run: its printed line.
run() {
    "$bin" --volume "$VOLUME" --no-rays "$@" 2>/tmp/voxcast_frames.log | grep "frame time" || true
}
field() { sed -n "s/.*$1.*/\\1/p"; }
# Median CPU render time in ms.
render_ms() {
    "$bin" render --volume "$VOLUME" "$@" --repeat 5 --out /tmp/voxcast_frames.png 2>/dev/null |
        sed -n 's/.* in \([0-9.]*\) s (median.*/\1/p' | awk '{ printf "%.0f", $1 * 1000 }'
}

run --size 64x64 --measure-frames 1 >/dev/null
adapter=$(sed -n 's/.*AdapterInfo { name: "\([^"]*\)".*/\1/p' /tmp/voxcast_frames.log | head -1)
cpu_model=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
table=$(mktemp)
{
    echo "<!-- bench:preview -->"
    echo "$VOLUME, default view, step ½ voxel, $(nproc) cores ($cpu_model), adapter ${adapter:-unknown}."
    echo "Window frame times are medians over $FRAMES frames after a warm-up (\`voxcast --no-rays"
    echo "--measure-frames $FRAMES [--auto-orbit 2]\`); orbiting moves the camera 2° every frame."
    echo "With the CPU live view, *images/s* is how many new volume images arrived a second while"
    echo "orbiting (at the size shown), and *exact after stop* how long after the camera stopped the"
    echo "exact render was on screen; with the GPU preview, how long until the resting view was on screen"
    echo "at full quality (drawn a strip a frame when a whole frame would take longer than a frame's"
    echo "share of 50 ms). The CPU render is \`voxcast render\` of the same view, median of 5."
    echo
    echo "| size | method | drawn by | resting frame (ms) | orbiting frame (ms) | orbiting fps | images/s while orbiting | full quality after stop (ms) | CPU render (ms) |"
    echo "| --- | --- | --- | ---: | ---: | ---: | --- | ---: | ---: |"
    for size in 640x360 1280x720; do
        for method in accumulate first average maximum minimum; do
            for backend in cpu gpu; do
                if [ "$backend" = gpu ] && [ "$method" != accumulate ]; then continue; fi
                common=(--size "$size" --method "$method" --preview-backend "$backend")
                rest=$(run "${common[@]}" --measure-frames "$FRAMES" | field 'median \([0-9.]*\) ms')
                orbit_line=$(run "${common[@]}" --measure-frames "$FRAMES" --auto-orbit 2)
                orbit=$(echo "$orbit_line" | field 'median \([0-9.]*\) ms')
                images="–"
                exact="–"
                if [ "$backend" = cpu ]; then
                    images=$(echo "$orbit_line" | field 'live view: \([0-9.]* images\/s at [0-9]*×[0-9]*\)' | sed 's/ images\/s at / at /')
                    exact=$(echo "$orbit_line" | field 'exact render \([0-9]*\) ms after')
                else
                    exact=$(echo "$orbit_line" | field 'full quality \([0-9]*\) ms after')
                    strips=$(echo "$orbit_line" | field 'drawn in \([0-9]*\) strips')
                    [ -n "$strips" ] && exact="$exact ($strips strips)"
                fi
                cpu=$(render_ms --size "$size" --method "$method")
                name=$([ "$backend" = cpu ] && echo "CPU live view" || echo "GPU preview")
                echo "| ${size/x/×} | $method | $name | $rest | $orbit | $(fps "$orbit") | ${images:-–} | ${exact:-–} | $cpu |"
            done
        done
    done
    echo "<!-- /bench:preview -->"
} >"$table"
cat "$table"
write_section preview "Sandbox preview" "$table"
