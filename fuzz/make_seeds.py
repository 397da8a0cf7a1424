#!/usr/bin/env python3
"""Writes the seed corpora of the fuzz targets into fuzz/corpus/<target>/ (committed)."""
import os
import random
import struct

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.dirname(here)


def put(target, name, data):
    d = os.path.join(here, "corpus", target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


octa_v = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
octa_f = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]

off = "OFF\n6 8 0\n" + "".join("%g %g %g\n" % v for v in octa_v) + "".join("3 %d %d %d\n" % f for f in octa_f)
put("off", "octahedron.off", off)
put("off", "coff_quad.off", "COFF\n4 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n0 1 0 9 9 9 255\n4 0 1 2 3\n")
put("off", "crlf_bom.off", "\ufeffOFF\r\n# c\r\n3 1 0\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n")
put("off", "truncated.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n")
put("off", "absurd.off", "OFF\n2000000000 1 0\n0 0 0\n")

obj = "".join("v %g %g %g\n" % v for v in octa_v) + "g region_1\n" + "".join(
    "f %d %d %d\n" % tuple(i + 1 for i in f) for f in octa_f[:4]) + "g region_2\n" + "".join(
    "f %d/1/1 %d//2 %d\n" % tuple(i + 1 for i in f) for f in octa_f[4:]) + "l 1 3 2\n"
put("obj", "octahedron_regions.obj", obj)
put("obj", "negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf -4 -3 -2\nf -3 -1 -2\n")
put("obj", "zero_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n")

ply = ("ply\nformat ascii 1.0\nelement vertex 6\nproperty double x\nproperty double y\nproperty double z\n"
       "element face 8\nproperty list uchar int vertex_indices\nproperty int patch_id\n"
       "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n"
       + "".join("%g %g %g\n" % v for v in octa_v) + "".join("3 %d %d %d %d\n" % (*f, i % 2) for i, f in enumerate(octa_f))
       + "0 2\n")
put("ply", "octahedron_ascii.ply", ply)
hdr = ("ply\nformat binary_little_endian 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 8\nproperty list uchar int vertex_indices\nend_header\n").encode()
body = b"".join(struct.pack("<3f", *v) for v in octa_v) + b"".join(struct.pack("<B3i", 3, *f) for f in octa_f)
put("ply", "octahedron_le.ply", hdr + body)
hdr_be = hdr.replace(b"binary_little_endian", b"binary_big_endian")
body_be = b"".join(struct.pack(">3f", *v) for v in octa_v) + b"".join(struct.pack(">B3i", 3, *f) for f in octa_f)
put("ply", "octahedron_be.ply", hdr_be + body_be)
# Issue 14: only edges flagged `curve` are curve edges (an unflagged list, as CGAL writes, is skipped).
put("ply", "octahedron_flagged_edges.ply", ply.replace("property int vertex2\nend_header", "property int vertex2\nproperty uchar curve\nend_header").replace("\n0 2\n", "\n0 2 1\n"))
put("ply", "property_first.ply", "ply\nformat ascii 1.0\nproperty float x\nelement vertex 0\nend_header\n")

stl = "solid o\n"
for f in octa_f:
    stl += "facet normal 0 0 0\nouter loop\n" + "".join("vertex %g %g %g\n" % octa_v[i] for i in f) + "endloop\nendfacet\n"
stl += "endsolid o\n"
put("stl", "octahedron_ascii.stl", stl)
put("stl", "octahedron_binary.stl", b"\0" * 80 + struct.pack("<I", 8) + b"".join(
    struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *octa_v[i]) for i in f) + b"\0\0" for f in octa_f))

with open(os.path.join(root, "examples", "data", "curves.polylines.txt")) as f:
    put("polylines", "example.polylines.txt", f.read())
put("polylines", "star.polylines.txt", "# star\n2 0 0 0 1 0 0\n2 0 0 0 0 1 0\n2 0 0 0 0 0 1\n3 1 0 0 0 1 0 0 0 1\n")
put("polylines", "near.polylines.txt", "2 0 0 0 1 0 0\n2 1.0000000000001 0 0 1 1 0\n")

put("correspondences", "pairs.txt", "# pairs\n0 0 0 0\n1 1 0 0\n2 0 1 0\n4 0 0 1\n")
put("correspondences", "coplanar.txt", "0 0 0 0\n1 1 0 0\n2 0 1 0\n3 1 1 1\n")
put("correspondences", "by_index.txt", "# network vertices by index, mixed with a point\n0 @0\n1 @1\n2 0 1 0\n4 @3\n5 @99\n")

curves = "4 0 0 0 1 0 0 0 1 0 0 0 0\n2 0 0 0 0 0 1\n"
put("check", "valid.txt", off + "@@\n" + curves + "@@\n" + "0 0 0 0\n1 1 0 0\n2 0 1 0\n4 0 0 1\n")
put("check", "bad_pairs.txt", off + "@@\n" + curves + "@@\n" + "0 0 0 0\n0 1 0 0\n")

rng = random.Random(1)
for t, n in (("flip", 18), ("rbf", 80), ("deform", 60)):
    for k in range(8):
        b = bytes(rng.randrange(256) for _ in range(n))
        put(t, "random_%d" % k, b)
        if t == "deform":  # the fit target decodes its input as the deform target does
            put("fit", "random_%d" % k, b)
