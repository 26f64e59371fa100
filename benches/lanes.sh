#!/usr/bin/env bash
# Regenerates BENCHMARKS.md's table of the CPU renderer's three paths against VTK's CPU ray
# caster: each scene of benches/bench.sh (512², step ½ voxel, Accumulate) rendered with the
# widest lanes this CPU has, with `--narrow-lanes` (SSE 4.1's halves, as an x86-64 without AVX
# renders) and with `--no-lanes` (one sample at a time), one run right after the other so that
# all three meet the same VTK. Each run: `voxcast bench`, 5 alternating rounds with VTK.
#
#   bash benches/lanes.sh [PEER_DIR] [DATA_DIR]
#
# As benches/bench.sh: PEER_DIR needs the peer's venv (its setup_env.sh), ch2 is fetched once.
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=benches/peer.sh
source benches/peer.sh "$@"
lines=$(mktemp)
trap 'rm -f "$lines"' EXIT

# One scene three ways: a line "scene<TAB>mode<TAB>the report's VTK sentence" per run.
scene() { # name file camera [extra arguments]
    local name=$1 file=$2 camera=$3
    shift 3
    for mode in widest --narrow-lanes --no-lanes; do
        local flag=()
        [ "$mode" = widest ] || flag=("$mode")
        "$bin" bench --volume "$file" --camera "$camera" --peer "$PEER" --threads "$THREADS" \
            --repeat 3 --peer-rounds 5 --steps 0.5 "${flag[@]}" "$@" 2>/dev/null |
            grep "VTK / Voxcast =" | sed "s/^/$name\t$mode\t/" >> "$lines"
    done
}
scene ct_cranium "$DATA/ct_cranium.nrrd" "$PEER/cams/ct_cranium.json"
scene mri_mni152 "$DATA/mri_mni152.nii.gz" "$PEER/cams/mri_mni152.json"
scene mri_brainsmall "$DATA/mri_brainsmall.nrrd" "$PEER/cams/mri_brainsmall.json"
scene bunny_sdf "$DATA/bunny_sdf.nrrd" "$PEER/cams/bunny_sdf.json"
scene mri_ch2 "$(ch2)" benches/cams/mri_ch2.json --tf mri_brain

python3 - "$lines" "$(lscpu | sed -n 's/^Model name: *//p' | head -1)" \
    "$(lscpu | sed -n 's/^CPU family: *//p' | head -1)" \
    "$(lscpu | sed -n 's/^Model: *//p' | head -1)" "$THREADS" "$(date +%F)" <<'PY'
import re, sys
path, cpu, family, model, threads, day = sys.argv[1:]
runs = {}
for line in open(path):
    name, mode, text = line.rstrip("\n").split("\t", 2)
    vtk = float(re.search(r"\): ([0-9.]+) s per frame", text).group(1))
    ours = float(re.search(r"per frame, Voxcast ([0-9.]+) s", text).group(1))
    rounds = re.search(r"per round (.*?); VTK", text).group(1).split(", ")
    ratios = [float(a) / float(b) for a, b in (r.split("/") for r in rounds)]
    runs.setdefault(name, {})[mode] = (vtk, ours, vtk / ours, min(ratios), max(ratios))
head = (
    f"Measured on {cpu} (family {family}, model {model}), {threads} threads, {day}: "
    "`bash benches/lanes.sh`, each scene with the widest lanes this CPU has, then "
    "`--narrow-lanes`, then `--no-lanes`, each run 5 rounds alternating with VTK "
    "(medians; VTK / Voxcast, and its rounds' least and greatest).\n\n"
    "| scene | VTK (s) | widest: Voxcast (s) | VTK / Voxcast | narrow (SSE 4.1): Voxcast (s) "
    "| VTK / Voxcast | its rounds | one at a time: Voxcast (s) | VTK / Voxcast |\n"
    "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n"
)
rows = []
for name, m in runs.items():
    w, n, o = m["widest"], m["--narrow-lanes"], m["--no-lanes"]
    vtk = sorted(x[0] for x in (w, n, o))[1]
    rows.append(
        f"| {name} | {vtk:.3f} | {w[1]:.3f} | {w[2]:.2f}× | {n[1]:.3f} | **{n[2]:.2f}×** "
        f"| {n[3]:.2f}–{n[4]:.2f}× | {o[1]:.3f} | {o[2]:.2f}× |"
    )
table = "<!-- bench:lanes -->\n" + head + "\n".join(rows) + "\n<!-- /bench:lanes -->"
text = open("BENCHMARKS.md").read()
pattern = re.compile(r"<!-- bench:lanes -->.*?<!-- /bench:lanes -->", re.S)
if not pattern.search(text):
    sys.exit("BENCHMARKS.md has no <!-- bench:lanes --> section to replace")
open("BENCHMARKS.md", "w").write(pattern.sub(lambda _: table, text))
print(table)
PY
