#!/usr/bin/env python3
"""The normals of the vertices no face gives a normal, in a vnconvert output.

    keep_normals.py OUT EXPECTED
    keep_normals.py --dump FILE     (positions and normals, one vertex a line)

OUT is a NOFF, .gltf, .glb, or the JSON of tests/draco/decode.mjs (a .drc as
the npm draco3d decoder reads it). EXPECTED is a file of lines
"x y z nx ny nz": for each, the output vertex nearest that position (within
0.01: Draco quantizes positions) must have that normal, compared as
MODE says on the first line ("exact": the same float32 values; "unit": the
same, after scaling to unit length one whose length is not within 1e-6 of
1, as the glTF writer does (glTF's normals are unit vectors);
"angle DEG": within DEG degrees, or both zero). Exits 1 naming every
difference."""
import base64, json, math, os, struct, sys


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def read_off(path):
    words = []
    for line in open(path):
        words += line.split("#")[0].split()
    assert words[0] == "NOFF", path + ": not NOFF"
    n = int(words[1])
    values = [float(w) for w in words[4:4 + 6 * n]]
    return [(values[6 * i:6 * i + 3], values[6 * i + 3:6 * i + 6]) for i in range(n)]


def read_gltf(path):
    raw = open(path, "rb").read()
    bin_chunk = None
    if raw[:4] == b"glTF":
        length = struct.unpack("<I", raw[12:16])[0]
        d = json.loads(raw[20:20 + length])
        rest = raw[20 + length:]
        bin_chunk = rest[8:8 + struct.unpack("<I", rest[:4])[0]]
    else:
        d = json.loads(raw)
    buffers = []
    for b in d["buffers"]:
        uri = b.get("uri")
        if uri is None:
            buffers.append(bin_chunk)
        elif uri.startswith("data:"):
            buffers.append(base64.b64decode(uri.split(",", 1)[1]))
        else:
            buffers.append(open(os.path.join(os.path.dirname(path), uri), "rb").read())

    def vec3(index):
        a = d["accessors"][index]
        v = d["bufferViews"][a["bufferView"]]
        data = buffers[v["buffer"]]
        stride = v.get("byteStride", 12)
        base = v.get("byteOffset", 0) + a.get("byteOffset", 0)
        assert a["componentType"] == 5126 and a["type"] == "VEC3"
        return [list(struct.unpack_from("<3f", data, base + i * stride)) for i in range(a["count"])]

    out = []
    for mesh in d["meshes"]:
        for p in mesh["primitives"]:
            pos = vec3(p["attributes"]["POSITION"])
            nor = vec3(p["attributes"]["NORMAL"])
            out += list(zip(pos, nor))
    return out


def read_draco_json(path):
    d = json.load(open(path))
    n = d["points"]
    nor = d["normals"] or [0.0] * (3 * n)
    return [(d["positions"][3 * i:3 * i + 3], nor[3 * i:3 * i + 3]) for i in range(n)]


def read(path):
    if path.endswith(".off"):
        return read_off(path)
    if path.endswith(".json"):
        return read_draco_json(path)
    return read_gltf(path)


def main():
    if sys.argv[1] == "--dump":
        for p, n in read(sys.argv[2]):
            print(" ".join(repr(x) for x in p + n))
        return 0
    vertices = read(sys.argv[1])
    lines = [l.split() for l in open(sys.argv[2]) if l.strip()]
    mode, expected = lines[0], [[float(w) for w in l] for l in lines[1:]]
    bad = 0
    for e in expected:
        p, want = e[:3], e[3:]
        best = min(vertices, key=lambda v: sum((a - b) ** 2 for a, b in zip(v[0], p)))
        if math.dist(best[0], p) > 0.01:
            print("no vertex at %s" % p)
            bad += 1
            continue
        got = best[1]
        if mode[0] == "exact":
            ok = [f32(x) for x in got] == [f32(x) for x in want]
        elif mode[0] == "unit":
            l = math.sqrt(sum(x * x for x in want))
            l = 1 if abs(l - 1) <= 1e-6 else l
            ok = [f32(x) for x in got] == [f32(x / l) for x in want]
        else:
            lg, lw = math.hypot(*got), math.hypot(*want)
            if lg == 0 or lw == 0:
                ok = lg == lw
            else:
                c = sum(a * b for a, b in zip(got, want)) / (lg * lw)
                ok = math.degrees(math.acos(max(-1.0, min(1.0, c)))) <= float(mode[1])
        if not ok:
            print("vertex at %s: normal %s, expected %s (%s)" % (p, got, want, " ".join(mode)))
            bad += 1
    return 1 if bad else 0


sys.exit(main())
