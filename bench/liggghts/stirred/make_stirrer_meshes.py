#!/usr/bin/env python3
"""ASCII STL of the stirrer of the one-disk LS1 slice for LIGGGHTS (bench/liggghts/stirred):
the shaft (closed cylinder surface, radius 19 mm, z = 0..L) and one plain disk (annulus slab,
radius 19..38 mm, thickness 7.5 mm, centred at L/2; no holes: LIGGGHTS's mesh code would
need them as many more facets, and the comparison is one of throughput). Usage:
  make_stirrer_meshes.py OUT_DIR [L]"""
import math
import os
import sys

N = 120  # facets around


def tri(f, a, b, c):
    ux, uy, uz = (b[i] - a[i] for i in range(3))
    vx, vy, vz = (c[i] - a[i] for i in range(3))
    n = (uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx)
    ln = math.sqrt(sum(x * x for x in n)) or 1.0
    f.write("facet normal %g %g %g\n outer loop\n" % tuple(x / ln for x in n))
    for p in (a, b, c):
        f.write("  vertex %.9g %.9g %.9g\n" % p)
    f.write(" endloop\nendfacet\n")


def ring(r, z):
    return [(r * math.cos(2 * math.pi * k / N), r * math.sin(2 * math.pi * k / N), z) for k in range(N)]


def band(f, r, z0, z1, outward=True):
    lo, hi = ring(r, z0), ring(r, z1)
    for k in range(N):
        k1 = (k + 1) % N
        if outward:
            tri(f, lo[k], lo[k1], hi[k1])
            tri(f, lo[k], hi[k1], hi[k])
        else:
            tri(f, lo[k], hi[k1], lo[k1])
            tri(f, lo[k], hi[k], hi[k1])


def annulus(f, r0, r1, z, up=True):
    a, b = ring(r0, z), ring(r1, z)
    for k in range(N):
        k1 = (k + 1) % N
        if up:
            tri(f, a[k], b[k], b[k1])
            tri(f, a[k], b[k1], a[k1])
        else:
            tri(f, a[k], b[k1], b[k])
            tri(f, a[k], a[k1], b[k1])


def main():
    out = sys.argv[1]
    length = float(sys.argv[2]) if len(sys.argv) > 2 else 0.03575
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "shaft.stl"), "w") as f:
        f.write("solid shaft\n")
        band(f, 0.019, 0.0, length)
        f.write("endsolid shaft\n")
    zc, ht = 0.5 * length, 0.5 * 0.0075
    with open(os.path.join(out, "disk.stl"), "w") as f:
        f.write("solid disk\n")
        band(f, 0.038, zc - ht, zc + ht)
        annulus(f, 0.019, 0.038, zc + ht, True)
        annulus(f, 0.019, 0.038, zc - ht, False)
        f.write("endsolid disk\n")


main()
