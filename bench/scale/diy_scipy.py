#!/usr/bin/env python3
"""What a do-it-yourself user gets with SciPy (issue 12's peer): the thesis's two RBF levels only.

  diy_scipy.py CASE_DIR

Coarse: scipy.interpolate.RBFInterpolator (kernel r, degree 1) through the user's pairs moves the
template. Fine: each network vertex is paired with its nearest template vertex (scipy's cKDTree,
first come keeps it, the user's pairs kept), an RBF through all the pairs moves the template onto
them. No flip prevention, no partition, no smoothing, nothing verified. Prints one line:
"seconds S peak_mb M centres N" (reading excluded).
"""
import resource
import sys
import time

import numpy as np
from scipy.interpolate import RBFInterpolator
from scipy.spatial import cKDTree


def read_off(path):
    with open(path) as f:
        tokens = [t for line in f for t in line.split('#', 1)[0].split()]
    start = 1 if tokens[0] == 'OFF' else 0
    nv = int(tokens[start])
    body = np.array(tokens[start + 3:start + 3 + 3 * nv], dtype=float)
    return body.reshape(-1, 3)


def read_network(path):
    points = []
    with open(path) as f:
        for line in f:
            s = line.split('#', 1)[0].split()
            if not s:
                continue
            n = int(s[0])
            points.extend(tuple(map(float, s[1 + 3 * i:4 + 3 * i])) for i in range(n))
    return np.unique(np.array(points), axis=0)


def read_pairs(path):
    idx, pts = [], []
    with open(path) as f:
        for line in f:
            s = line.split('#', 1)[0].split()
            if not s:
                continue
            idx.append(int(s[0]))
            pts.append(tuple(map(float, s[1:4])))
    return np.array(idx), np.array(pts)


def main(case):
    v = read_off(f"{case}/template.off")
    net = read_network(f"{case}/curves.polylines.txt")
    pi, pt = read_pairs(f"{case}/pairs.txt")
    t0 = time.perf_counter()
    coarse = RBFInterpolator(v[pi], pt, kernel='linear', degree=1)
    w = coarse(v)
    w[pi] = pt
    _, nearest = cKDTree(w).query(net)
    taken = {int(i) for i in pi}
    src, dst = list(w[pi]), list(pt)
    for k, i in enumerate(nearest):
        if int(i) not in taken:
            taken.add(int(i))
            src.append(w[i])
            dst.append(net[k])
    src, dst = np.array(src), np.array(dst)
    fine = RBFInterpolator(src, dst - src, kernel='linear', degree=1)
    w = w + fine(w)
    seconds = time.perf_counter() - t0
    assert np.isfinite(w).all()
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"seconds {seconds:.2f} peak_mb {peak:.0f} centres {len(src)}")


if __name__ == '__main__':
    main(sys.argv[1])
