#!/usr/bin/python3
"""Where a fit's distance to the truth comes from, on a battery case (bench/battery).

  bench/battery/error_profile.py CASE_DIR [OUTPUT.off]

CASE_DIR is a case written by make_battery (template.off, truth.off, curves.polylines.txt). Prints:
- for real-* cases (truth = the template's vertices deformed, same connectivity): the bound that
  exact correspondences would give. Every network point is mapped back onto the template through
  the barycentric coordinates of its truth face, and an RBF (phi(r)=r, thin-plate spline; both
  with an affine part) through those pairs moves the template; the largest vertex error against
  the truth, in % of the truth's bounding-box diagonal.
- with OUTPUT.off (a fit of the case): its two-sided sampled distance to the truth, and the mean and
  95th percentile of that distance by distance from the curves.
Needs Debian's python3-numpy and python3-scipy. A measuring tool, not a test.
"""
import sys
import numpy as np
from scipy.interpolate import RBFInterpolator
from scipy.spatial import cKDTree

from battery_io import read_curves, read_off


def sample(points, faces, n=200000, seed=0):
    rng = np.random.default_rng(seed)
    a, b, c = points[faces[:, 0]], points[faces[:, 1]], points[faces[:, 2]]
    area = np.linalg.norm(np.cross(b - a, c - a), axis=1)
    f = rng.choice(len(faces), n, p=area / area.sum())
    s, t = np.sqrt(rng.random(n)), rng.random(n)
    return a[f] * (1 - s)[:, None] + b[f] * (s * (1 - t))[:, None] + c[f] * (s * t)[:, None]


def barycentric_on(points, faces, tree, p):
    """The face of `points` nearest to p among 16 candidates, and p's clamped barycentric coordinates."""
    best = None
    for f in tree.query(p, k=16)[1]:
        a, b, c = points[faces[f]]
        v0, v1, v2 = b - a, c - a, p - a
        d00, d01, d11, d20, d21 = v0 @ v0, v0 @ v1, v1 @ v1, v2 @ v0, v2 @ v1
        den = d00 * d11 - d01 * d01
        if den <= 0:
            continue
        v, w = (d11 * d20 - d01 * d21) / den, (d00 * d21 - d01 * d20) / den
        bc = np.clip([1 - v - w, v, w], 0, 1)
        bc /= bc.sum()
        dist = np.linalg.norm(bc @ points[faces[f]] - p)
        if best is None or dist < best[0]:
            best = (dist, f, bc)
    return best[1], best[2]


def main():
    case = sys.argv[1]
    template, tfaces = read_off(case + '/template.off')
    truth, faces = read_off(case + '/truth.off')
    curves = read_curves(case + '/curves.polylines.txt')
    diag = np.linalg.norm(truth.max(0) - truth.min(0))
    if len(template) == len(truth) and np.array_equal(tfaces, faces):
        tree = cKDTree(truth[faces].mean(1))
        pre = []
        for p in curves:
            f, bc = barycentric_on(truth, faces, tree, p)
            pre.append(bc @ template[faces[f]])
        pre = np.array(pre)
        for kernel in ('linear', 'thin_plate_spline'):
            moved = template + RBFInterpolator(pre, curves - pre, kernel=kernel, degree=1)(template)
            err = np.linalg.norm(moved - truth, axis=1)
            print('exact correspondences, %-17s largest vertex error %.2f %% of the diagonal' % (kernel + ':', 100 * err.max() / diag))
    if len(sys.argv) > 2:
        out, ofaces = read_off(sys.argv[2])
        so, st = sample(out, ofaces), sample(truth, faces, seed=1)
        d_out, d_truth = cKDTree(st).query(so)[0], cKDTree(so).query(st)[0]
        print('output: largest distance %.3f %% (output to truth), %.3f %% (truth to output)' %
              (100 * d_out.max() / diag, 100 * d_truth.max() / diag))
        near = cKDTree(curves).query(so)[0] / diag * 100
        for lo, hi in ((0, 2), (2, 5), (5, 10), (10, 20), (20, 100)):
            m = (near >= lo) & (near < hi)
            if m.any():
                print('  %2d-%3d %% from the curves: %6d samples, mean %.2f %%, 95th percentile %.2f %%' %
                      (lo, hi, m.sum(), 100 * d_out[m].mean() / diag, 100 * np.percentile(d_out[m], 95) / diag))


if __name__ == '__main__':
    main()
