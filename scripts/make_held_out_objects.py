#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Writes the held-out objects of issue 18 (data/meshes/held-out/*.obj): five objects of the same kinds as the
test objects (overhangs, legs, tunnels, wheels) that no setting of nbs was chosen on. Each is a union of closed,
outward (counter-clockwise) boxes, cylinders and frusta standing on z = 0, metres, about 0.16 m across; parts touch or
overlap (the ground truth counts internal faces unobservable). Deterministic.

usage: /usr/bin/python3 scripts/make_held_out_objects.py [OUT_DIR]   (default data/meshes/held-out)
"""
import math
import os
import sys


def box(lo, hi):
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    f = [(0, 2, 1), (0, 3, 2), (4, 5, 6), (4, 6, 7), (0, 1, 5), (0, 5, 4), (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6),
         (3, 0, 4), (3, 4, 7)]
    return v, f


def frustum(base, axis, r0, r1, h, n=48):
    """Closed frustum from `base` along the unit axis (x, y or z), radius r0 at the base and r1 at the top."""
    a = [float(c) for c in axis]
    t = (1.0, 0.0, 0.0) if abs(a[0]) < 0.9 else (0.0, 1.0, 0.0)
    u = (a[1] * t[2] - a[2] * t[1], a[2] * t[0] - a[0] * t[2], a[0] * t[1] - a[1] * t[0])
    un = math.sqrt(sum(c * c for c in u))
    u = tuple(c / un for c in u)
    w = (a[1] * u[2] - a[2] * u[1], a[2] * u[0] - a[0] * u[2], a[0] * u[1] - a[1] * u[0])  # (u, w, a) right-handed
    v = []
    for k, r in ((0.0, r0), (h, r1)):
        for i in range(n):
            c, s = math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n)
            v.append(tuple(base[j] + k * a[j] + r * (c * u[j] + s * w[j]) for j in range(3)))
    v.append(tuple(base))
    v.append(tuple(base[j] + h * a[j] for j in range(3)))
    f = []
    for i in range(n):
        j = (i + 1) % n
        f += [(i, j, n + j), (i, n + j, n + i)]  # side, outward
        f.append((2 * n, j, i))                  # bottom cap, facing −axis
        f.append((2 * n + 1, n + i, n + j))      # top cap, facing +axis
    return v, f


def cylinder(base, axis, r, h, n=48):
    return frustum(base, axis, r, r, h, n)


OBJECTS = {
    # a lamp: a base disk, a thin stem, a shade (frustum) overhanging from 9 to 14 cm
    "lamp": ("a lamp: base r 4 cm, stem r 8 mm to 10 cm, a shade r 7 -> 3 cm from 9 to 14 cm",
             [cylinder((0, 0, 0), (0, 0, 1), 0.04, 0.01), cylinder((0, 0, 0.005), (0, 0, 1), 0.008, 0.095),
              frustum((0, 0, 0.09), (0, 0, 1), 0.07, 0.03, 0.05, 72)]),
    # a bench: a plank on two blocks
    "bench": ("a bench: a 16 x 5 x 1.5 cm plank at 5 cm on two 2 x 5 x 5 cm blocks",
              [box((-0.08, -0.025, 0.05), (0.08, 0.025, 0.065)), box((-0.07, -0.025, 0.0), (-0.05, 0.025, 0.05)),
               box((0.05, -0.025, 0.0), (0.07, 0.025, 0.05))]),
    # an arch: two pillars and a lintel over a 10 cm x 6 cm tunnel
    "arch": ("an arch: two 3 x 6 x 6 cm pillars, a 16 x 6 x 2 cm lintel, a tunnel 10 cm wide, 6 cm high",
             [box((-0.08, -0.03, 0.0), (-0.05, 0.03, 0.06)), box((0.05, -0.03, 0.0), (0.08, 0.03, 0.06)),
              box((-0.08, -0.03, 0.06), (0.08, 0.03, 0.08))]),
    # a stool: a seat disk on three legs
    "stool": ("a stool: a seat r 6 cm, 1.5 cm thick, at 8 cm on three legs r 8 mm",
              [cylinder((0, 0, 0.08), (0, 0, 1), 0.06, 0.015, 72)] +
              [cylinder((0.045 * math.cos(2 * math.pi * k / 3), 0.045 * math.sin(2 * math.pi * k / 3), 0.0),
                        (0, 0, 1), 0.008, 0.085) for k in range(3)]),
    # a spool lying on its side: an axle between two wheels that touch the support
    "spool": ("a spool on its side: an axle r 1.2 cm, 13 cm long, between two wheels r 4 cm, 1.5 cm wide",
              [cylinder((-0.075, 0, 0.04), (1, 0, 0), 0.04, 0.015), cylinder((0.06, 0, 0.04), (1, 0, 0), 0.04, 0.015),
               cylinder((-0.065, 0, 0.04), (1, 0, 0), 0.012, 0.13)]),
}


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "data/meshes/held-out"
    os.makedirs(out, exist_ok=True)
    for name, (what, parts) in OBJECTS.items():
        lines = [f"# nbs held-out object (issue 18): {what}", "# scripts/make_held_out_objects.py; metres, +z up"]
        verts, faces = [], []
        for v, f in parts:
            o = len(verts)
            verts += v
            faces += [(a + o, b + o, c + o) for a, b, c in f]
        lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in verts]
        lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
        path = os.path.join(out, name + ".obj")
        tmp = path + ".tmp"
        with open(tmp, "w") as fh:
            fh.write("\n".join(lines) + "\n")
        os.replace(tmp, path)
        print(f"{path}: {len(verts)} vertices, {len(faces)} triangles")


if __name__ == "__main__":
    main()
