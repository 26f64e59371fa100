#!/usr/bin/env bash
# The window's own cost (issue 41, item 2): the sandbox at 1280×720 with the CPU live view on
# the bunny (--no-rays), resting and orbiting 5° a frame (`--measure-frames 20 [--auto-orbit
# 5]`), in alternating rounds of each binary given (default: this build), with the median of
# each part of a frame (`src/sandbox/drivers/frame_parts.rs`). Writes BENCHMARKS.md's
# `window` section.
#
#   bash benches/window.sh [[LABEL=]BINARY...]        ROUNDS=5 SIZE=1280x720 FRAMES=20
#
# Needs a display: without $DISPLAY it starts Xvfb on :78 (lavapipe then draws the window).
set -euo pipefail
cd "$(dirname "$0")/.."
ROUNDS=${ROUNDS:-5}
SIZE=${SIZE:-1280x720}
FRAMES=${FRAMES:-20}
source benches/common.sh
bins=("$@")
[ ${#bins[@]} -eq 0 ] && bins=("$bin")
raw=$(mktemp)
for round in $(seq "$ROUNDS"); do
    for spec in "${bins[@]}"; do
        b=${spec#*=}
        label=${spec%%=*}
        for orbit in 0 5; do
            args=(--volume builtin:bunny --no-rays --size "$SIZE" --measure-frames "$FRAMES")
            [ "$orbit" != 0 ] && args+=(--auto-orbit "$orbit")
            line=$("$b" "${args[@]}" 2>/dev/null | grep "frame time" || true)
            echo "$round	$label	$orbit	$line" >>"$raw"
            echo "round $round $(basename "$b") orbit $orbit: $(echo "$line" | grep -o 'median [0-9.]* ms')" >&2
        done
    done
done
cpu_model=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
table=$(mktemp)
python3 - "$raw" "$SIZE" "$FRAMES" "$ROUNDS" "$(nproc)" "$cpu_model" >"$table" <<'PY'
import re, statistics, sys
raw, size, frames, rounds, cores, cpu = sys.argv[1:7]
rows = {}
for line in open(raw):
    _, b, orbit, text = line.rstrip("\n").split("\t", 3)
    m = re.search(r"median ([0-9.]+) ms", text)
    if not m:
        continue
    r = rows.setdefault((b, orbit), {"median": [], "parts": {}, "images": []})
    r["median"].append(float(m.group(1)))
    for name, value in re.findall(r"([A-Za-z' ]+?) ([0-9.]+)(?=[,)])", text.split("where a frame goes")[-1]):
        r["parts"].setdefault(name.strip(), []).append(float(value))
    im = re.search(r"([0-9.]+) images/s at ([0-9]+)×([0-9]+)", text)
    if im and orbit != "0":
        r["images"].append((float(im.group(1)), int(im.group(2))))
print("<!-- bench:window -->")
print(f"The sandbox at {size.replace('x', '×')}, the bunny, `--no-rays`, the CPU live view on lavapipe, "
      f"{cores} cores ({cpu}); `voxcast --measure-frames {frames} [--auto-orbit 5]`, {rounds} "
      "alternating rounds (`bash benches/window.sh [BINARY...]`). Frame times are the median over "
      "rounds of each round's median (range in brackets); the parts are medians over rounds "
      "of each part's median, in ms (`src/sandbox/drivers/frame_parts.rs`).")
print()
print("| binary | camera | frame (ms) | fps | main world | egui's UI + tessellation | render world | presenting (lavapipe draws here) | live images while orbiting |")
print("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | --- |")
for (b, orbit), r in rows.items():
    med = statistics.median(r["median"])
    p = {k: statistics.median(v) for k, v in r["parts"].items()}
    main = sum(p.get(k, 0) for k in ["input and time", "the sandbox's systems", "egui's UI", "egui's tessellation", "the rest"])
    egui = p.get("egui's UI", 0) + p.get("egui's tessellation", 0)
    render = sum(p.get(k, 0) for k in ["asset uploads", "the window's next image", "queue and prepare", "recording the passes", "submitting them", "presenting"])
    images = "–"
    if r["images"]:
        rate = statistics.median(i[0] for i in r["images"])
        width = statistics.median(i[1] for i in r["images"])
        images = f"{rate:.0f}/s, {width:.0f} px wide"
    part = lambda v: f"{v:.1f}" if p else "–"
    print(f"| {b} | {'orbiting 5°/frame' if orbit != '0' else 'resting'} | {med:.1f} ({min(r['median']):.1f}–{max(r['median']):.1f}) | "
          f"{1000 / med:.0f} | {part(main)} | {part(egui)} | {part(render)} | {part(p.get('presenting', 0))} | {images} |")
print("<!-- /bench:window -->")
PY
cat "$table"
write_section window "The window's own cost" "$table"
