#!/usr/bin/env python3
"""An NRRD volume resampled to N×N×N by nearest neighbour, spacing scaled so the object keeps its
size — issue 41's 512³ volume made from the CT. Plain python3 (no numpy); reads what
peer_raw.py reads (attached header, raw or gzip), writes a raw-encoded NRRD.

    python3 benches/upsample.py SRC.nrrd DST.nrrd [N]
"""
import array
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peer_raw import ARRAY_CODES, read_nrrd  # noqa: E402


def main():
    src, dst = sys.argv[1:3]
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 512
    (nx, ny, nz), dtype, spacing, data, big = read_nrrd(src)
    size = array.array(ARRAY_CODES[dtype]).itemsize
    xs = [x * nx // n for x in range(n)]
    rows = {}

    def row(z, y):
        # One source row stretched to n voxels, kept for the output rows that repeat it.
        if (z, y) not in rows:
            start = (z * ny + y) * nx * size
            r = data[start:start + nx * size]
            rows[(z, y)] = b"".join(r[x * size:(x + 1) * size] for x in xs)
        return rows[(z, y)]

    with open(dst, "wb") as out:
        out.write((
            "NRRD0004\ntype: %s\ndimension: 3\nsizes: %d %d %d\nendian: %s\nencoding: raw\n"
            "spacings: %g %g %g\n\n"
            % (dtype, n, n, n, "big" if big else "little",
               spacing[0] * nx / n, spacing[1] * ny / n, spacing[2] * nz / n)
        ).encode())
        for z in range(n):
            sz = z * nz // n
            out.write(b"".join(row(sz, y * ny // n) for y in range(n)))
            if (z + 1) * nz // n != sz:
                rows.clear()  # the next slice reads another source slice


if __name__ == "__main__":
    main()
