#!/usr/bin/env python3
"""Write radkit's scene library (scenes/*/) deterministically.

Run from anywhere:  python3 scenes/gen/make_scenes.py
Only the Python 3 standard library is used.  Every file it writes is
committed; re-running it must reproduce them byte for byte (the tests load
the committed files; `git diff` after a run shows any drift).

Conventions (DESIGN.md): faces are one-sided, the front is the side of the
counter-clockwise winding's normal.  Enclosures face inwards, objects outwards.
OBJ + MTL: Kd = reflectance per RGB channel, Ke = emitted exitance (W/m^2).
References (papers/refs.bib): the Cornell box data [cornellbox], the plates'
form factors [howell2010].  scenes/README.md records every scene's provenance.
"""
import base64
import math
import os
import struct
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def num(x):
    """Shortest text that reads back as the same double (no -0)."""
    if x == 0:
        return "0"
    r = repr(float(x))
    return r[:-2] if r.endswith(".0") else r


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def newell(points):
    """Normal of a polygon (not normalised), robust for non-planar quads."""
    n = [0.0, 0.0, 0.0]
    for i, p in enumerate(points):
        q = points[(i + 1) % len(points)]
        n[0] += (p[1] - q[1]) * (p[2] + q[2])
        n[1] += (p[2] - q[2]) * (p[0] + q[0])
        n[2] += (p[0] - q[0]) * (p[1] + q[1])
    return n


def orient(points, towards=None, away=None, normal=None):
    """Return the polygon wound so that its normal points towards `towards`,
    away from `away`, or along `normal`."""
    n = newell(points)
    c = [sum(p[i] for p in points) / len(points) for i in range(3)]
    if towards is not None:
        want = sub(towards, c)
    elif away is not None:
        want = sub(c, away)
    else:
        want = normal
    return points if dot(n, want) > 0 else list(reversed(points))


class Obj:
    """An OBJ under construction: shared vertices, polygons with materials."""

    def __init__(self):
        self.vertices, self.index, self.faces = [], {}, []

    def vertex(self, p):
        key = tuple(p)
        if key not in self.index:
            self.vertices.append(key)
            self.index[key] = len(self.vertices)
        return self.index[key]

    def polygon(self, points, material, triangulate=True):
        ids = [self.vertex(p) for p in points]
        if triangulate and len(ids) > 3:
            for k in range(1, len(ids) - 1):
                self.faces.append(([ids[0], ids[k], ids[k + 1]], material))
        else:
            self.faces.append((ids, material))

    def write(self, path, mtllib, header, camera=None):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            for line in header:
                f.write("# " + line + "\n" if line else "#\n")
            if camera:
                f.write("# radkit camera position %s look_at %s up %s fov_y %s\n" % (
                    " ".join(num(x) for x in camera[0]), " ".join(num(x) for x in camera[1]),
                    " ".join(num(x) for x in camera[2]), num(camera[3])))
            if mtllib:
                f.write("mtllib %s\n" % mtllib)
            for v in self.vertices:
                f.write("v %s %s %s\n" % tuple(num(x) for x in v))
            current = None
            for ids, material in self.faces:
                if material != current:
                    f.write("usemtl %s\n" % material)
                    current = material
                f.write("f %s\n" % " ".join(str(i) for i in ids))


def write_mtl(path, materials, header):
    """materials: list of (name, rho[3], emission[3])."""
    with open(path, "w") as f:
        for line in header:
            f.write("# " + line + "\n" if line else "#\n")
        for name, rho, e in materials:
            f.write("newmtl %s\n" % name)
            f.write("Kd %s %s %s\n" % tuple(num(x) for x in rho))
            f.write("Ke %s %s %s\n" % tuple(num(x) for x in e))


# ---------------------------------------------------------------------------
# The Cornell box, as measured and published by the Cornell University Program
# of Computer Graphics ("Cornell Box Data", graphics.cornell.edu/online/box/data.html).
# Coordinates there are in millimetres; radkit's file is in metres.

# Reflectance spectra (400..700 nm every 4 nm) of the white, green and red paint.
WAVELENGTHS = list(range(400, 701, 4))
WHITE = [0.343, 0.445, 0.551, 0.624, 0.665, 0.687, 0.708, 0.723, 0.715, 0.710, 0.745, 0.758, 0.739,
         0.767, 0.777, 0.765, 0.751, 0.745, 0.748, 0.729, 0.745, 0.757, 0.753, 0.750, 0.746, 0.747,
         0.735, 0.732, 0.739, 0.734, 0.725, 0.721, 0.733, 0.725, 0.732, 0.743, 0.744, 0.748, 0.728,
         0.716, 0.733, 0.726, 0.713, 0.740, 0.754, 0.764, 0.752, 0.736, 0.734, 0.741, 0.740, 0.732,
         0.745, 0.755, 0.751, 0.744, 0.731, 0.733, 0.744, 0.731, 0.712, 0.708, 0.729, 0.730, 0.727,
         0.707, 0.703, 0.729, 0.750, 0.760, 0.751, 0.739, 0.724, 0.730, 0.740, 0.737]
GREEN = [0.092, 0.096, 0.098, 0.097, 0.098, 0.095, 0.095, 0.097, 0.095, 0.094, 0.097, 0.098, 0.096,
         0.101, 0.103, 0.104, 0.107, 0.109, 0.112, 0.115, 0.125, 0.140, 0.160, 0.187, 0.229, 0.285,
         0.343, 0.390, 0.435, 0.464, 0.472, 0.476, 0.481, 0.462, 0.447, 0.441, 0.426, 0.406, 0.373,
         0.347, 0.337, 0.314, 0.285, 0.277, 0.266, 0.250, 0.230, 0.207, 0.186, 0.171, 0.160, 0.148,
         0.141, 0.136, 0.130, 0.126, 0.123, 0.121, 0.122, 0.119, 0.114, 0.115, 0.117, 0.117, 0.118,
         0.120, 0.122, 0.128, 0.132, 0.139, 0.144, 0.146, 0.150, 0.152, 0.157, 0.159]
RED = [0.040, 0.046, 0.048, 0.053, 0.049, 0.050, 0.053, 0.055, 0.057, 0.056, 0.059, 0.057, 0.061,
       0.061, 0.060, 0.062, 0.062, 0.062, 0.061, 0.062, 0.060, 0.059, 0.057, 0.058, 0.058, 0.058,
       0.056, 0.055, 0.056, 0.059, 0.057, 0.055, 0.059, 0.059, 0.058, 0.059, 0.061, 0.061, 0.063,
       0.063, 0.067, 0.068, 0.072, 0.080, 0.090, 0.099, 0.124, 0.154, 0.192, 0.255, 0.287, 0.349,
       0.402, 0.443, 0.487, 0.513, 0.558, 0.584, 0.620, 0.606, 0.609, 0.651, 0.612, 0.610, 0.650,
       0.638, 0.627, 0.620, 0.630, 0.628, 0.642, 0.639, 0.657, 0.639, 0.635, 0.642]
# The light's emission spectrum as published (400, 500, 600, 700 nm).
LIGHT_WL = [400, 500, 600, 700]
LIGHT = [0.0, 8.0, 15.6, 18.4]

# The three bands of the RGB reduction: blue 400-500, green 500-600, red 600-700 nm.
BANDS = [(600, 700), (500, 600), (400, 500)]  # r, g, b


def band_mean(wl, values, lo, hi):
    """Mean of the piecewise-linear interpolant of (wl, values) over [lo, hi],
    by the trapezoid rule on its own knots (exact for a piecewise-linear
    function whose knots include lo and hi, which holds for every band here)."""
    total = 0.0
    for i in range(len(wl) - 1):
        a, b = max(wl[i], lo), min(wl[i + 1], hi)
        if b <= a:
            continue
        def at(x):
            t = (x - wl[i]) / (wl[i + 1] - wl[i])
            return values[i] + t * (values[i + 1] - values[i])
        total += 0.5 * (at(a) + at(b)) * (b - a)
    return total / (hi - lo)


def rgb(wl, values):
    return [round(band_mean(wl, values, lo, hi), 6) for lo, hi in BANDS]


def cornell():
    mm = 0.001
    def P(x, y, z):
        return [round(x * mm, 6), round(y * mm, 6), round(z * mm, 6)]
    centre = P(278.0, 274.4, 279.6)
    obj = Obj()
    floor = [P(552.8, 0, 0), P(0, 0, 0), P(0, 0, 559.2), P(549.6, 0, 559.2)]
    back = [P(549.6, 0, 559.2), P(0, 0, 559.2), P(0, 548.8, 559.2), P(556.0, 548.8, 559.2)]
    right = [P(0, 0, 559.2), P(0, 0, 0), P(0, 548.8, 0), P(0, 548.8, 559.2)]
    left = [P(552.8, 0, 0), P(549.6, 0, 559.2), P(556.0, 548.8, 559.2), P(556.0, 548.8, 0)]
    ceiling = [P(556.0, 548.8, 0), P(556.0, 548.8, 559.2), P(0, 548.8, 559.2), P(0, 548.8, 0)]
    light = [P(343.0, 548.8, 227.0), P(343.0, 548.8, 332.0), P(213.0, 548.8, 332.0),
             P(213.0, 548.8, 227.0)]
    obj.polygon(orient(floor, towards=centre), "white")
    # The published light lies in the ceiling's plane, overlapping it; here the
    # ceiling is the ring around the light (8 triangles joining each outer edge
    # to the matching light edge), so light and ceiling partition the plane.
    outer = sorted(ceiling, key=lambda p: math.atan2(p[2] - 0.2796, p[0] - 0.278))
    inner = sorted(light, key=lambda p: math.atan2(p[2] - 0.2796, p[0] - 0.278))
    for k in range(4):
        o0, o1, i0, i1 = outer[k], outer[(k + 1) % 4], inner[k], inner[(k + 1) % 4]
        obj.polygon(orient([o0, o1, i1], normal=[0, -1, 0]), "white")
        obj.polygon(orient([o0, i1, i0], normal=[0, -1, 0]), "white")
    obj.polygon(orient(light, normal=[0, -1, 0]), "light")
    obj.polygon(orient(back, towards=centre), "white")
    obj.polygon(orient(right, towards=centre), "green")
    obj.polygon(orient(left, towards=centre), "red")
    short_top = [P(130.0, 165.0, 65.0), P(82.0, 165.0, 225.0), P(240.0, 165.0, 272.0),
                 P(290.0, 165.0, 114.0)]
    tall_top = [P(423.0, 330.0, 247.0), P(265.0, 330.0, 296.0), P(314.0, 330.0, 456.0),
                P(472.0, 330.0, 406.0)]
    for top in (short_top, tall_top):
        c = [sum(p[i] for p in top) / 4 for i in range(3)]
        c[1] = top[0][1] / 2
        obj.polygon(orient(top, away=c), "white")
        # The four sides; the blocks stand on the floor and have no bottom face.
        for k in range(4):
            a, b = top[k], top[(k + 1) % 4]
            side = [[a[0], 0.0, a[2]], [b[0], 0.0, b[2]], b, a]
            obj.polygon(orient(side, away=c), "white")
    fov = 2 * math.degrees(math.atan(0.5 * 0.025 / 0.035))
    camera = ([0.278, 0.273, -0.8], [0.278, 0.273, 0.0], [0.0, 1.0, 0.0], round(fov, 6))
    light_e = [round(math.pi * x, 6) for x in rgb(LIGHT_WL, LIGHT)]
    d = os.path.join(ROOT, "cornell")
    header = ["The Cornell box (Cornell University Program of Computer Graphics, 'Cornell Box Data'),",
              "measured geometry converted from millimetres to metres.  See scenes/README.md.",
              "Written by scenes/gen/make_scenes.py; do not edit by hand."]
    obj.write(os.path.join(d, "cornell.obj"), "cornell.mtl", header, camera)
    write_mtl(os.path.join(d, "cornell.mtl"), [
        ("white", rgb(WAVELENGTHS, WHITE), [0, 0, 0]),
        ("red", rgb(WAVELENGTHS, RED), [0, 0, 0]),
        ("green", rgb(WAVELENGTHS, GREEN), [0, 0, 0]),
        ("light", [0.78, 0.78, 0.78], light_e),
    ], ["Cornell box materials: Kd = band means of the published reflectance spectra",
        "(r: 600-700 nm, g: 500-600 nm, b: 400-500 nm); light Ke = pi x band means of the",
        "published emission spectrum (radiance -> exitance of a Lambertian emitter).",
        "Written by scenes/gen/make_scenes.py; see scenes/README.md."])


# ---------------------------------------------------------------------------
def box_faces(lo, hi):
    """The six faces of an axis-aligned box as quads (unoriented)."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    return [
        [[x0, y0, z0], [x0, y1, z0], [x0, y1, z1], [x0, y0, z1]],
        [[x1, y0, z0], [x1, y1, z0], [x1, y1, z1], [x1, y0, z1]],
        [[x0, y0, z0], [x1, y0, z0], [x1, y0, z1], [x0, y0, z1]],
        [[x0, y1, z0], [x1, y1, z0], [x1, y1, z1], [x0, y1, z1]],
        [[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0]],
        [[x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]],
    ]


def add_box(obj, lo, hi, material):
    """A closed axis-aligned box, its faces turned outward."""
    c = [(lo[i] + hi[i]) / 2 for i in range(3)]
    for quad in box_faces(lo, hi):
        obj.polygon(orient(quad, away=c), material)


FURNACE_RHO = 0.375
FURNACE_E = 2.385


def furnace_cube():
    side = 1.25
    obj = Obj()
    c = [side / 2] * 3
    for quad in box_faces([0, 0, 0], [side] * 3):
        obj.polygon(orient(quad, towards=c), "furnace")
    d = os.path.join(ROOT, "furnace_cube")
    obj.write(os.path.join(d, "cube.obj"), "cube.mtl",
              ["A closed cube of side 1.25 m, faces inward, uniform grey reflectance and emission.",
               "Furnace test: B = E / (1 - rho) = 2.385 / 0.625 = 3.816 on every face.",
               "Written by scenes/gen/make_scenes.py."])
    write_mtl(os.path.join(d, "cube.mtl"), [("furnace", [FURNACE_RHO] * 3, [FURNACE_E] * 3)],
              ["uniform grey furnace material"])


def tetrahedron():
    a = 1.5
    pts = [[a, a, a], [a, -a, -a], [-a, a, -a], [-a, -a, a]]  # regular, edge 2 sqrt(2) a
    obj = Obj()
    for skip in range(4):
        tri = [p for i, p in enumerate(pts) if i != skip]
        obj.polygon(orient(tri, towards=[0, 0, 0]), "furnace")
    d = os.path.join(ROOT, "tetrahedron")
    obj.write(os.path.join(d, "tetrahedron.obj"), "tetrahedron.mtl",
              ["A regular tetrahedron (corners (+-1.5, +-1.5, +-1.5) with an even number of minus",
               "signs), faces inward, uniform grey reflectance and emission (furnace: B = 3.816).",
               "Written by scenes/gen/make_scenes.py."])
    write_mtl(os.path.join(d, "tetrahedron.mtl"), [("furnace", [FURNACE_RHO] * 3, [FURNACE_E] * 3)],
              ["uniform grey furnace material"])


def icosphere(level, radius):
    t = (1 + math.sqrt(5)) / 2
    verts = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t],
             [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    faces = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
             [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
             [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]
    def unit(v):
        n = math.sqrt(dot(v, v))
        return [x / n for x in v]
    verts = [unit(v) for v in verts]
    for _ in range(level):
        mids, nf = {}, []
        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in mids:
                verts.append(unit([(verts[a][i] + verts[b][i]) / 2 for i in range(3)]))
                mids[key] = len(verts) - 1
            return mids[key]
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        faces = nf
    return [[radius * x for x in v] for v in verts], faces


def sphere():
    d = os.path.join(ROOT, "sphere")
    for level in range(4):
        verts, faces = icosphere(level, 1.25)
        obj = Obj()
        for f in faces:
            tri = [verts[i] for i in f]
            obj.polygon(orient(tri, towards=[0, 0, 0]), "furnace")
        obj.write(os.path.join(d, "sphere_%d.obj" % level), "sphere.mtl",
                  ["An icosphere of radius 1.25 m (corners on the sphere), subdivision level %d:" % level,
                   "%d faces, all facing inward (the centre).  Furnace material (B = 3.816)." % len(faces),
                   "Written by scenes/gen/make_scenes.py."])
    write_mtl(os.path.join(d, "sphere.mtl"), [("furnace", [FURNACE_RHO] * 3, [FURNACE_E] * 3)],
              ["uniform grey furnace material"])


def furnace_rooms():
    """Closed rooms holding closed boxes: furnaces with occlusion.  Every face is
    the furnace material and every point sees only furnace surfaces (the room
    faces inward, the boxes outward, nothing touches), so B = E / (1 - rho)
    exactly, whatever blocks what."""
    d = os.path.join(ROOT, "furnace_room")
    room = 2.0
    rc = [room / 2] * 3

    def write(name, boxes, header):
        obj = Obj()
        for quad in box_faces([0, 0, 0], [room] * 3):
            obj.polygon(orient(quad, towards=rc), "furnace")
        for lo, hi in boxes:
            add_box(obj, lo, hi, "furnace")
        obj.write(os.path.join(d, name), "room.mtl", header + [
            "Furnace: every face emits E = 2.385 and reflects rho = 0.375 (override with",
            "--rho), so B = E / (1 - rho) on every face, occluded or not.",
            "Written by scenes/gen/make_scenes.py."])

    write("room_box.obj", [([0.6, 0.5, 0.6], [1.4, 1.3, 1.4])],
          ["A closed 2 m room (inward) holding one closed 0.8 m box (outward) that",
           "touches nothing."])
    grid = []
    for i in range(3):
        for j in range(3):
            for k in range(3):
                lo = [0.35 + 0.5 * i, 0.35 + 0.5 * j, 0.35 + 0.5 * k]
                grid.append((lo, [x + 0.3 for x in lo]))
    write("room_27.obj", grid,
          ["A closed 2 m room (inward) holding 27 closed 0.3 m boxes (outward) on a",
           "3 x 3 x 3 grid, 0.2 m apart."])
    write("room_hair.obj", [([0.6, 0.5, 0.001], [1.4, 1.3, 0.801])],
          ["A closed 2 m room (inward) holding one closed 0.8 m box (outward) 1 mm",
           "from the wall z = 0: a near-touching pair."])
    write_mtl(os.path.join(d, "room.mtl"), [("furnace", [FURNACE_RHO] * 3, [FURNACE_E] * 3)],
              ["uniform grey furnace material"])


def plates():
    mats = [("emitter", [0, 0, 0], [1, 1, 1]), ("receiver", [0, 0, 0], [0, 0, 0])]
    d = os.path.join(ROOT, "plates_parallel")
    obj = Obj()
    obj.polygon(orient([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], normal=[0, 0, 1]), "emitter")
    obj.polygon(orient([[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], normal=[0, 0, -1]), "receiver")
    obj.write(os.path.join(d, "plates.obj"), "plates.mtl",
              ["Two unit squares facing each other at distance 1 (the classic parallel plates):",
               "F(emitter -> receiver) = 0.19982.",
               "Written by scenes/gen/make_scenes.py."])
    write_mtl(os.path.join(d, "plates.mtl"), mats, ["emitter E = 1 W/m^2, both black (rho = 0)"])
    d = os.path.join(ROOT, "plates_perpendicular")
    obj = Obj()
    obj.polygon(orient([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], normal=[0, 0, 1]), "emitter")
    obj.polygon(orient([[0, 0, 0], [0, 1, 0], [0, 1, 1], [0, 0, 1]], normal=[1, 0, 0]), "receiver")
    obj.write(os.path.join(d, "plates.obj"), "plates.mtl",
              ["Two unit squares sharing an edge at a right angle (the classic perpendicular plates):",
               "F(emitter -> receiver) = 0.20004.",
               "Written by scenes/gen/make_scenes.py."])
    write_mtl(os.path.join(d, "plates.mtl"), mats, ["emitter E = 1 W/m^2, both black (rho = 0)"])
    d = os.path.join(ROOT, "occluder")
    obj = Obj()
    obj.polygon(orient([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], normal=[0, 0, 1]), "emitter")
    obj.polygon(orient([[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], normal=[0, 0, -1]), "receiver")
    obj.polygon(orient([[0.25, 0.25, 0.5], [0.75, 0.25, 0.5], [0.75, 0.75, 0.5], [0.25, 0.75, 0.5]],
                       normal=[0, 0, -1]), "occluder")
    obj.write(os.path.join(d, "occluder.obj"), "occluder.mtl",
              ["The parallel plates with a 0.5 x 0.5 plate half-way between them, centred,",
               "facing the emitter.  Written by scenes/gen/make_scenes.py."])
    write_mtl(os.path.join(d, "occluder.mtl"), mats + [("occluder", [0, 0, 0], [0, 0, 0])],
              ["emitter E = 1 W/m^2, all black (rho = 0)"])


def lattice():
    """A floor lit through a regular lattice of small black cubes."""
    obj = Obj()
    obj.polygon(orient([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], normal=[0, 0, 1]), "floor")
    obj.polygon(orient([[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], normal=[0, 0, -1]), "light")
    n, cell = 8, 1.0 / 8
    half = cell / 4
    for i in range(n):
        for j in range(n):
            c = [(i + 0.5) * cell, (j + 0.5) * cell, 0.5]
            add_box(obj, [x - half for x in c], [x + half for x in c], "cube")
    d = os.path.join(ROOT, "lattice")
    obj.write(os.path.join(d, "lattice.obj"), "lattice.mtl",
              ["A unit floor (reflectance 0.5) lit by a unit emitter 1 m above it (E = 1 W/m^2,",
               "black) through an 8 x 8 lattice of black cubes of side 1/16 m half-way between:",
               "every floor-emitter pair is seen between dozens of cubes, so the hierarchical",
               "solvers' links take visibility from rays, and the lattice's regularity shows any",
               "bias of regularly placed ray ends.  Written by scenes/gen/make_scenes.py."])
    write_mtl(os.path.join(d, "lattice.mtl"), [("floor", [0.5] * 3, [0] * 3),
                                               ("light", [0] * 3, [1] * 3),
                                               ("cube", [0] * 3, [0] * 3)],
              ["a grey floor, a black emitter and black cubes"])


def slit():
    """Boxes under a thin slab with a slit, in a room lit from the ceiling."""
    obj = Obj()
    room, c = 2.0, [1.0, 1.0, 1.0]
    quads = box_faces([0, 0, 0], [room] * 3)
    for k, quad in enumerate(quads):
        obj.polygon(orient(quad, towards=c), "light" if k == 5 else "wall")
    # two 2 cm slabs 0.5 m under the ceiling, from wall to wall but for a
    # 0.2 m slit between them along y
    for x0, x1 in ((0.0, 0.9), (1.1, 2.0)):
        add_box(obj, [x0, 0.0, 1.48], [x1, 2.0, 1.5], "slab")
    # a 4 x 4 grid of 0.2 m boxes floating 5 cm above the floor
    for i in range(4):
        for j in range(4):
            lo = [0.25 + 0.45 * i, 0.25 + 0.45 * j, 0.05]
            add_box(obj, lo, [lo[0] + 0.2, lo[1] + 0.2, 0.25], "box")
    d = os.path.join(ROOT, "slit")
    obj.write(os.path.join(d, "slit.obj"), "slit.mtl",
              ["A closed 2 m room (inward, walls and floor rho 0.5) lit by its ceiling",
               "(E = 1 W/m^2, black), with two thin slabs (2 cm, rho 0.3) 0.5 m under the",
               "ceiling that span it from wall to wall but for a 0.2 m slit along y, and 16",
               "boxes of 0.2 m (rho 0.6, 0.5, 0.4) on a 4 x 4 grid 5 cm above the floor: the",
               "light reaches the room below only through the slit, and a cluster link",
               "between a box and the ceiling sees it or not through a thin occluder.",
               "Written by scenes/gen/make_scenes.py."])
    write_mtl(os.path.join(d, "slit.mtl"), [("wall", [0.5] * 3, [0] * 3),
                                            ("light", [0] * 3, [1] * 3),
                                            ("slab", [0.3] * 3, [0] * 3),
                                            ("box", [0.6, 0.5, 0.4], [0] * 3)],
              ["grey walls and floor, an emitting black ceiling, grey slabs, coloured boxes"])


def lamp():
    """A small lamp in a dark open room: direct light dominates."""
    obj = Obj()
    c = [0.5, 0.5, 0.5]
    for quad in box_faces([0, 0, 0], [1, 1, 1])[:5]:  # no ceiling
        obj.polygon(orient(quad, towards=c), "wall")
    obj.polygon(orient([[0.4, 0.4, 0.5], [0.6, 0.4, 0.5], [0.6, 0.6, 0.5]], normal=[0, 0, -1]),
                "lamp")
    d = os.path.join(ROOT, "lamp")
    obj.write(os.path.join(d, "lamp.obj"), "lamp.mtl",
              ["A small lamp in a dark open room: a 1 m box without its ceiling (floor and four",
               "walls, faces inward, reflectance 0.02) lit by a 0.02 m^2 triangle hanging at its",
               "centre, 0.5 m above the floor, emitting downward.  Nearly all the light a wall",
               "reflects comes straight from the lamp, and no wall point above the lamp sees it.",
               "Written by scenes/gen/make_scenes.py."])
    write_mtl(os.path.join(d, "lamp.mtl"), [("wall", [0.02] * 3, [0] * 3),
                                            ("lamp", [0] * 3, [10] * 3)],
              ["dark walls, and a lamp that only emits (10 W/m^2)"])


def lamp_closed():
    """A small emitting cube in a dark closed room: sealed, direct light dominates."""
    obj = Obj()
    c = [0.5, 0.5, 0.5]
    for quad in box_faces([0, 0, 0], [1, 1, 1]):
        obj.polygon(orient(quad, towards=c), "wall")
    add_box(obj, [0.45, 0.45, 0.45], [0.55, 0.55, 0.55], "lamp")
    d = os.path.join(ROOT, "lamp")
    obj.write(os.path.join(d, "lamp_closed.obj"), "lamp.mtl",
              ["A small lamp in a dark closed room: a 1 m box (faces inward, reflectance 0.02)",
               "around a 0.1 m cube at its centre (faces outward) emitting 10 W/m^2.  Every point",
               "sees only front faces (sealed), and nearly all the light a wall reflects comes",
               "straight from the lamp.  Written by scenes/gen/make_scenes.py."])


def formats():
    """Small files in other formats, written as other tools write them."""
    d = os.path.join(ROOT, "formats")
    os.makedirs(d, exist_ok=True)
    # ASCII PLY with one quad and one triangle (a polygon list, as Blender and
    # MeshLab write), float coordinates and an extra vertex property.
    with open(os.path.join(d, "quad_tri.ply"), "w") as f:
        f.write("ply\nformat ascii 1.0\ncomment hand-written like a MeshLab export\n"
                "element vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
                "property float quality\nelement face 2\nproperty list uchar int vertex_indices\n"
                "end_header\n"
                "0 0 0 1\n2 0 0 1\n2 1.5 0 1\n0 1.5 0 1\n1 0.75 2 1\n"
                "4 0 1 2 3\n3 0 1 4\n")
    # ASCII STL: a 1.5 x 2 rectangle as two facets (STL repeats every corner).
    with open(os.path.join(d, "rectangle.stl"), "w") as f:
        f.write("solid rectangle\n")
        for tri in (((0, 0, 0), (1.5, 0, 0), (1.5, 2, 0)), ((0, 0, 0), (1.5, 2, 0), (0, 2, 0))):
            f.write("  facet normal 0 0 1\n    outer loop\n")
            for v in tri:
                f.write("      vertex %s %s %s\n" % tuple(num(x) for x in v))
            f.write("    endloop\n  endfacet\n")
        f.write("endsolid rectangle\n")
    # OFF: a tetrahedron facing outward.
    with open(os.path.join(d, "tetra.off"), "w") as f:
        f.write("OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
    # glTF 2.0, one triangle + one emitting triangle, buffer embedded as base64.
    pos = [0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 0, 1, 1]
    idx = [0, 1, 2, 0, 1, 2]
    blob = struct.pack("<18f", *pos) + struct.pack("<6H", *idx)
    uri = "data:application/octet-stream;base64," + base64.b64encode(blob).decode()
    gltf = """{
  "asset": {"version": "2.0", "generator": "hand-written for radkit tests"},
  "extensionsUsed": ["KHR_materials_emissive_strength"],
  "scene": 0,
  "scenes": [{"nodes": [0, 1]}],
  "nodes": [{"mesh": 0}, {"mesh": 1, "translation": [0.5, 0.25, 2.0]}],
  "meshes": [
    {"primitives": [{"attributes": {"POSITION": 0}, "indices": 2, "material": 0}]},
    {"primitives": [{"attributes": {"POSITION": 1}, "indices": 3, "material": 1}]}
  ],
  "materials": [
    {"name": "paint", "pbrMetallicRoughness": {"baseColorFactor": [0.625, 0.5, 0.25, 1.0]}},
    {"name": "lamp", "pbrMetallicRoughness": {"baseColorFactor": [0.125, 0.125, 0.125, 1.0]},
     "emissiveFactor": [1.0, 0.5, 0.25],
     "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}}}
  ],
  "buffers": [{"byteLength": %d, "uri": "%s"}],
  "bufferViews": [
    {"buffer": 0, "byteOffset": 0, "byteLength": 36, "target": 34962},
    {"buffer": 0, "byteOffset": 36, "byteLength": 36, "target": 34962},
    {"buffer": 0, "byteOffset": 72, "byteLength": 6, "target": 34963},
    {"buffer": 0, "byteOffset": 78, "byteLength": 6, "target": 34963}
  ],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
     "min": [0, 0, 0], "max": [1, 1, 0]},
    {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3",
     "min": [0, 0, 1], "max": [1, 1, 1]},
    {"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR"},
    {"bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR"}
  ]
}
""" % (len(blob), uri)
    with open(os.path.join(d, "two_triangles.gltf"), "w") as f:
        f.write(gltf)


def bad():
    """The bad inputs the tests use; each is wrong in exactly one way."""
    d = os.path.join(ROOT, "bad")
    os.makedirs(d, exist_ok=True)
    good_mtl = "newmtl m\nKd 0.5 0.5 0.5\nKe 1 1 1\n"
    square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    files = {
        "missing_mtl.obj": "mtllib no_such_file.mtl\n" + square + "usemtl m\nf 1 2 3\n",
        "nan_vertex.obj": "mtllib good.mtl\nv 0 0 0\nv 1 0 0\nv nan 1 0\nusemtl m\nf 1 2 3\n",
        "inf_vertex.obj": "mtllib good.mtl\nv 0 0 0\nv 1 0 inf\nv 1 1 0\nusemtl m\nf 1 2 3\n",
        "index_out_of_range.obj": "mtllib good.mtl\n" + square + "usemtl m\nf 1 2 3\nf 1 3 9\n",
        "zero_area.obj": "mtllib good.mtl\n" + square + "v 2 0 0\nusemtl m\nf 1 2 3\nf 1 2 5\n",
        "rho_too_big.obj": "mtllib rho_too_big.mtl\n" + square + "usemtl m\nf 1 2 3\n",
        "rho_too_big.mtl": "newmtl m\nKd 0.5 1.5 0.5\nKe 1 1 1\n",
        "negative_emission.obj": "mtllib negative_emission.mtl\n" + square + "usemtl m\nf 1 2 3\n",
        "negative_emission.mtl": "newmtl m\nKd 0.5 0.5 0.5\nKe 1 -0.25 1\n",
        "malformed_number.obj": "mtllib good.mtl\nv 0 0 0\nv 1 0.5x 0\nv 1 1 0\nusemtl m\nf 1 2 3\n",
        "undefined_material.obj": "mtllib good.mtl\n" + square + "usemtl nosuch\nf 1 2 3\n",
        "no_faces.obj": "mtllib good.mtl\n" + square,
        "empty.obj": "",
        "garbage.obj": "\x7fELF\x02\x01\x01 this is not a scene \x01\x02\x03\n%%%% 12 ab\n",
        "garbage.ply": "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n"
                       "zz yy\n",
        "zero_area.ply": "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                         "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
                         "end_header\n0 0 0\n1 0 0\n0 1 0\n2 0 0\n3 0 1 2\n3 0 1 3\n",
        "index_out_of_range.ply": "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                  "property float y\nproperty float z\nelement face 1\n"
                                  "property list uchar int vertex_indices\nend_header\n"
                                  "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
        "good.mtl": good_mtl,
    }
    for name, text in files.items():
        with open(os.path.join(d, name), "w") as f:
            f.write(text)


def main():
    cornell()
    furnace_cube()
    tetrahedron()
    sphere()
    furnace_rooms()
    plates()
    lamp()
    lamp_closed()
    lattice()
    slit()
    formats()
    bad()
    # many_objects: the committed small instance (the generator takes any N).
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import many_objects
    many_objects.write(64, 20261123, os.path.join(ROOT, "many_objects", "many_64.obj"))


if __name__ == "__main__":
    main()
