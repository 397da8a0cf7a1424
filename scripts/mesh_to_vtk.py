#!/usr/bin/python3
"""Converts a meshfit mesh (and optionally a curve network) into one legacy VTK file for f3d.

    mesh_to_vtk.py MESH OUT.vtk [--curves C.polylines.txt]
    mesh_to_vtk.py --camera FILE... (prints f3d camera options framing the files' points)

MESH is .off, .obj or .ply (ASCII or binary). The VTK file holds the triangles and the curves as
LINES, with a per-cell RGB array "rgb" (colour it with f3d's `--scalars=rgb --cells --comp=-2`).
Faces are coloured by region when the mesh has regions (PLY `patch_id`, OBJ `g region_<k>`), grey
otherwise. Lines are near-black: the mesh's own curve edges when it has some (PLY `edge` instances
flagged `curve`, OBJ `l`, or the file meshfit writes beside its outputs, MESH.curves.polylines.txt),
otherwise the polylines of the curve network given with --curves. Standard library only.
"""
import colorsys
import math
import os
import struct
import sys

FACE_GREY = (0.80, 0.80, 0.78)
CURVE_RGB = (0.05, 0.05, 0.05)


def fail(message):
    sys.stderr.write("mesh_to_vtk: %s\n" % message)
    sys.exit(1)


# ---------------------------------------------------------------------------------------------
# Readers: each returns (points, faces, face_region or None, edges)

def read_off(path):
    with open(path) as f:
        rows = [r.split() for r in (line.split("#", 1)[0] for line in f) if r.strip()]
    if not rows or not rows[0][0].endswith("OFF"):
        fail("%s: not an OFF file" % path)
    counts = rows[0][1:] if len(rows[0]) > 1 else rows[1]
    first = 1 if len(rows[0]) > 1 else 2
    nv, nf = int(counts[0]), int(counts[1])
    points = [tuple(float(t) for t in r[:3]) for r in rows[first:first + nv]]
    faces = [[int(t) for t in r[1:1 + int(r[0])]] for r in rows[first + nv:first + nv + nf]]
    if len(points) != nv or len(faces) != nf:
        fail("%s: truncated OFF file" % path)
    return points, faces, None, []


def read_obj(path):
    points, faces, regions, edges = [], [], [], []
    region = 0
    seen_group = False
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            key = parts[0]
            if key == "v":
                points.append(tuple(float(t) for t in parts[1:4]))
            elif key == "f":
                faces.append([int(t.split("/")[0]) - 1 for t in parts[1:]])
                regions.append(region)
            elif key == "g" and len(parts) > 1 and parts[1].startswith("region_"):
                region = int(parts[1][len("region_"):])
                seen_group = True
            elif key == "l":
                ids = [int(t.split("/")[0]) - 1 for t in parts[1:]]
                edges.extend(zip(ids, ids[1:]))
    return points, faces, regions if seen_group else None, edges


PLY_TYPES = {
    "char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h",
    "ushort": "H", "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I",
    "float": "f", "float32": "f", "double": "d", "float64": "d",
}


def read_ply(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        fail("%s: not a PLY file" % path)
    body_start = data.index(b"\n", end) + 1
    header = data[:end].decode("ascii", "replace").splitlines()
    fmt = None
    elements = []  # [name, count, [(prop_name, type, list_count_type or None)]]
    for line in header:
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "format":
            fmt = parts[1]
        elif parts[0] == "element":
            elements.append([parts[1], int(parts[2]), []])
        elif parts[0] == "property":
            if parts[1] == "list":
                elements[-1][2].append((parts[4], parts[3], parts[2]))
            else:
                elements[-1][2].append((parts[2], parts[1], None))
    records = {}
    if fmt == "ascii":
        tokens = data[body_start:].split()
        pos = 0

        def value(kind):
            nonlocal pos
            t = tokens[pos]
            pos += 1
            return float(t) if PLY_TYPES[kind] in "fd" else int(t)
    elif fmt in ("binary_little_endian", "binary_big_endian"):
        order = "<" if fmt == "binary_little_endian" else ">"
        pos = body_start

        def value(kind):
            nonlocal pos
            code = order + PLY_TYPES[kind]
            (v,) = struct.unpack_from(code, data, pos)
            pos += struct.calcsize(code)
            return v
    else:
        fail("%s: unsupported PLY format %s" % (path, fmt))
    # The same records from either encoding; only how a value is read differs.
    for name, count, props in elements:
        rows = []
        for _ in range(count):
            row = {}
            for pname, ptype, ltype in props:
                if ltype:
                    n = value(ltype)
                    row[pname] = [value(ptype) for _ in range(n)]
                else:
                    row[pname] = value(ptype)
            rows.append(row)
        records[name] = rows
    points = [(r["x"], r["y"], r["z"]) for r in records.get("vertex", [])]
    face_rows = records.get("face", [])
    faces = [r.get("vertex_indices", r.get("vertex_index")) for r in face_rows]
    regions = [r["patch_id"] for r in face_rows] if face_rows and "patch_id" in face_rows[0] else None
    # Only flagged edges are curves (CGAL's write_PLY lists every edge).
    edges = [(r["vertex1"], r["vertex2"]) for r in records.get("edge", []) if r.get("curve", 0)]
    return points, faces, regions, edges


def read_mesh(path):
    lower = path.lower()
    if lower.endswith(".off"):
        return read_off(path)
    if lower.endswith(".obj"):
        return read_obj(path)
    if lower.endswith(".ply"):
        return read_ply(path)
    fail("%s: unknown mesh extension (use .off, .obj or .ply)" % path)


def read_polylines(path):
    lines = []
    with open(path) as f:
        for number, line in enumerate(f, 1):
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            t = s.split()
            n = int(t[0])
            if len(t) != 1 + 3 * n:
                fail("%s:%d: expected %d points" % (path, number, n))
            lines.append([tuple(float(x) for x in t[1 + 3 * i:4 + 3 * i]) for i in range(n)])
    return lines


# ---------------------------------------------------------------------------------------------

def region_colour(k):
    """A distinct, fairly saturated colour for region k (golden-ratio hue steps)."""
    hue = (0.08 + 0.61803398875 * k) % 1.0
    sat = (0.8, 0.6, 0.95)[k % 3]
    val = (1.0, 0.9, 0.95)[(k // 3) % 3]
    return colorsys.hsv_to_rgb(hue, sat, val)


def write_vtk(out, points, faces, face_rgb, lines, line_rgb):
    with open(out, "w") as f:
        f.write("# vtk DataFile Version 3.0\nmeshfit\nASCII\nDATASET POLYDATA\n")
        f.write("POINTS %d double\n" % len(points))
        for p in points:
            f.write("%.9g %.9g %.9g\n" % p)
        if faces:
            f.write("POLYGONS %d %d\n" % (len(faces), sum(len(c) + 1 for c in faces)))
            for c in faces:
                f.write("%d %s\n" % (len(c), " ".join(map(str, c))))
        if lines:
            f.write("LINES %d %d\n" % (len(lines), sum(len(c) + 1 for c in lines)))
            for c in lines:
                f.write("%d %s\n" % (len(c), " ".join(map(str, c))))
        # VTK orders cell data as verts, lines, polys, strips
        f.write("CELL_DATA %d\nCOLOR_SCALARS rgb 3\n" % (len(faces) + len(lines)))
        for _ in lines:
            f.write("%.4f %.4f %.4f\n" % line_rgb)
        for rgb in face_rgb:
            f.write("%.4f %.4f %.4f\n" % rgb)


def convert(argv):
    if len(argv) not in (2, 4) or (len(argv) == 4 and argv[2] != "--curves"):
        fail("usage: mesh_to_vtk.py MESH OUT.vtk [--curves C.polylines.txt]")
    mesh, out = argv[0], argv[1]
    curves = argv[3] if len(argv) == 4 else None
    points, faces, regions, edges = read_mesh(mesh)
    # triangulate polygons as fans so every cell is a triangle
    tri, tri_region = [], []
    for index, c in enumerate(faces):
        for j in range(1, len(c) - 1):
            tri.append([c[0], c[j], c[j + 1]])
            tri_region.append(regions[index] if regions is not None else 0)
    if regions is not None:
        face_rgb = [region_colour(r) for r in tri_region]
    else:
        face_rgb = [FACE_GREY] * len(tri)
    points = list(points)
    lines = [[a, b] for a, b in edges]
    beside = mesh + ".curves.polylines.txt"
    if not lines and os.path.isfile(beside):
        for polyline in read_polylines(beside):
            first = len(points)
            points.extend(polyline)
            lines.append(list(range(first, len(points))))
        edges = lines
    if not lines and curves:
        for polyline in read_polylines(curves):
            first = len(points)
            points.extend(polyline)
            lines.append(list(range(first, len(points))))
    write_vtk(out, points, tri, face_rgb, lines, CURVE_RGB)
    sys.stderr.write("mesh_to_vtk: %s: %d points, %d triangles, %d lines (%s)%s\n" % (
        out, len(points), len(tri), len(lines),
        "the mesh's curve edges" if edges else "curve polylines",
        ", %d regions" % len(set(tri_region)) if regions is not None else ""))


def camera(paths):
    """Prints f3d options for a camera looking at all the files' points from the front-left,
    above, with +Z up: the same for every stage, so the pictures line up."""
    lo = [math.inf] * 3
    hi = [-math.inf] * 3
    for path in paths:
        if path.endswith(".polylines.txt"):
            pts = [p for line in read_polylines(path) for p in line]
        else:
            pts = read_mesh(path)[0]
        for p in pts:
            for k in range(3):
                lo[k] = min(lo[k], p[k])
                hi[k] = max(hi[k], p[k])
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    radius = 0.5 * math.sqrt(sum((b - a) ** 2 for a, b in zip(lo, hi)))
    direction = (-0.3, -0.8, 0.75)
    norm = math.sqrt(sum(d * d for d in direction))
    view_angle = 30.0
    distance = 0.78 * radius / math.sin(math.radians(view_angle / 2))
    position = [c + distance * d / norm for c, d in zip(centre, direction)]
    print("--camera-position=%.6g,%.6g,%.6g --camera-focal-point=%.6g,%.6g,%.6g "
          "--camera-view-up=0,0,1 --camera-view-angle=%g" % (tuple(position) + tuple(centre) +
                                                             (view_angle,)))


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--camera":
        camera(sys.argv[2:])
    else:
        convert(sys.argv[1:])


if __name__ == "__main__":
    main()
