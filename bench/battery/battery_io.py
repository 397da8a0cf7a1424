"""Readers for the battery's case files (bench/battery/make_battery.cpp writes them), shared by the
measuring scripts beside this file."""
import numpy as np


def read_off(path):
    """The points (n x 3) and faces (one row of corner indices each) of an OFF file."""
    toks = [t for line in open(path) for t in line.split('#')[0].split()]
    nv, nf = int(toks[1]), int(toks[2])
    points = np.array(toks[4:4 + 3 * nv], float).reshape(-1, 3)
    faces, i = [], 4 + 3 * nv
    for _ in range(nf):
        n = int(toks[i])
        faces.append([int(t) for t in toks[i + 1:i + 1 + n]])
        i += 1 + n
    return points, np.array(faces)


def read_curves(path):
    """The network's points of a .polylines.txt file, each once (shared and closing points)."""
    points = []
    for line in open(path):
        t = line.split('#')[0].split()
        if t:
            points.append(np.array(t[1:1 + 3 * int(t[0])], float).reshape(-1, 3))
    return np.unique(np.round(np.vstack(points), 12), axis=0)
