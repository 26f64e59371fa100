#!/usr/bin/env bash
# The web page's figures for BENCHMARKS.md ("In a browser"), beside the desktop's on the same
# machine: the bundle's size (raw and gzip), the time to the first frame in headless chromium,
# the frame time at 1280×720 orbiting and resting, and Render image's time (the page: one
# thread, in slices between frames; the desktop: `voxcast render` of the same view and size on
# 1 and on all threads). The browser figures come from tests/browser.rs, which prints them.
#
#   bash benches/web.sh            (SKIP_BUILD=1 uses the page already in dist/)
#
# Needs chromium and chromedriver (Debian: chromium chromium-driver), a display or Xvfb for the
# desktop's window (benches/common.sh), and a release build of voxcast (built there).
set -euo pipefail
cd "$(dirname "$0")/.."
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

echo "== the page in headless chromium (tests/browser.rs)"
cargo test --test browser -- --nocapture --test-threads 1 2>&1 |
    grep -oE "(webgl2|webgpu): .*" || echo "(the browser test printed no figures)"
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
echo "== Render image's render of the same view, 833×669 (the page's scene at 1280×720)"
for threads in 1 "$(nproc)"; do
    line=$(RAYON_NUM_THREADS=$threads "$bin" render --volume builtin:bunny --size 833x669 \
        --repeat 5 --out /tmp/voxcast_web_render.png 2> /dev/null | grep " in " || true)
    echo "desktop, $threads thread(s): $line"
done
