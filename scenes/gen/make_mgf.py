#!/usr/bin/env python3
"""The Cornell box in MGF (scenes/mgf/cornell.mgf + cornell_blocks.mgf) and
its OBJ twin (scenes/mgf/cornell_twin.obj + .mtl), from scenes/cornell/.

The MGF file says the same box as scenes/cornell/cornell.obj in MGF's terms:
coordinates in millimetres under `xf -s 0.001`, each material as a CIE xy
chromaticity with `rd` (and `ed` for the light), the blocks in an included
file as `o` objects.  The chromaticities are the inverse of radkit's documented
conversion (core/scene/import_mgf.c, papers/mgf.md) applied to the OBJ's Kd
and Ke, rounded to 6 decimals; the twin's Kd and Ke are the forward conversion
of those rounded numbers, written with 17 digits, and its vertices are the
millimetres times 0.001 as the reader computes them.  So both files hold the
same triangles in the same order with the same materials, and `radkit solve`
must give the same per-face answers (tests/test_mgf.c).

Python 3 standard library only, deterministic:
    python3 scenes/gen/make_mgf.py    # then `git diff scenes/mgf`: empty
"""
import os

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
SRC = os.path.join(ROOT, "scenes", "cornell")
OUT = os.path.join(ROOT, "scenes", "mgf")

PRIMARIES = [(0.640, 0.330), (0.290, 0.600), (0.150, 0.060)]  # Radiance's R, G, B


def inv3(m):
    d = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
         - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
         + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    return [[(m[(j + 1) % 3][(i + 1) % 3] * m[(j + 2) % 3][(i + 2) % 3]
              - m[(j + 1) % 3][(i + 2) % 3] * m[(j + 2) % 3][(i + 1) % 3]) / d
             for j in range(3)] for i in range(3)]


def rgb_to_xyz_matrix():
    """Columns: each primary's XYZ scaled so that R = G = B = 1 is X = Y = Z = 1."""
    P = [[x / y for x, y in PRIMARIES], [1.0] * 3, [(1 - x - y) / y for x, y in PRIMARIES]]
    Pi = inv3(P)
    S = [sum(Pi[c]) for c in range(3)]
    return [[P[i][c] * S[c] for c in range(3)] for i in range(3)]


M = rgb_to_xyz_matrix()
MI = inv3(M)


def to_cxy(rgb):
    X, Y, Z = (sum(M[i][c] * rgb[c] for c in range(3)) for i in range(3))
    return X / (X + Y + Z), Y / (X + Y + Z), Y


def to_rgb(x, y, Y):
    if abs(x - 1 / 3) < 1e-12 and abs(y - 1 / 3) < 1e-12:
        return [Y, Y, Y]
    xyz = [x * Y / y, Y, (1 - x - y) * Y / y]
    return [MI[i][0] * xyz[0] + MI[i][1] * xyz[1] + MI[i][2] * xyz[2] for i in range(3)]


def read_obj():
    verts, faces, mat = [], [], None
    for line in open(os.path.join(SRC, "cornell.obj")):
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            verts.append([float(t) for t in w[1:4]])
        elif w[0] == "usemtl":
            mat = w[1]
        elif w[0] == "f":
            faces.append((mat, [int(t) - 1 for t in w[1:]]))
    mats, cur = {}, None
    for line in open(os.path.join(SRC, "cornell.mtl")):
        w = line.split()
        if not w or w[0].startswith("#"):
            continue
        if w[0] == "newmtl":
            cur = w[1]
            mats[cur] = {}
        elif w[0] in ("Kd", "Ke"):
            mats[cur][w[0]] = [float(t) for t in w[1:4]]
    return verts, faces, mats


def mm(x):
    s = "%.10g" % (x * 1000)
    assert abs(float(s) - x * 1000) < 1e-9
    return s


def main():
    verts, faces, mats = read_obj()
    order = ["white", "red", "green", "light"]
    head = ("# The Cornell box (scenes/cornell/, see scenes/README.md) in MGF, millimetres.\n"
            "# Written by scenes/gen/make_mgf.py; do not edit by hand.\n")
    mgf = [head]
    twin_mtl = ["# The materials of cornell.mgf after radkit's colour conversion.\n"
                "# Written by scenes/gen/make_mgf.py; do not edit by hand.\n"]
    for name in order:
        kd, ke = mats[name]["Kd"], mats[name]["Ke"]
        mgf.append("m %s =\n\tsides 1\n" % name)
        if kd[0] == kd[1] == kd[2]:
            mgf.append("\tc\n\trd %.6f\n" % kd[0])
            rho = [round(kd[0], 6)] * 3
        else:
            x, y, Y = to_cxy(kd)
            x, y, Y = round(x, 6), round(y, 6), round(Y, 6)
            mgf.append("\tc\n\t\tcxy %.6f %.6f\n\trd %.6f\n" % (x, y, Y))
            rho = to_rgb(x, y, Y)
        e = [0.0, 0.0, 0.0]
        if any(ke):
            x, y, Y = to_cxy(ke)
            x, y, Y = round(x, 6), round(y, 6), round(Y, 6)
            mgf.append("\tc\n\t\tcxy %.6f %.6f\n\ted %.6f\n" % (x, y, Y))
            e = to_rgb(x, y, Y)
        twin_mtl.append("newmtl %s\nKd %s\nKe %s\n" % (name, " ".join(repr(v) for v in rho),
                                                       " ".join(repr(v) for v in e)))
    # room: faces before the first block vertex (index 12); blocks in the include
    room = [f for f in faces if max(f[1]) < 12]
    blocks = [f for f in faces if min(f[1]) >= 12]
    assert room + blocks == faces
    mgf.append("# millimetres to metres for everything below\nxf -s 0.001\n")
    for i, v in enumerate(verts[:12]):
        mgf.append("v r%d =\n\tp %s %s %s\n" % (i + 1, mm(v[0]), mm(v[1]), mm(v[2])))
    cur = None
    for name, idx in room:
        if name != cur:
            mgf.append("m %s\n" % name)
            cur = name
        mgf.append("f %s\n" % " ".join("r%d" % (i + 1) for i in idx))
    mgf.append("# the blocks, in their own file, inside this transform\ni cornell_blocks.mgf\nxf\n")
    inc = [head.replace("in MGF", "in MGF: the two blocks (included by cornell.mgf)")]
    inc.append("m white\n")
    for b, (lo, hi, label) in enumerate([(12, 20, "short_block"), (20, 28, "tall_block")]):
        inc.append("o %s\n" % label)
        for i in range(lo, hi):
            v = verts[i]
            inc.append("\tv b%d =\n\t\tp %s %s %s\n" % (i + 1, mm(v[0]), mm(v[1]), mm(v[2])))
        for name, idx in blocks:
            if lo <= min(idx) and max(idx) < hi:
                inc.append("\tf %s\n" % " ".join("b%d" % (i + 1) for i in idx))
        inc.append("o\n")
    twin = ["# The OBJ twin of cornell.mgf: the same triangles, in the same order.\n"
            "# Written by scenes/gen/make_mgf.py; do not edit by hand.\nmtllib cornell_twin.mtl\n"]
    for v in verts:
        twin.append("v %s\n" % " ".join(repr(float(mm(c)) * 0.001) for c in v))
    cur = None
    for name, idx in faces:
        if name != cur:
            twin.append("usemtl %s\n" % name)
            cur = name
        twin.append("f %s\n" % " ".join(str(i + 1) for i in idx))
    os.makedirs(OUT, exist_ok=True)
    for fname, text in [("cornell.mgf", mgf), ("cornell_blocks.mgf", inc),
                        ("cornell_twin.obj", twin), ("cornell_twin.mtl", twin_mtl)]:
        with open(os.path.join(OUT, fname), "w") as f:
            f.write("".join(text))


if __name__ == "__main__":
    main()
