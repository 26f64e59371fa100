#!/usr/bin/env python3
"""BENCHMARKS.md's opening table, made from the per-volume sections `benches/bench.sh` has just
written: for each scene, VTK's and Voxcast's median frame, their ratio and the spread of the
ratio over the alternating rounds, with the date, the CPU and the thread count.

    python3 benches/today.py [BENCHMARKS.md]     (bench.sh runs it last)
"""
import datetime
import re
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peer_line import parse  # noqa: E402

SCENES = [
    ("ct_cranium", "ct_cranium, ct_skin_bone"),
    ("mri_mni152", "mri_mni152, mri_brain"),
    ("mri_brainsmall", "mri_brainsmall, Voxcast's own preset (VTK reads it converted)"),
    ("bunny_sdf", "bunny_sdf, bunny"),
    ("mri_ch2", "ch2, mri_brain, an oblique camera nobody tuned for"),
]
def section(text, name):
    m = re.search(r"<!-- bench:%s -->(.*?)<!-- /bench:%s -->" % (name, name), text, re.S)
    return m.group(1) if m else ""


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else "BENCHMARKS.md"
    text = open(path).read()
    cpu = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
    model = re.search(r"Model name:\s*(.+)", cpu)
    family = re.search(r"CPU family:\s*(\d+)", cpu)
    number = re.search(r"Model:\s*(\d+)", cpu)
    cpu_name = model.group(1).strip() if model else "unknown CPU"
    if family and number:
        cpu_name += " (family %s, model %s)" % (family.group(1), number.group(1))
    measured = re.search(r"Measured on (.+?) \(\d+ threads", section(text, SCENES[0][0]))
    if measured:
        cpu_name = measured.group(1)  # the run's own words for its CPU
    rows, threads, rounds = [], "?", "?"
    for name, label in SCENES:
        figures = parse(section(text, name))
        if not figures:
            rows.append("| %s | – | – | not measured | – |" % label)
            continue
        threads, vtk, ours, rounds, per_round, _ = figures
        rows.append("| %s | %.3f | %.3f | **%.2f×** | %.2f–%.2f× |" % (
            label, vtk, ours, vtk / ours, min(per_round), max(per_round)))
    table = "\n".join([
        "<!-- bench:today -->",
        "%s, %s, %s threads for both programs, 512×512 pixels, step ½ voxel, composite, shaded, "
        "medians of %s alternating rounds (`bash benches/bench.sh`):" % (
            datetime.date.today().isoformat(), cpu_name, threads, rounds),
        "",
        "| scene | VTK fixed-point (s) | Voxcast (s) | VTK / Voxcast | over the rounds |",
        "| --- | ---: | ---: | ---: | ---: |",
        *rows,
        "<!-- /bench:today -->",
    ])
    pattern = re.compile(r"<!-- bench:today -->.*?<!-- /bench:today -->", re.S)
    if pattern.search(text):
        text = pattern.sub(lambda _: table, text)
    else:
        sys.exit("%s has no <!-- bench:today --> section to replace" % path)
    open(path, "w").write(text)
    print(table)


if __name__ == "__main__":
    main()
