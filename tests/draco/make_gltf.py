#!/usr/bin/env python3
"""Writes tests/data/draco/gltf/shared-accessors.gltf (tests/data/draco/README.md):
one mesh, three KHR_draco_mesh_compression primitives sharing their
POSITION, NORMAL and indices accessors (valid glTF: with Draco an accessor
only carries count and type). Primitives 0 and 2 share one Draco stream (a
sphere), primitive 1 has its own (an ellipsoid beside it, the same number
of points and triangles). Both streams are made by Debian's draco_encoder
from OBJ files with analytic normals.

Also writes decoded-count.gltf: the sphere's stream alone, its POSITION and
NORMAL accessors saying 6 points fewer than the stream decodes to (valid:
loaders use the decoded data; Cesium's DracoCompressed/CesiumMilkTruck.gltf
says 1856 points where its stream has 1886).

  make_gltf.py FOLDER
"""
import base64
import json
import math
import os
import subprocess
import sys
import tempfile

RINGS, SEGMENTS = 8, 12


def ellipsoid(radii, centre):
    """OBJ text of a UV ellipsoid without duplicated vertices (single poles)."""
    verts = [(0.0, 0.0, 1.0)]
    for r in range(1, RINGS):
        t = math.pi * r / RINGS
        verts += [(math.sin(t) * math.cos(2 * math.pi * s / SEGMENTS), math.sin(t) * math.sin(2 * math.pi * s / SEGMENTS),
                   math.cos(t)) for s in range(SEGMENTS)]
    verts.append((0.0, 0.0, -1.0))
    ring = lambda r, s: 1 + (r - 1) * SEGMENTS + s % SEGMENTS
    faces = [(0, ring(1, s), ring(1, s + 1)) for s in range(SEGMENTS)]
    for r in range(1, RINGS - 1):
        for s in range(SEGMENTS):
            a, b, c, d = ring(r, s), ring(r, s + 1), ring(r + 1, s), ring(r + 1, s + 1)
            faces += [(a, c, b), (b, c, d)]
    last = len(verts) - 1
    faces += [(last, ring(RINGS - 1, s + 1), ring(RINGS - 1, s)) for s in range(SEGMENTS)]
    lines = []
    for v in verts:
        lines.append("v %.9g %.9g %.9g" % tuple(centre[k] + radii[k] * v[k] for k in range(3)))
    for v in verts:
        n = [v[k] / radii[k] for k in range(3)]
        length = math.sqrt(sum(x * x for x in n))
        lines.append("vn %.9g %.9g %.9g" % tuple(x / length for x in n))
    lines += ["f %d//%d %d//%d %d//%d" % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1) for a, b, c in faces]
    return "\n".join(lines) + "\n", len(verts), len(faces), [
        [centre[k] - radii[k] for k in range(3)], [centre[k] + radii[k] for k in range(3)]]


def main(folder):
    streams, bounds = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for k, (radii, centre) in enumerate([((1, 1, 1), (0, 0, 0)), ((1, 0.6, 0.3), (3, 0, 0))]):
            obj, points, triangles, box = ellipsoid(radii, centre)
            with open(os.path.join(tmp, "%d.obj" % k), "w") as f:
                f.write(obj)
            subprocess.run(["draco_encoder", "-i", os.path.join(tmp, "%d.obj" % k), "-o", os.path.join(tmp, "%d.drc" % k)],
                           check=True, stdout=subprocess.DEVNULL)
            with open(os.path.join(tmp, "%d.drc" % k), "rb") as f:
                streams.append(f.read())
            bounds.append(box)
    data, views = b"", []
    for s in streams:
        views.append({"buffer": 0, "byteOffset": len(data), "byteLength": len(s)})
        data += s + b"\0" * (-len(s) % 4)
    draco = lambda view: {"KHR_draco_mesh_compression": {"bufferView": view, "attributes": {"POSITION": 0, "NORMAL": 1}}}
    prim = lambda view, material: {"attributes": {"POSITION": 1, "NORMAL": 2}, "indices": 0, "material": material,
                                   "extensions": draco(view)}
    doc = {
        "asset": {"version": "2.0", "generator": "vn tests/draco/make_gltf.py"},
        "extensionsUsed": ["KHR_draco_mesh_compression"], "extensionsRequired": ["KHR_draco_mesh_compression"],
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "materials": [{"name": "sphere"}, {"name": "ellipsoid"}, {"name": "sphere again"}],
        "meshes": [{"primitives": [prim(0, 0), prim(1, 1), prim(0, 2)]}],
        "accessors": [
            {"componentType": 5123, "count": 3 * triangles, "type": "SCALAR"},
            {"componentType": 5126, "count": points, "type": "VEC3",
             "min": [min(b[0][k] for b in bounds) for k in range(3)], "max": [max(b[1][k] for b in bounds) for k in range(3)]},
            {"componentType": 5126, "count": points, "type": "VEC3"}],
        "bufferViews": views,
        "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
    }
    write(os.path.join(folder, "shared-accessors.gltf"), doc)
    sphere = streams[0]
    doc["materials"], doc["meshes"] = [{"name": "sphere"}], [{"primitives": [prim(0, 0)]}]
    doc["accessors"][1]["min"], doc["accessors"][1]["max"] = bounds[0]
    for a in doc["accessors"][1:]:
        a["count"] = points - 6
    doc["bufferViews"] = [{"buffer": 0, "byteLength": len(sphere)}]
    doc["buffers"] = [{"byteLength": len(sphere), "uri": "data:application/octet-stream;base64," + base64.b64encode(sphere).decode()}]
    write(os.path.join(folder, "decoded-count.gltf"), doc)


def write(path, doc):
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main(sys.argv[1])
