#!/usr/bin/env python3
"""Writes N small closed organs (cubes of 12 triangles, 6 mm, on a 10 mm grid) as OBJ files into a
folder, the many-organ case of docs/BENCHMARKS.md:

    scripts/many-organs.py /tmp/many 1000
    vbrain bench /tmp/many --frames 5 --size 512x512 --cull none --opacity all=0.5
"""
import itertools
import math
import os
import sys

CORNERS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
# Counter-clockwise seen from outside, 1-based.
FACES = [(1, 3, 2), (1, 4, 3), (5, 6, 7), (5, 7, 8), (1, 2, 6), (1, 6, 5),
         (2, 3, 7), (2, 7, 6), (3, 4, 8), (3, 8, 7), (4, 1, 5), (4, 5, 8)]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    out, count = sys.argv[1], int(sys.argv[2])
    os.makedirs(out, exist_ok=True)
    side = math.ceil(round(count ** (1 / 3), 6))
    cells = itertools.islice(itertools.product(range(side), repeat=3), count)
    for i, (x, y, z) in enumerate(cells):
        with open(os.path.join(out, f"c{i:04d}.obj"), "w") as f:
            for c in CORNERS:
                f.write("v %g %g %g\n" % (x * 10 + c[0] * 6, y * 10 + c[1] * 6, z * 10 + c[2] * 6))
            for t in FACES:
                f.write("f %d %d %d\n" % t)


if __name__ == "__main__":
    main()
