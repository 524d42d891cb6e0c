#!/usr/bin/env python3
"""many_objects: a closed room (10 m cube, faces inward, the ceiling emits)
holding N small axis-aligned cubes (faces outward), one per cell of a
k x k x k grid (k = ceil(N^(1/3)); the first N cells in x-fastest order), each
with a pseudo-random size (30-60 % of the cell) and offset inside its cell, so
no two cubes touch.  For clustering studies: N up to 100,000 (1.2 M faces).

Usage: python3 scenes/gen/many_objects.py N [SEED] > scene.obj
       (the MTL it names, many_objects.mtl, lives in scenes/many_objects/)
Deterministic: a 64-bit linear congruential generator (Knuth's MMIX
constants) seeded with SEED (default 20261123) drives every choice.
"""
import math
import os
import sys

ROOM = 10.0


class Lcg:
    def __init__(self, seed):
        self.state = seed & 0xFFFFFFFFFFFFFFFF

    def uniform(self):
        self.state = (6364136223846793005 * self.state + 1442695040888963407) & 0xFFFFFFFFFFFFFFFF
        return (self.state >> 11) / float(1 << 53)


def num(x):
    return "%.9g" % x


def cube_quads(lo, hi):
    """Six faces of a box as (quad, outward normal axis, sign)."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    # Each quad is wound counter-clockwise seen from outside (normal outward).
    return [
        [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)],  # -x
        [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)],  # +x
        [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],  # -y
        [(x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)],  # +y
        [(x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)],  # -z
        [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],  # +z
    ]


def emit(out, n, seed):
    rng = Lcg(seed)
    out.write("# many_objects: a 10 m room with %d small cubes (seed %d).\n" % (n, seed))
    out.write("# Written by scenes/gen/many_objects.py; see scenes/README.md.\n")
    out.write("mtllib many_objects.mtl\n")
    nv = 0
    # The room: outward-wound cube faces reversed, so they face inward.
    room = cube_quads((0, 0, 0), (ROOM, ROOM, ROOM))
    for q in room:
        for p in q:
            out.write("v %s %s %s\n" % tuple(num(c) for c in p))
    for i, q in enumerate(room):
        out.write("usemtl %s\n" % ("ceiling" if i == 3 else "wall"))
        b = nv + 4 * i + 1
        out.write("f %d %d %d\nf %d %d %d\n" % (b + 3, b + 2, b + 1, b + 3, b + 1, b))
    nv += 24
    out.write("usemtl object\n")
    k = max(1, math.ceil(round(n ** (1.0 / 3.0), 9)))
    while k ** 3 < n:
        k += 1
    cell = ROOM / k
    for c in range(n):
        ix, iy, iz = c % k, (c // k) % k, c // (k * k)
        size = cell * (0.3 + 0.3 * rng.uniform())
        lo = [cell * i + (cell - size) * rng.uniform() for i in (ix, iy, iz)]
        hi = [x + size for x in lo]
        quads = cube_quads(lo, hi)
        for q in quads:
            for p in q:
                out.write("v %s %s %s\n" % tuple(num(x) for x in p))
        for i in range(6):
            b = nv + 4 * i + 1
            out.write("f %d %d %d\nf %d %d %d\n" % (b, b + 1, b + 2, b, b + 2, b + 3))
        nv += 24


def write(n, seed, path):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        emit(f, n, seed)
    with open(os.path.join(os.path.dirname(path), "many_objects.mtl"), "w") as f:
        f.write("# many_objects materials (scenes/gen/many_objects.py)\n"
                "newmtl wall\nKd 0.7 0.7 0.7\nKe 0 0 0\n"
                "newmtl ceiling\nKd 0.7 0.7 0.7\nKe 5 5 5\n"
                "newmtl object\nKd 0.5 0.45 0.4\nKe 0 0 0\n")


if __name__ == "__main__":
    if len(sys.argv) < 2 or not sys.argv[1].isdigit() or not 1 <= int(sys.argv[1]) <= 100000:
        sys.stderr.write("usage: many_objects.py N [SEED]   (1 <= N <= 100000)\n")
        sys.exit(2)
    emit(sys.stdout, int(sys.argv[1]), int(sys.argv[2]) if len(sys.argv) > 2 else 20261123)
