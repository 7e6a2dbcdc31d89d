#!/usr/bin/env python3
"""Inputs for tests/bench/draco_memory.sh and the memory check of
tests/test_draco.sh, from a GLB of one triangle primitive (vnconvert's
output of an OFF):

  draco_inputs.py attributes IN.glb OUT.glb   adds TEXCOORD_0 (float) and COLOR_0
                                              (normalized uint8 RGBA) to it
  draco_inputs.py split IN.glb OUT.glb K      cuts it into K primitives of one
                                              mesh, each with its own vertices
  draco_inputs.py decoded FILE.glb            prints the decoded size of its Draco
                                              primitives in bytes: per primitive,
                                              points x every attribute's element
                                              size + indices, as the accessors
                                              type them
"""
import array
import json
import math
import struct
import sys

SIZES = {5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4}
COUNTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


def read(path):
    raw = open(path, "rb").read()
    length = struct.unpack_from("<I", raw, 12)[0]
    doc = json.loads(raw[20:20 + length])
    size = struct.unpack_from("<I", raw, 20 + length)[0] if len(raw) > 20 + length else 0
    return doc, bytearray(raw[28 + length:28 + length + size])


def write(path, doc, data):
    while len(data) % 4:
        data.append(0)
    doc["buffers"] = [{"byteLength": len(data)}]
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    with open(path, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 28 + len(text) + len(data)))
        f.write(struct.pack("<II", len(text), 0x4E4F534A) + text)
        f.write(struct.pack("<II", len(data), 0x004E4942) + bytes(data))


def element(a):
    return SIZES[a["componentType"]] * COUNTS[a["type"]]


def values(doc, data, index):
    a = doc["accessors"][index]
    v = doc["bufferViews"][a["bufferView"]]
    start = v.get("byteOffset", 0) + a.get("byteOffset", 0)
    return bytes(data[start:start + element(a) * a["count"]])


def append(doc, data, blob, accessor, target):
    while len(data) % 4:
        data.append(0)
    doc["bufferViews"].append({"buffer": 0, "byteOffset": len(data), "byteLength": len(blob), "target": target})
    data.extend(blob)
    accessor["bufferView"] = len(doc["bufferViews"]) - 1
    doc["accessors"].append(accessor)
    return len(doc["accessors"]) - 1


def attributes(src, dst):
    doc, data = read(src)
    prim = doc["meshes"][0]["primitives"][0]
    pos = array.array("f", values(doc, data, prim["attributes"]["POSITION"]))
    n = len(pos) // 3
    uv, rgba = array.array("f"), bytearray()
    for i in range(n):
        x, y, z = pos[3 * i:3 * i + 3]
        uv.extend((math.atan2(y, x) / (2 * math.pi) + 0.5, z * 0.5 + 0.5))
        rgba.extend(int(128 + 127 * math.sin(3 * c)) for c in (x, y, z))
        rgba.append(255)
    prim["attributes"]["TEXCOORD_0"] = append(doc, data, uv.tobytes(), {"componentType": 5126, "count": n, "type": "VEC2"}, 34962)
    prim["attributes"]["COLOR_0"] = append(doc, data, bytes(rgba),
                                           {"componentType": 5121, "normalized": True, "count": n, "type": "VEC4"}, 34962)
    write(dst, doc, data)


def split(src, dst, k):
    doc, data = read(src)
    prim = doc["meshes"][0]["primitives"][0]
    corners = array.array("I", values(doc, data, prim["indices"]))
    sources = {name: (doc["accessors"][i], values(doc, data, i)) for name, i in prim["attributes"].items()}
    doc["accessors"], doc["bufferViews"], out, prims = [], [], bytearray(), []
    triangles = len(corners) // 3
    for p in range(k):
        part = corners[3 * (triangles * p // k):3 * (triangles * (p + 1) // k)]
        local, order = {}, []
        for v in part:
            if v not in local:
                local[v] = len(order)
                order.append(v)
        attrs = {}
        for name, (a, blob) in sources.items():
            size = element(a)
            picked = b"".join(blob[v * size:(v + 1) * size] for v in order)
            new = {key: a[key] for key in ("componentType", "type", "normalized") if key in a}
            new["count"] = len(order)
            if name == "POSITION":
                xyz = array.array("f", picked)
                new["min"] = [min(xyz[c::3]) for c in range(3)]
                new["max"] = [max(xyz[c::3]) for c in range(3)]
            attrs[name] = append(doc, out, picked, new, 34962)
        indices = array.array("I" if len(order) > 65536 else "H", (local[v] for v in part))
        prims.append({"attributes": attrs, "indices": append(doc, out, indices.tobytes(), {
            "componentType": 5125 if indices.typecode == "I" else 5123, "count": len(indices), "type": "SCALAR"}, 34963)})
    doc["meshes"][0]["primitives"] = prims
    write(dst, doc, out)


def decoded(path):
    doc, _ = read(path)
    total = 0
    for mesh in doc["meshes"]:
        for prim in mesh["primitives"]:
            if "KHR_draco_mesh_compression" in prim.get("extensions", {}):
                total += sum(element(doc["accessors"][i]) * doc["accessors"][i]["count"] for i in prim["attributes"].values())
                a = doc["accessors"][prim["indices"]]
                total += element(a) * a["count"]
    print(total)


if __name__ == "__main__":
    if sys.argv[1:2] == ["attributes"] and len(sys.argv) == 4:
        attributes(sys.argv[2], sys.argv[3])
    elif sys.argv[1:2] == ["split"] and len(sys.argv) == 5:
        split(sys.argv[2], sys.argv[3], int(sys.argv[4]))
    elif sys.argv[1:2] == ["decoded"] and len(sys.argv) == 3:
        decoded(sys.argv[2])
    else:
        sys.exit(__doc__)
