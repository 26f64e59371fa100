#!/usr/bin/env bash
# Regenerates the README's screenshots from the scripted play-through (`voxcast
# --play-levels`, the same run tests/levels.rs checks): free play, a level's first step, a ray's
# breakdown, Render image, a cut volume, several lights, the skip blocks and the preview's cost
# view, at 1280×720, in docs/screenshots/.
#
#   bash docs/screenshots.sh
#
# Needs a display: without $DISPLAY it starts Xvfb (see benches/common.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
source benches/common.sh
run=$(mktemp -d)
"$bin" --play-levels "$run" --size 1280x720 >/dev/null
out=docs/screenshots
mkdir -p "$out"
cp "$run/free_play.png" "$out/free_play.png"
# Chosen by level id (their numbers follow the levels' order).
cp "$(ls "$run"/*_first-hit.png)" "$out/level.png"
cp "$(ls "$run"/*_sampling_step*.png | head -1)" "$out/breakdown.png"
cp "$(ls "$run"/*_preview-render_step*.png | head -1)" "$out/render_image.png"
cp "$(ls "$run"/*_clipping_step*.png | head -1)" "$out/looking_inside.png"
cp "$(ls "$run"/*_lights_step5.png)" "$out/lights.png"
cp "$(ls "$run"/*_acceleration_step9.png)" "$out/skip_blocks.png"
cp "$(ls "$run"/*_acceleration_step10.png)" "$out/cost_view.png"
ls -l "$out"
