#!/usr/bin/env python3
"""The figures of the line `voxcast bench --peer` writes about VTK: threads, VTK's and Voxcast's
median frames, the rounds and each round's ratio, and the images' difference. today.py reads
it from BENCHMARKS.md's sections; cameras.sh from a run's output:

    voxcast bench … --peer DIR | python3 benches/peer_line.py SCENE CAMERA   (one table row)
"""
import re
import sys

PEER = re.compile(
    r"VTK peer \(vtkFixedPointVolumeRayCastMapper, (\d+) threads.*?: ([0-9.]+) s per frame, "
    r"Voxcast ([0-9.]+) s \(medians over (\d+) alternating rounds; VTK/Voxcast per round "
    r"([0-9./, ]+);",
    re.S,
)
RMSE = re.compile(r"Image difference Voxcast vs VTK: ([0-9.]+)/255")


def parse(text):
    """(threads, VTK s, Voxcast s, rounds, [VTK/Voxcast per round], RMSE or None), or None
    where the text holds no such line."""
    m = PEER.search(text)
    if not m:
        return None
    per_round = [float(a) / float(b) for a, b in
                 (r.split("/") for r in m.group(5).split(", ") if "/" in r)]
    rmse = RMSE.search(text)
    return (m.group(1), float(m.group(2)), float(m.group(3)), m.group(4), per_round,
            rmse.group(1) if rmse else None)


def main():
    scene, camera = sys.argv[1:3]
    figures = parse(sys.stdin.read())
    if not figures:
        print("| %s | %s | – | – | not measured | – | – |" % (scene, camera))
        return
    _, vtk, ours, _, per_round, rmse = figures
    print("| %s | %s | %.3f | %.3f | **%.2f×** | %.2f–%.2f× | %s/255 |" % (
        scene, camera, vtk, ours, vtk / ours, min(per_round), max(per_round), rmse or "–"))


if __name__ == "__main__":
    main()
