#!/usr/bin/env bash
# Regenerates BENCHMARKS.md's levels section: every level played to the end by the release
# build in a 1280×720 window on lavapipe (`voxcast --play-levels`): how long each level's scene
# takes to set up (its volume loaded and its defaults applied) and to play through, and the
# step-size trade the sampling level measures.
#
#   bash benches/levels.sh
#
# Needs a display: without $DISPLAY it starts Xvfb on :78.
set -euo pipefail
cd "$(dirname "$0")/.."
source benches/common.sh
dir=$(mktemp -d)
"$bin" --play-levels "$dir" --size 1280x720 >/dev/null 2>&1
table=$(mktemp)
python3 - "$dir/report.txt" "$(nproc)" >"$table" <<'PY'
import re, sys
lines = open(sys.argv[1]).read().splitlines()
setup, steps, done, trades, at = {}, {}, {}, {}, None
for l in lines:
    if m := re.match(r"(\S+): scene set up in ([\d.]+) s", l):
        setup[m[1]] = float(m[2])
    elif m := re.match(r"(\S+) step (\d+): ok", l):
        steps[m[1]] = steps.get(m[1], 0) + 1
        at = f"{m[1]}, step {m[2]}"
    elif m := re.match(r"(\S+): done at ([\d.]+) s", l):
        done[m[1]] = float(m[2])
    elif l.startswith("trade "):
        trades.setdefault(at, []).append(l[len("trade "):])
print("<!-- bench:levels -->")
print(f"Release build, 1280×720 window, {sys.argv[2]} cores, lavapipe, preview at full resolution")
print("(`bash benches/levels.sh`, which runs `voxcast --play-levels`).")
print()
print("| level | scene set up (s) | steps | played through (s) |")
print("| --- | ---: | ---: | ---: |")
last = 0.0
for level, t in done.items():
    print(f"| {level} | {setup.get(level, 0):.2f} | {steps.get(level, 0)} | {t - last:.1f} |")
    last = t
for where, trade in trades.items():
    print()
    print(f"The trade measured in {where} (the level's view at 192×108; the reference is always")
    print("trilinear at 1/16 voxel):")
    print()
    print("| step (voxels) | time | samples | max error | RMSE |")
    print("| --- | ---: | ---: | ---: | ---: |")
    for t in trade:
        m = re.match(r"(step|reference) (\S+): ([\d.]+) ms, (\d+) samples(?:, max ([\d.]+)/255, RMSE ([\d.]+)/255)?", t)
        if m:
            name = m[2] + (" (reference)" if m[1] == "reference" else "")
            print(f"| {name} | {m[3]} ms | {m[4]} | {m[5] or 0}/255 | {m[6] or 0}/255 |")
print("<!-- /bench:levels -->")
PY
cat "$table"
write_section levels "Levels" "$table"
