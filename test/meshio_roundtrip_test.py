#!/usr/bin/env python3
"""meshfit's outputs read by another program's readers (issue 14).

Fits the embedded example once per output format (.ply, .obj, .vtk, .vtp) and reads every output
back with meshio (Debian python3-meshio; .vtp, which meshio 5 does not read, with Python's XML
parser), checking counts and regions against the run's report, and the curve edges written beside
the output (<output>.curves.polylines.txt) against the mesh's vertices and the VTK lines.

Exit status: 0 all checks passed, 1 a check failed, 77 meshio is missing (SKIPPED).
usage: meshio_roundtrip_test.py --meshfit BIN --data EXAMPLE_DIR --work DIR
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

try:
    import meshio
except ImportError:
    print("SKIPPED: meshio is not installed (Debian python3-meshio; scripts/install-deps.sh installs it)")
    sys.exit(77)

failures = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        failures.append(what)


def read_polylines(path):
    chains = []
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t or t[0].startswith("#"):
                continue
            n = int(t[0])
            v = [float(x) for x in t[1:]]
            assert len(v) == 3 * n, "%s: a chain of %d points has %d coordinates" % (path, n, len(v))
            chains.append([tuple(v[3 * i:3 * i + 3]) for i in range(n)])
    return chains


def cells_of(mesh, kind):
    return sum(len(b.data) for b in mesh.cells if b.type == kind)


def cell_values(mesh, name, kind):
    out = []
    for block, values in zip(mesh.cells, mesh.cell_data[name]):
        if block.type == kind:
            out.extend(int(x) for x in values)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--meshfit", required=True)
    ap.add_argument("--data", required=True)
    ap.add_argument("--work", required=True)
    a = ap.parse_args()
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    inputs = ["--template", os.path.join(a.data, "template.off"), "--curves",
              os.path.join(a.data, "curves.polylines.txt"), "--correspondences", os.path.join(a.data, "pairs.txt")]
    reports = {}
    for ext in ("ply", "obj", "vtk", "vtp"):
        out = os.path.join(a.work, "fit." + ext)
        r = subprocess.run([a.meshfit, "fit", "--quiet"] + inputs + ["--output", out, "--report", out + ".json"],
                           capture_output=True, text=True)
        check(r.returncode == 0, "fit to .%s exits 0 (%s)" % (ext, r.stderr.strip()))
        if r.returncode != 0:
            return
        with open(out + ".json") as f:
            reports[ext] = json.load(f)
        check(os.path.exists(out + ".curves.polylines.txt"), ".%s: curve edges written beside the output" % ext)
    rep = reports["ply"]
    vertices, faces, regions = rep["quality"]["vertices"], rep["quality"]["faces"], rep["counts"]["regions"]
    check(regions == 12, "the report counts 12 regions (%d)" % regions)

    # .ply: patch_id per face, no edge element.
    ply = meshio.read(os.path.join(a.work, "fit.ply"))
    check(len(ply.points) == vertices, ".ply: meshio reads %d vertices (report: %d)" % (len(ply.points), vertices))
    check(cells_of(ply, "triangle") == faces, ".ply: meshio reads %d triangles (report: %d)" % (cells_of(ply, "triangle"), faces))
    check("patch_id" in ply.cell_data, ".ply: meshio finds the face property patch_id")
    if "patch_id" in ply.cell_data:
        patch = cell_values(ply, "patch_id", "triangle")
        check(len(patch) == faces and len(set(patch)) == regions,
              ".ply: patch_id on every face, %d distinct values" % len(set(patch)))
        # The region's colour beside patch_id (what f3d shows): one per region, each different.
        rgb = ("red", "green", "blue")
        check(all(c in ply.cell_data for c in rgb), ".ply: meshio finds the face properties red green blue")
        if all(c in ply.cell_data for c in rgb):
            colours = list(zip(*(cell_values(ply, c, "triangle") for c in rgb)))
            by_region = {}
            for p, c in zip(patch, colours):
                by_region.setdefault(p, set()).add(c)
            check(all(len(s) == 1 for s in by_region.values()) and
                  len(set(min(s) for s in by_region.values())) == regions,
                  ".ply: one face colour per region, %d different" % len(set(min(s) for s in by_region.values())))

    # .obj: readable (no l lines), same triangles.
    obj = meshio.read(os.path.join(a.work, "fit.obj"))
    check(len(obj.points) == vertices and cells_of(obj, "triangle") == faces,
          ".obj: meshio reads %d vertices, %d triangles" % (len(obj.points), cells_of(obj, "triangle")))

    # The curve edges beside the .ply: their points are mesh vertices (exactly).
    chains = read_polylines(os.path.join(a.work, "fit.ply.curves.polylines.txt"))
    curve_edges = sum(len(c) - 1 for c in chains)
    points = set(tuple(float(x) for x in p) for p in ply.points)
    check(all(p in points for c in chains for p in c), "curves beside the .ply: every point is a mesh vertex")
    check(curve_edges >= 220, "curves beside the .ply: %d curve edges in %d chains" % (curve_edges, len(chains)))

    # .vtk: triangles with their region, curve edges as lines flagged curve.
    vtk = meshio.read(os.path.join(a.work, "fit.vtk"))
    check(cells_of(vtk, "triangle") == faces, ".vtk: meshio reads %d triangles" % cells_of(vtk, "triangle"))
    check(cells_of(vtk, "line") == curve_edges,
          ".vtk: %d lines, as many as the curve edges beside the .ply (%d)" % (cells_of(vtk, "line"), curve_edges))
    check("region" in vtk.cell_data and "curve" in vtk.cell_data, ".vtk: cell data region and curve")
    if "region" in vtk.cell_data and "curve" in vtk.cell_data:
        check(len(set(cell_values(vtk, "region", "triangle"))) == regions, ".vtk: %d regions on the triangles" % regions)
        check(set(cell_values(vtk, "curve", "line")) == {1} and set(cell_values(vtk, "curve", "triangle")) == {0},
              ".vtk: curve is 1 on lines, 0 on triangles")
        if "patch_id" in ply.cell_data:
            check(cell_values(vtk, "region", "triangle") == cell_values(ply, "patch_id", "triangle"),
                  ".vtk: the same region per face as the .ply's patch_id")

    # .vtp (VTK XML PolyData): parsed here, as meshio 5 has no reader for it.
    piece = ET.parse(os.path.join(a.work, "fit.vtp")).getroot().find("PolyData/Piece")
    check(int(piece.get("NumberOfPoints")) == vertices and int(piece.get("NumberOfPolys")) == faces and
          int(piece.get("NumberOfLines")) == curve_edges, ".vtp: points, polygons and lines counted")
    arrays = {d.get("Name"): [int(x) for x in d.text.split()] for d in piece.find("CellData")}
    nl = int(piece.get("NumberOfLines"))
    check(len(arrays.get("region", [])) == nl + faces and len(set(arrays["region"][nl:])) == regions,
          ".vtp: a region per cell, %d on the polygons" % regions)
    check(arrays.get("curve", [])[:nl] == [1] * nl and set(arrays["curve"][nl:]) == {0}, ".vtp: curve flags")
    conn = [int(x) for x in piece.find("Polys/DataArray[@Name='connectivity']").text.split()]
    check(len(conn) == 3 * faces and max(conn) < vertices, ".vtp: triangle connectivity in range")

    # A template with texture coordinates and normals (an OBJ written here): the .vtk's point data
    # TCoords and Normals hold them on the template's vertices, exactly, and values for the others.
    template = meshio.read(os.path.join(a.data, "template.off"))
    uvs = [(0.5 + 0.5 * p[0], 0.25 - 0.5 * p[2]) for p in template.points]
    with open(os.path.join(a.work, "template.obj"), "w") as f:
        f.writelines("v %r %r %r\n" % tuple(float(x) for x in p) for p in template.points)
        f.writelines("vt %r %r\n" % uv for uv in uvs)
        f.writelines("vn %r %r %r\n" % tuple(float(x) for x in p) for p in template.points)
        for t in template.cells_dict["triangle"]:
            f.write("f " + " ".join("%d/%d/%d" % (v + 1, v + 1, v + 1) for v in t) + "\n")
    out = os.path.join(a.work, "attributes.vtk")
    inputs[1] = os.path.join(a.work, "template.obj")
    r = subprocess.run([a.meshfit, "fit", "--quiet"] + inputs + ["--output", out], capture_output=True, text=True)
    check(r.returncode == 0, "fit of a template with attributes to .vtk exits 0 (%s)" % r.stderr.strip())
    att = meshio.read(out)
    nt = len(template.points)
    check("TCoords" in att.point_data and "Normals" in att.point_data, ".vtk: point data TCoords and Normals")
    if "TCoords" in att.point_data and "Normals" in att.point_data:
        tc, nn = att.point_data["TCoords"], att.point_data["Normals"]
        check(tc.shape == (len(att.points), 2) and nn.shape == (len(att.points), 3), ".vtk: one value per vertex")
        check([tuple(x) for x in tc[:nt]] == uvs, ".vtk: the template's texture coordinates, exactly")
        check((nn[:nt] == template.points).all(), ".vtk: the template's normals, exactly")
        check(len(att.points) > nt and all(abs(sum(c * c for c in n) - 1) < 1e-9 for n in nn[nt:]),
              ".vtk: unit normals on the %d added vertices" % (len(att.points) - nt))


if __name__ == "__main__":
    main()
    print("%d failures" % len(failures))
    sys.exit(1 if failures else 0)
