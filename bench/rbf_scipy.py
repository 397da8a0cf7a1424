#!/usr/bin/env python3
"""Reference side of the RBF benchmark: generates the data sets and times SciPy's RBFInterpolator.

  rbf_scipy.py generate <dir> <n> <m>     writes centres_<n>.bin, values_<n>.bin, points_<m>.bin
  rbf_scipy.py run <dir> <n> <m> <kernel> times fit + evaluate, writes scipy_<n>_<m>.bin, prints a line
  rbf_scipy.py compare <dir> <n> <m>      prints the largest difference between the two results
"""
import sys
import time

import numpy as np


def generate(d, n, m):
    rng = np.random.default_rng(20261122 + n)
    # Centres on a bumpy sphere (template vertices), values moved onto an ellipsoid-like shape.
    c = rng.normal(size=(n, 3))
    c /= np.linalg.norm(c, axis=1)[:, None]
    c *= (1 + 0.1 * np.sin(3 * c[:, :1]))
    v = c * np.array([2.0, 0.8, 0.7]) + 0.05 * np.sin(5 * c[:, [1, 2, 0]])
    p = rng.normal(size=(m, 3))
    p /= np.linalg.norm(p, axis=1)[:, None]
    p *= rng.uniform(0.9, 1.1, size=(m, 1))
    c.astype('<f8').tofile(f"{d}/centres_{n}.bin")
    v.astype('<f8').tofile(f"{d}/values_{n}.bin")
    rng2 = np.random.default_rng(7 + m)
    p = rng2.normal(size=(m, 3))
    p /= np.linalg.norm(p, axis=1)[:, None]
    p *= rng2.uniform(0.9, 1.1, size=(m, 1))
    p.astype('<f8').tofile(f"{d}/points_{m}.bin")


def load(path):
    return np.fromfile(path, dtype='<f8').reshape(-1, 3)


def run(d, n, m, kernel):
    from scipy.interpolate import RBFInterpolator
    c, v, p = load(f"{d}/centres_{n}.bin"), load(f"{d}/values_{n}.bin"), load(f"{d}/points_{m}.bin")
    t0 = time.perf_counter()
    f = RBFInterpolator(c, v, kernel=kernel, degree=1)
    fit = time.perf_counter() - t0
    t0 = time.perf_counter()
    out = f(p)
    ev = time.perf_counter() - t0
    out.astype('<f8').tofile(f"{d}/scipy_{n}_{m}.bin")
    print(f"scipy n={n} m={m} fit_s={fit:.3f} eval_s={ev:.3f}")


def compare(d, n, m):
    a, b = load(f"{d}/scipy_{n}_{m}.bin"), load(f"{d}/meshfit_{n}_{m}.bin")
    scale = np.abs(a).max()
    print(f"diff n={n} m={m} max_abs={np.abs(a - b).max():.3e} max_rel={np.abs(a - b).max() / scale:.3e}")


def blas():
    try:
        from threadpoolctl import threadpool_info
        return ",".join(f"{i['internal_api']}:{i.get('filepath','').split('/')[-1]}" for i in threadpool_info())
    except ImportError:
        import io
        import contextlib
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf):
            np.show_config()
        lines = [ln.strip() for ln in buf.getvalue().splitlines() if 'libraries' in ln or 'name' in ln]
        return " ".join(lines[:4])


if __name__ == "__main__":
    cmd = sys.argv[1]
    if cmd == "generate":
        generate(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))
    elif cmd == "run":
        run(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), sys.argv[5])
    elif cmd == "compare":
        compare(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))
    elif cmd == "blas":
        print(blas())
