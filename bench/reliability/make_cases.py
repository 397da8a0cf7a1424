#!/usr/bin/env python3
"""Generates the hostile inputs of issue 13 (reliability) from examples/data.

    make_cases.py EXAMPLES_DIR OUT_DIR [--sweep] [--big]

Writes one folder per input set under OUT_DIR (template.off, curves.polylines.txt, pairs.txt).
--sweep adds the scaled copies of every example (1e-150 ... 1e150 by decades); --big adds the
5.8 M-point polyline and the 62 MB line with a wrong count (slow to write, ~120 MB).
Standard library only.
"""
import math
import os
import shutil
import sys


def read_off(path):
    with open(path) as f:
        words = [w for line in f for w in (line.split('#')[0].split())]
    assert words[0] == 'OFF'
    nv, nf = int(words[1]), int(words[2])
    vals = words[4:]
    pts = [tuple(float(vals[3 * i + k]) for k in range(3)) for i in range(nv)]
    rest = vals[3 * nv:]
    faces, i = [], 0
    for _ in range(nf):
        n = int(rest[i])
        faces.append([int(x) for x in rest[i + 1:i + 1 + n]])
        i += 1 + n
    return pts, faces


def write_off(path, pts, faces):
    with open(path, 'w') as f:
        f.write('OFF\n%d %d 0\n' % (len(pts), len(faces)))
        for p in pts:
            f.write('%r %r %r\n' % p)
        for fc in faces:
            f.write('%d %s\n' % (len(fc), ' '.join(map(str, fc))))


def records(path):
    """The tokens of each line of a text input that is neither blank nor a comment."""
    with open(path) as f:
        for line in f:
            t = line.split()
            if t and not t[0].startswith('#'):
                yield t


def read_polylines(path):
    return [[tuple(float(t[1 + 3 * i + k]) for k in range(3)) for i in range(int(t[0]))] for t in records(path)]


def write_polylines(path, polys):
    with open(path, 'w') as f:
        for pl in polys:
            f.write('%d %s\n' % (len(pl), ' '.join('%r %r %r' % p for p in pl)))


def read_pairs(path):
    return [(int(t[0]), (float(t[1]), float(t[2]), float(t[3]))) for t in records(path)]


def write_pairs(path, pairs):
    with open(path, 'w') as f:
        for i, p in pairs:
            f.write('%d %r %r %r\n' % ((i,) + tuple(p)))


def emit(out, name, pts, faces, polys, pairs):
    d = os.path.join(out, name)
    os.makedirs(d, exist_ok=True)
    if pts is not None:
        write_off(os.path.join(d, 'template.off'), pts, faces)
    write_polylines(os.path.join(d, 'curves.polylines.txt'), polys)
    write_pairs(os.path.join(d, 'pairs.txt'), pairs)


def mapped(f, pts, polys, pairs, template=True):
    return ([f(p) for p in pts] if template else pts, [[f(p) for p in pl] for pl in polys],
            [(i, f(p)) for i, p in pairs])


def main():
    ex, out = sys.argv[1], sys.argv[2]
    flags = set(sys.argv[3:])
    pts, faces = read_off(os.path.join(ex, 'template.off'))
    polys = read_polylines(os.path.join(ex, 'curves.polylines.txt'))
    pairs = read_pairs(os.path.join(ex, 'pairs.txt'))

    def scaled(s):
        return lambda p: (p[0] * s, p[1] * s, p[2] * s)

    # Extreme coordinates.
    # 4.7e99 and 2.9e-101 put the example at the edges of the supported range (|x| <= 1e100,
    # bounding-box diagonal >= 1e-100).
    for s in ('1e150', '1e-150', '1e200', '1e-200', '4.7e99', '2.9e-101', '1e101', '1e-101'):
        t, c, q = mapped(scaled(float(s)), pts, polys, pairs)
        emit(out, 'scale' + s, t, faces, c, q)
    t, c, q = mapped(scaled(1e150), pts, polys, pairs, template=False)
    emit(out, 'curves-scale1e150', t, faces, c, q)
    # Runaway work: a 3-point polyline at x = 1000 that no pair uses.
    emit(out, 'far-polyline', pts, faces, polys + [[(1000, 0, 0), (1000, 1, 0), (1000, 0, 1)]], pairs)
    # Runaway work: 300 000 segments from one point (a feature point of that degree), with the
    # example's pairs' template vertices on four of the spokes' ends.
    n = 300000
    star = [[(0.0, 0.0, 0.0), (math.cos(2 * math.pi * k / n), math.sin(2 * math.pi * k / n), 0.5)] for k in range(n)]
    emit(out, 'star', pts, faces, star, [(i, star[k][1]) for i, k in zip(range(4), (0, n // 4, n // 2, 3 * n // 4))])
    # Memory: every segment cut into 70 pieces (about 15 000 network vertices).
    fine = []
    for pl in polys:
        q = [pl[0]]
        for a, b in zip(pl, pl[1:]):
            for k in range(1, 70):
                u = k / 70.0
                q.append(tuple(a[j] + u * (b[j] - a[j]) for j in range(3)))
            q.append(b)
        fine.append(q)
    emit(out, 'dense70', pts, faces, fine, pairs)
    # No report on exit 3: mirrored pairs, pairs rotated 180 degrees, nearly coplanar pairs.
    t, c, q = mapped(lambda p: (-p[0], p[1], p[2]), pts, polys, pairs, template=False)
    emit(out, 'mirrored', t, faces, c, q)
    # Pairs rotated: each template vertex paired with the point of the pair half the list away.
    emit(out, 'rotated180', pts, faces, polys,
         [(pairs[k][0], pairs[(k + len(pairs) // 2) % len(pairs)][1]) for k in range(len(pairs))])
    t, c, q = mapped(lambda p: (p[0], p[1], p[2] * 1e-7), pts, polys, pairs, template=False)
    emit(out, 'nearly-coplanar', t, faces, c, q)
    # Unused vertices: every vertex repeated once, the copies unused.
    emit(out, 'unused-copies', pts + pts, faces, polys, pairs)
    # A polyline count of 2^64 - 1.
    d = os.path.join(out, 'count2e64')
    emit(out, 'count2e64', pts, faces, polys, pairs)
    with open(os.path.join(d, 'curves.polylines.txt'), 'a') as f:
        f.write('18446744073709551615 0 0 0\n')
    # A pair that is not a network vertex (the message shows the tolerance).
    emit(out, 'pair-off-network', pts, faces, polys, pairs[:-1] + [(pairs[-1][0], (1e-13, 0.5, 0.5))])

    if '--sweep' in flags:
        sets = [('example', 'template.off', 'curves.polylines.txt', 'pairs.txt'),
                ('peanut', 'template.off', 'curves-2.polylines.txt', 'pairs-2.txt'),
                ('sheet', 'sheet/template.off', 'sheet/curves.polylines.txt', 'sheet/pairs.txt')]
        for name, tp, cp, pp in sets:
            P, F = read_off(os.path.join(ex, tp))
            C = read_polylines(os.path.join(ex, cp))
            Q = read_pairs(os.path.join(ex, pp))
            for e in range(-150, 151, 10):
                t, c, q = mapped(scaled(float('1e%d' % e)), P, C, Q)
                emit(os.path.join(out, 'sweep'), '%s-1e%d' % (name, e), t, F, c, q)

    if '--big' in flags:
        n = 5800000
        d = os.path.join(out, 'big-polyline')
        os.makedirs(d, exist_ok=True)
        write_off(os.path.join(d, 'template.off'), pts, faces)
        ring = [(1.2 * math.cos(2 * math.pi * k / n), 1.2 * math.sin(2 * math.pi * k / n), 0.3 * math.sin(6 * math.pi * k / n))
                for k in range(n)]
        ring.append(ring[0])
        with open(os.path.join(d, 'curves.polylines.txt'), 'w') as f:
            f.write('%d ' % len(ring))
            f.write(' '.join('%.9g %.9g %.9g' % p for p in ring))
            f.write('\n')
        write_pairs(os.path.join(d, 'pairs.txt'),
                    [(0, ring[0]), (1, ring[n // 4]), (2, ring[n // 2]), (3, ring[3 * n // 4]), (4, ring[n // 8])])
        d2 = os.path.join(out, 'big-wrong-count')
        os.makedirs(d2, exist_ok=True)
        # The same template and pairs, so that the run reaches the curve file (and fails there).
        for name in ('template.off', 'pairs.txt'):
            shutil.copyfile(os.path.join(d, name), os.path.join(d2, name))
        with open(os.path.join(d, 'curves.polylines.txt')) as src, \
                open(os.path.join(d2, 'curves.polylines.txt'), 'w') as dst:
            line = src.readline()
            head, tail = line.split(' ', 1)
            dst.write('%d %s' % (int(head) + 1, tail))


main()
