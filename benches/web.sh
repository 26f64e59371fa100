#!/usr/bin/env bash
# The web page's figures for BENCHMARKS.md ("In a browser"), beside the desktop's and the web
# peers' on the same machine: the bundle's size (raw and gzip), the time to the first frame in
# headless chromium (on the page's own clock, benches/peers/first_frame.py), the frame time at
# 1280×720 orbiting and resting, the page's exact render against the desktop's on one thread
# (the same view and size), and niivue's and vtk.js's frames beside the page's
# (benches/peers/run.py: the same files and canvas, screenshots of each). The page's other
# figures come from tests/browser.rs, which prints them.
#
#   bash benches/web.sh            (SKIP_BUILD=1 uses the page already in dist/)
#
# Needs chromium and chromedriver (Debian: chromium chromium-driver), a display or Xvfb for the
# desktop's window (benches/common.sh), a release build of voxcast (built there), npm (the
# peers, fetched once) and Pillow; the CT and the peers' transfer functions and cameras from
# ../shared (data/, tools/peer/), where the CT's rows are left out if it is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! python3 -c "import PIL" 2> /dev/null; then
    # Found before the run, not at its end (the peers' screenshots are read with it).
    echo "benches/web.sh needs Pillow for python3 (pip install pillow, or Debian's python3-pil)" >&2
    exit 1
fi
source benches/common.sh

if [ -z "${SKIP_BUILD:-}" ]; then
    bash web/build.sh dist > /dev/null
fi
echo "CPU: $(lscpu | sed -n 's/^Model name: *//p' | head -1), family $(lscpu | sed -n 's/^CPU family: *//p'), model $(lscpu | sed -n 's/^Model: *//p'), $(nproc) cores"
echo
echo "| build | .wasm raw | .wasm gzip -9 | JS glue gzip | a visitor downloads (gzip) |"
echo "| --- | ---: | ---: | ---: | ---: |"
page=$(cat dist/index.html dist/voxcast.js | gzip -9 | wc -c)
for gpu in webgl2 webgpu; do
    raw=$(stat -c %s "dist/$gpu/voxcast_bg.wasm")
    gz=$(gzip -9 -c "dist/$gpu/voxcast_bg.wasm" | wc -c)
    js=$(gzip -9 -c "dist/$gpu/voxcast.js" | wc -c)
    echo "| $gpu | $(awk -v b="$raw" 'BEGIN{printf "%.1f MB", b/1e6}') | $(awk -v b="$gz" 'BEGIN{printf "%.1f MB", b/1e6}') | $(awk -v b="$js" 'BEGIN{printf "%.0f kB", b/1e3}') | $(awk -v b="$((gz + js + page))" 'BEGIN{printf "%.1f MB", b/1e6}') |"
done
echo "(the whole folder, both builds: $(du -sh dist | cut -f1) raw)"
echo

echo "== the first frame on the page's clock (benches/peers/first_frame.py; goal: 1.5 s)"
for gpu in webgl2 webgpu; do
    python3 benches/peers/first_frame.py dist "$gpu" 4
done
echo

echo "== the page in headless chromium (tests/browser.rs)"
log=$(mktemp)
VOXCAST_PAGE_FIGURES=1 cargo test --test browser -- --nocapture --test-threads 1 > "$log" 2>&1 || true
grep -oE "(webgl2|webgpu|chromium \[).*" "$log" || echo "(the browser test printed no figures)"
echo

echo "== the desktop window under Xvfb, the same view"
for what in "orbiting:--auto-orbit 5" "resting:"; do
    label=${what%%:*}
    extra=${what#*:}
    # shellcheck disable=SC2086
    line=$("$bin" --volume builtin:bunny --no-rays --size 1280x720 --measure-frames 40 $extra \
        2> /dev/null | grep "frame time" || true)
    echo "desktop $label: $line"
done
echo

# The page's exact render against the desktop's on one thread, the same view at the page's scene
# size: the CPU live view's exact render (the core alone) and Render image (in slices, between
# the page's frames; the picture and its cost map from one march, which `render --cost` times
# too). Goal (issue 55): the page at 0.8 of the desktop's one-thread speed or more.
exact=$(grep -oE 'webgl2: first frame.*"[0-9]+×[0-9]+ in [0-9]+ ms: the exact render' "$log" |
    grep -oE '[0-9]+×[0-9]+ in [0-9]+ ms' | head -1 || true)
size=$(echo "$exact" | grep -oE '^[0-9]+×[0-9]+' | sed 's/×/x/' || true)
live=$(echo "$exact" | grep -oE '[0-9]+ ms' | grep -oE '[0-9]+' || true)
work=$(grep -oE "webgl2: Render image's work, median of 5: [0-9.]+ s" "$log" | grep -oE '[0-9.]+ s' | head -1 | grep -oE '[0-9.]+' || true)
echo "== Render image's render of the same view at the page's scene size, ${size:-833x669}"
for threads in 1 "$(nproc)"; do
    line=$(RAYON_NUM_THREADS=$threads "$bin" render --volume builtin:bunny --size "${size:-833x669}" \
        --repeat 5 --out /tmp/voxcast_web_render.png 2> /dev/null | grep " in " || true)
    echo "desktop, $threads thread(s): $line"
    if [ "$threads" = 1 ]; then
        one=$(echo "$line" | grep -oE 'in [0-9.]+ s' | grep -oE '[0-9.]+')
    fi
done
line=$(RAYON_NUM_THREADS=1 "$bin" render --volume builtin:bunny --size "${size:-833x669}" \
    --repeat 5 --cost samples --out /tmp/voxcast_web_render.png 2> /dev/null | grep " in " || true)
echo "desktop, 1 thread, as Render image: $line"
both=$(echo "$line" | grep -oE 'in [0-9.]+ s' | grep -oE '[0-9.]+' || true)
if [ -n "${one:-}" ] && [ -n "${both:-}" ] && [ -n "${live:-}" ] && [ -n "${work:-}" ]; then
    awk -v one="$one" -v both="$both" -v live="$live" -v work="$work" 'BEGIN {
        printf "the page (WebGL2 build) against the desktop on one thread: the live view'"'"'s exact render %.0f ms, %.2f× the desktop'"'"'s speed; Render image %.0f ms of work (median of 5), %.2f× (goal: 0.8× or more)\n", live, one * 1000 / live, work * 1000, both / work }'
fi
echo

echo "== the page beside niivue and vtk.js (benches/peers/run.py, the same browser)"
python3 benches/peers/run.py --dist dist
