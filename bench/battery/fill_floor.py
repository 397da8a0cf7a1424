#!/usr/bin/env python3
"""How near the truth a surface can come that knows the truth only along the network.

For the battery's icosphere-onto-analytic cases (bench/battery/make_battery.cpp: the truth is
r(u) u over the unit directions u, r a superellipsoid's, a bumpy sphere's or a peanut's radius),
the truth's radius is taken at the network's points only and filled in over the sphere of
directions by a smooth interpolant (SciPy's RBFInterpolator): phi(d) = d or d^3 of the chordal
distance d between directions, plus an affine term, through every network point. The fill is compared with the truth
at the truth's vertices: |s(u) - r(u)| times the cosine between the direction and the truth's
normal (the distance to first order), largest over the vertices, in % of the truth's
bounding-box diagonal. No fitter is involved, and the fill is told the sphere parametrization
that a fitter is not: a row whose two figures are both above the battery's 1 % bound (the
great-circle networks) says that the curves alone do not pin the surface down to 1 % for these
interpolants, whatever the fitter does between them; a low figure says the information is there.

The torus case (torus_family: a torus with R = 1, r = 0.35 onto one whose tube radius is
0.35 (1 + 0.25 cos 3 phi), scaled and warped) is filled the same way over the template torus: each
network point's torus angles (phi, theta) are recovered exactly from its coordinates, the motion
from the template torus's point at those angles to the network point is interpolated over the
template torus in space (phi(d) = d or d^3, affine term), and the filled surface is compared with
the truth at its vertices along their normals. Its three meridians sit where cos 3 phi is the same
(phi = 0.3 + 2 pi k / 3), so the curves never see the tube at its thinnest or thickest.

  fill_floor.py CASES_DIR          (CASES_DIR: the generator's output, build/battery/cases)

Prints one row per base case (variants share their base's curves and truth).
"""
import os
import sys

import numpy as np
from scipy.interpolate import RBFInterpolator

from battery_io import read_curves, read_off


# The radii of make_battery.cpp (superellipsoid_r, bumpy_r, peanut_r); checked below against each
# case's truth.off, whose vertices are r(u) u.
def superellipsoid(u):
    p = 3.0
    s = np.abs(u[:, 0] / 1.3) ** p + np.abs(u[:, 1] / 1.0) ** p + np.abs(u[:, 2] / 0.8) ** p
    return s ** (-1 / p)


def bumpy(u):
    x, y, z = u.T
    return 1.0 + 0.15 * (3 * x * x * y - y ** 3) + 0.5 * x * y * z + 0.08 * (5 * z ** 3 - 3 * z) / 2


def peanut(u):
    x = u[:, 0]
    return np.sqrt(2 * x * x - 1 + np.sqrt(1.5 - 4 * x * x * (1 - x * x)))


RADIUS = {"superellipsoid": superellipsoid, "bumpy": bumpy, "peanut": peanut}


def unit(p):
    return p / np.linalg.norm(p, axis=1)[:, None]


def vertex_normals(v, f):
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    out = np.zeros_like(v)
    for k in range(3):
        np.add.at(out, f[:, k], n)
    return unit(out)


def torus_angles(p):
    """The (phi, theta) of make_battery.cpp's deformed torus at its points p (exact inversion)."""
    x, y, z = p.T
    phi = np.arctan2(y / 0.9, x / 1.2)
    r = 0.35 * (1 + 0.25 * np.cos(3 * phi))
    c = (np.hypot(x / 1.2, y / 0.9) - 1.0) / r
    s = (z - 0.1 * np.sin(2 * phi)) / (1.1 * r)
    return phi, np.arctan2(s, c)


def torus_point(phi, theta, deformed):
    r = 0.35 * (1 + 0.25 * np.cos(3 * phi)) if deformed else 0.35 + 0 * phi
    a, b, h = (1.2, 0.9, 1.1) if deformed else (1.0, 1.0, 1.0)
    ring = 1.0 + r * np.cos(theta)
    lift = 0.1 * np.sin(2 * phi) if deformed else 0 * phi
    return np.stack([a * ring * np.cos(phi), b * ring * np.sin(phi), h * r * np.sin(theta) + lift], 1)


def torus_row(cases):
    truth, faces = read_off(os.path.join(cases, "torus", "truth.off"))
    phi, theta = torus_angles(truth)
    if np.max(np.linalg.norm(torus_point(phi, theta, True) - truth, axis=1)) > 1e-9:
        sys.exit("fill_floor.py: torus: truth.off is not the deformed torus of make_battery.cpp")
    p = read_curves(os.path.join(cases, "torus", "curves.polylines.txt"))
    a, b = torus_angles(p)
    at = torus_point(a, b, False)
    where = torus_point(phi, theta, False)
    normal = vertex_normals(truth, faces)
    diagonal = np.linalg.norm(truth.max(0) - truth.min(0))
    figures = []
    for kernel in ("linear", "cubic"):
        s = where + RBFInterpolator(at, p - at, kernel=kernel, degree=1)(where)
        figures.append(100 * np.max(np.abs(((s - truth) * normal).sum(1))) / diagonal)
    return f"| torus | {len(p)} | {figures[0]:.3f} | {figures[1]:.3f} |"


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    cases = sys.argv[1]
    print("| case | network points | fill phi=r, % | fill phi=r^3, % |")
    print("|---|---:|---:|---:|")
    for name in sorted(os.listdir(cases)):
        parts = name.split("-")
        if "@" in name or not name.startswith("ico") or len(parts) < 3 or parts[1] not in RADIUS:
            continue
        radius = RADIUS[parts[1]]
        truth, faces = read_off(os.path.join(cases, name, "truth.off"))
        u = unit(truth)
        r = np.linalg.norm(truth, axis=1)
        if np.max(np.abs(radius(u) - r)) > 1e-9 * np.max(r):
            sys.exit(f"fill_floor.py: {name}: truth.off is not the {parts[1]} of make_battery.cpp")
        diagonal = np.linalg.norm(truth.max(0) - truth.min(0))
        cosine = np.abs((vertex_normals(truth, faces) * u).sum(1))
        p = read_curves(os.path.join(cases, name, "curves.polylines.txt"))
        figures = []
        for kernel in ("linear", "cubic"):  # SciPy's -d and d^3, both with an affine term
            s = RBFInterpolator(unit(p), np.linalg.norm(p, axis=1), kernel=kernel, degree=1)(u)
            figures.append(100 * np.max(np.abs(s - r) * cosine) / diagonal)
        print(f"| {name} | {len(p)} | {figures[0]:.3f} | {figures[1]:.3f} |", flush=True)
    if os.path.isdir(os.path.join(cases, "torus")):
        print(torus_row(cases), flush=True)


if __name__ == "__main__":
    main()
