#!/usr/bin/env python3
"""Writes rbf_reference.txt: an independent reference for meshfit's RBF interpolant.

SciPy's RBFInterpolator(kernel=K, degree=1) solves the same problem as meshfit's
Rbf_interpolant (phi(r) = r or r^3 with an affine term and the matching side conditions), so the
two must agree to rounding. Run with Debian's python3-scipy:  python3 make_rbf_reference.py
The output is committed; the test reads it (test/rbf_test.cpp).
"""
import numpy as np
from scipy.interpolate import RBFInterpolator

rng = np.random.default_rng(2026)
n, m = 60, 200
centres = rng.uniform(-1, 1, size=(n, 3)) * np.array([2.0, 1.0, 0.5]) + np.array([10.0, -3.0, 0.25])
values = np.column_stack([
    centres[:, 0] + 0.3 * np.sin(2 * centres[:, 1]),
    1.2 * centres[:, 1] + 0.2 * centres[:, 2] * centres[:, 0],
    centres[:, 2] - 0.1 * centres[:, 0] ** 2,
])
queries = rng.uniform(-1.2, 1.2, size=(m, 3)) * np.array([2.0, 1.0, 0.5]) + np.array([10.0, -3.0, 0.25])

with open("rbf_reference.txt", "w") as out:
    out.write("# meshfit RBF reference from scipy %s RBFInterpolator(degree=1)\n" % __import__("scipy").__version__)
    out.write("# sections: centres n, then per kernel: kernel name m, queries and results (x y z qx qy qz)\n")
    out.write("centres %d\n" % n)
    for c, v in zip(centres, values):
        out.write("%.17g %.17g %.17g %.17g %.17g %.17g\n" % (*c, *v))
    for kernel in ("linear", "cubic"):
        f = RBFInterpolator(centres, values, kernel=kernel, degree=1)
        res = f(queries)
        out.write("kernel %s %d\n" % (kernel, m))
        for q, r in zip(queries, res):
            out.write("%.17g %.17g %.17g %.17g %.17g %.17g\n" % (*q, *r))
