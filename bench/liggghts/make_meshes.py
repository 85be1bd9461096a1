#!/usr/bin/env python3
"""Write a millsim drum (default: the 300 mm case) as ASCII STL meshes for LIGGGHTS (fix mesh/surface).

Geometry (docs/cases.md, src/dem/walls/drum_walls.hpp): axis z through the origin, inner
radius R, end plates at z = 0 and z = L, N box lifters of radial height h and tangential width
w. At drum angle phi lifter k is centred on the direction phi + pi/2 + 2 pi k / N; its box is
R - h <= u <= R (u along that direction), |v| <= w/2 across it, 0 <= z <= L.

Each wall is its own file (and its own LIGGGHTS mesh) so that no triangle of one part shares
an edge with another part: LIGGGHTS checks mesh topology per mesh, and separate meshes avoid
T-junctions where the lifters stand on the cylinder.

Usage: make_meshes.py OUTDIR [--phi RAD] [--facets 180]
                       [--radius R --length L --lifters N --lifter-height H --lifter-width W]
The geometry options default to the 300 mm case (constants below).
"""
import argparse
import math
import os

R0, L0 = 0.146, 0.1       # defaults: inner radius, length [m] of the 300 mm case,
N_LIFT0, H0, W0 = 8, 0.005, 0.005   # and its lifters (count, height, width)


def write_stl(path, name, tris):
    """ASCII STL; the normal is recomputed by LIGGGHTS from the vertex order, but we write it."""
    with open(path, "w") as f:
        f.write(f"solid {name}\n")
        for a, b, c in tris:
            u = [b[i] - a[i] for i in range(3)]
            v = [c[i] - a[i] for i in range(3)]
            n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
            s = math.sqrt(sum(x * x for x in n)) or 1.0
            f.write("  facet normal %.9e %.9e %.9e\n    outer loop\n" % tuple(x / s for x in n))
            for p in (a, b, c):
                f.write("      vertex %.12e %.12e %.12e\n" % tuple(p))
            f.write("    endloop\n  endfacet\n")
        f.write(f"endsolid {name}\n")


def quad(p0, p1, p2, p3):
    """Two triangles of the quadrilateral p0 p1 p2 p3 (in order around it)."""
    return [(p0, p1, p2), (p0, p2, p3)]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("outdir")
    ap.add_argument("--phi", type=float, default=0.0, help="drum angle of the meshes [rad]")
    ap.add_argument("--facets", type=int, default=180, help="facets around the cylinder")
    ap.add_argument("--radius", type=float, default=R0, help="inner drum radius [m]")
    ap.add_argument("--length", type=float, default=L0, help="inner drum length [m]")
    ap.add_argument("--lifters", type=int, default=N_LIFT0, help="number of lifters")
    ap.add_argument("--lifter-height", type=float, default=H0, help="radial lifter height [m]")
    ap.add_argument("--lifter-width", type=float, default=W0, help="tangential lifter width [m]")
    a = ap.parse_args()
    R, L, N_LIFT, H, W = a.radius, a.length, a.lifters, a.lifter_height, a.lifter_width
    os.makedirs(a.outdir, exist_ok=True)
    n = a.facets

    # Rim vertices lie on the true circle (the flat facets are at most R (1 - cos(pi/n)) =
    # 22 um inside it for n = 180). The end discs reuse the same rim so there is no gap.
    rim = [(R * math.cos(a.phi + 2 * math.pi * i / n), R * math.sin(a.phi + 2 * math.pi * i / n))
           for i in range(n)]
    cyl, front, back = [], [], []
    for i in range(n):
        (x0, y0), (x1, y1) = rim[i], rim[(i + 1) % n]
        cyl += quad((x0, y0, 0.0), (x0, y0, L), (x1, y1, L), (x1, y1, 0.0))
        front.append(((0.0, 0.0, 0.0), (x1, y1, 0.0), (x0, y0, 0.0)))  # fan from the axis
        back.append(((0.0, 0.0, L), (x0, y0, L), (x1, y1, L)))

    # Lifters: the inner face and the two side faces. The sides reach 1 mm beyond the cylinder
    # (unreachable by balls) so no slit is left where the flat side meets the curved wall; the
    # end faces are not needed because the end plates cover them.
    lift = []
    for k in range(N_LIFT):
        ang = a.phi + math.pi / 2 + 2 * math.pi * k / N_LIFT
        er, et = (math.cos(ang), math.sin(ang)), (-math.sin(ang), math.cos(ang))

        def p(u, v, z):
            return (u * er[0] + v * et[0], u * er[1] + v * et[1], z)
        u0, u1, hw = R - H, R + 0.001, W / 2
        lift += quad(p(u0, -hw, 0), p(u0, hw, 0), p(u0, hw, L), p(u0, -hw, L))   # inner face
        lift += quad(p(u0, hw, 0), p(u1, hw, 0), p(u1, hw, L), p(u0, hw, L))     # +v side
        lift += quad(p(u0, -hw, 0), p(u0, -hw, L), p(u1, -hw, L), p(u1, -hw, 0))  # -v side

    for name, tris in (("cylinder", cyl), ("front", front), ("back", back), ("lifters", lift)):
        write_stl(os.path.join(a.outdir, name + ".stl"), name, tris)


if __name__ == "__main__":
    main()
