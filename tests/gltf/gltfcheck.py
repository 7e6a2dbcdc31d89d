#!/usr/bin/env python3
"""glTF checks for vn's tests (python3 standard library only).

  gltfcheck.py diff IN OUT [--tangents-dropped]
      OUT's JSON equals IN's, key order included, except for what recomputing
      normals may change: NORMAL accessors' min/max, appended bufferViews and
      accessors (which must be NORMAL data), buffers' byteLength and uri, a
      primitive's and its morph targets' NORMAL index (and TANGENT, when
      dropped), and in a KHR_draco_mesh_compression primitive its Draco
      bufferView and its NORMAL unique id. Every accessor that
      is not NORMAL reads back the same bytes, and so does every bufferView
      that no NORMAL accessor uses (images, animations, ...). Every NORMAL
      element with data outside Draco is a unit vector.
  gltfcheck.py drc FILE STEM
      Writes the Draco data of each KHR_draco_mesh_compression primitive as
      STEM_0.drc, STEM_1.drc, ...; exit 1 when there is none.
  gltfcheck.py nodraco FILE
      FILE does not mention KHR_draco_mesh_compression.
  gltfcheck.py seams FILE same|differ
      In every triangle primitive, vertices at the same position have the
      same normal (same), or at least one such pair does not (differ).
  gltfcheck.py sphere FILE
      Writes a UV sphere with a seam (split vertices along u = 0/1 with
      different UVs) as a .gltf with a data-URI buffer.
  gltfcheck.py shapes FILE
      Writes the same sphere as five primitives over one POSITION accessor:
      the top half (NORMAL 1), the bottom half sharing NORMAL 1 (one vertex
      array with the top half), the whole sphere without NORMAL, a
      TRIANGLE_STRIP band, and POINTS.
  gltfcheck.py quantized FILE
      The sphere under KHR_mesh_quantization: POSITION as SHORT (not
      normalized, byteStride 8), NORMAL as normalized BYTE (byteStride 4).
  gltfcheck.py scattered FOLDER
      Writes the sphere as files are spread in practice: FOLDER/a/model.gltf
      with three buffers (a file, a data URI, a file in a subfolder),
      TEXCOORD_0, COLOR_0, _TEMPERATURE, an image outside the model's folder
      (../tex/checker.png) and one in a subfolder, rounded POSITION bounds.
  gltfcheck.py packed FILE
      No unused accessor or bufferView, and no buffer bytes outside every
      bufferView (but padding).
  gltfcheck.py bounds FILE
      Every accessor's min/max are its values' exact bounds.
  gltfcheck.py prims FILE STEM
      Writes each uncompressed TRIANGLES primitive k as STEM_k.off: its
      POSITION values as stored (not dequantized) and its triangles.
  gltfcheck.py ownnormals FILE VNCONVERT METHOD DEGREES
      Every uncompressed TRIANGLES primitive's NORMAL is within DEGREES of
      the normal VNCONVERT computes on an OFF of that primitive's own
      positions and triangles (so no primitive got another's data).
  gltfcheck.py twosided FILE
      Writes a double-sided bowl as exporters write one: the 7 x 7 grid
      z = 0.3 (x^2 + y^2) over [-1, 1]^2, front copies 0..48 with the exact
      normals, back copies 49..97 with the faces reversed and the normals
      negated.
  gltfcheck.py twosided-check FILE DEGREES
      In FILE (that bowl converted), every front normal is within DEGREES of
      the exact one and every back normal is its front copy's, negated.
  gltfcheck.py twosided-shared FILE
      The same bowl with both sides on the same 49 vertices (the back's
      faces reversed on them), no NORMAL, TEXCOORD_0 = (x, y).
  gltfcheck.py twosided-shared-check FILE DEGREES
      In FILE (that bowl converted): 98 vertices, each with its own
      position's TEXCOORD_0; every corner of a front face has a normal
      within DEGREES of the exact one, every corner of a back face the
      front's at its position, negated.
  gltfcheck.py metadata IN OUT
      Every EXT_structural_metadata property table's bufferViews (values,
      arrayOffsets, stringOffsets) read back the same bytes in OUT as in IN.
  gltfcheck.py samenormals IN OUT DEGREES
      Every vertex's NORMAL in OUT is within DEGREES of its NORMAL in IN,
      primitive by primitive (OUT converted from IN without splitting).
  gltfcheck.py drcnormals JSON VNCONVERT METHOD DEGREES
      The same for a Draco mesh decoded by tests/draco/decode.mjs (its
      normals' directions: integer normals are not scaled by decoders).
  gltfcheck.py uvtriangle FILE
      Writes one triangle with TEXCOORD_0 as normalized UNSIGNED_SHORT
      (0, 0), (65535, 1000), (0, 65535) and TEXCOORD_1 as normalized
      UNSIGNED_BYTE (0, 10), (255, 20), (0, 255).
  gltfcheck.py uvcorners A B TOLERANCE [POSITION_TOLERANCE]
      A and B (each glTF, or OBJ by its .obj name) have the same corners:
      every (position, texture coordinate) pair of a triangle corner in one
      is within TOLERANCE (positions: POSITION_TOLERANCE, default the same)
      of such a pair in the other, as each file stores it (TEXCOORD_0 of
      TRIANGLES primitives; OBJ's v and vt).
  gltfcheck.py materials FILE
      Prints each material that a TRIANGLES primitive uses, by name: its
      base colour factor, metallic and roughness factors (6 decimals; glTF's
      defaults where absent), alpha mode, base colour image (MIME type and
      SHA-1 of its bytes), normal map (image and scale), emissive factor
      and image, and the positions (5 decimals) and total area of its
      triangles: what a conversion must keep whatever its primitive split,
      triangulation and vertex order.
Exit status 0 when the check holds, 1 with one line per problem otherwise.
"""
import base64
import copy
import hashlib
import json
import math
import os
import struct
import sys
import urllib.parse
import zlib

SIZES = {5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4}
FORMATS = {5120: "b", 5121: "B", 5122: "h", 5123: "H", 5125: "I", 5126: "f"}
COUNTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}


def load(path):
    """(json text, parsed document, list of buffer bytes)"""
    with open(path, "rb") as f:
        data = f.read()
    bin_chunk = None
    if data[:4] == b"glTF":
        length = struct.unpack_from("<I", data, 12)[0]
        text = data[20:20 + length].decode("utf-8")
        at = 20 + length
        if at + 8 <= len(data):
            n, kind = struct.unpack_from("<II", data, at)
            if kind == 0x004E4942:
                bin_chunk = data[at + 8:at + 8 + n]
    else:
        text = data.decode("utf-8")
    doc = json.loads(text)
    buffers = []
    for i, b in enumerate(doc.get("buffers", [])):
        uri = b.get("uri")
        if uri is None:
            buffers.append(bin_chunk if i == 0 else b"")
        elif uri.startswith("data:"):
            buffers.append(base64.b64decode(uri.split(",", 1)[1]))
        else:
            with open(os.path.join(os.path.dirname(path), urllib.parse.unquote(uri)), "rb") as f:
                buffers.append(f.read())
    return text, doc, buffers


def view_bytes(doc, buffers, v):
    view = doc["bufferViews"][v]
    start = view.get("byteOffset", 0)
    return buffers[view["buffer"]][start:start + view["byteLength"]]


def accessor_bytes(doc, buffers, a):
    """The accessor's element bytes (stride removed) and its sparse parts."""
    acc = doc["accessors"][a]
    element = SIZES[acc["componentType"]] * COUNTS[acc["type"]]
    out = b""
    if "bufferView" in acc:
        view = doc["bufferViews"][acc["bufferView"]]
        data = view_bytes(doc, buffers, acc["bufferView"])
        stride = view.get("byteStride", element)
        at = acc.get("byteOffset", 0)
        out += b"".join(data[at + i * stride:at + i * stride + element] for i in range(acc["count"]))
    sparse = acc.get("sparse")
    if sparse:
        for part in ("indices", "values"):
            p = sparse[part]
            size = SIZES[p["componentType"]] if part == "indices" else element
            at = p.get("byteOffset", 0)
            out += view_bytes(doc, buffers, p["bufferView"])[at:at + size * sparse["count"]]
    return out


def accessor_values(doc, buffers, a):
    acc = doc["accessors"][a]
    n = COUNTS[acc["type"]]
    size = SIZES[acc["componentType"]] * n * acc["count"]
    data = accessor_bytes(doc, buffers, a)
    raw, tail = (data[:size], data[size:]) if "bufferView" in acc else (bytes(size), data)
    values = list(struct.unpack("<%d%s" % (n * acc["count"], FORMATS[acc["componentType"]]), raw))
    if acc.get("sparse"):
        sp = acc["sparse"]
        isize = SIZES[sp["indices"]["componentType"]]
        idx = struct.unpack("<%d%s" % (sp["count"], FORMATS[sp["indices"]["componentType"]]), tail[:isize * sp["count"]])
        vals = struct.unpack("<%d%s" % (n * sp["count"], FORMATS[acc["componentType"]]), tail[isize * sp["count"]:])
        for k, i in enumerate(idx):
            values[n * i:n * i + n] = vals[n * k:n * k + n]
    if acc.get("normalized"):
        scale = {5120: 127.0, 5121: 255.0, 5122: 32767.0, 5123: 65535.0}[acc["componentType"]]
        values = [max(v / scale, -1.0) for v in values]
    return [values[i:i + n] for i in range(0, len(values), n)]


def primitives(doc):
    for m, mesh in enumerate(doc.get("meshes", [])):
        for p, prim in enumerate(mesh["primitives"]):
            yield m, p, prim


def normal_accessors(doc, targets=False):
    """NORMAL accessors of the primitives (targets: of their morph targets)."""
    if targets:
        return {t["NORMAL"] for _, _, prim in primitives(doc) for t in prim.get("targets", []) if "NORMAL" in t}
    return {prim["attributes"]["NORMAL"] for _, _, prim in primitives(doc) if "NORMAL" in prim["attributes"]}


def ordered(text):
    return json.loads(text, object_pairs_hook=lambda pairs: [list(p) for p in pairs])


def get(obj, key):
    for k, v in obj:
        if k == key:
            return v
    return None


def drop(obj, *keys):
    obj[:] = [kv for kv in obj if kv[0] not in keys]


def image_bytes(doc, buffers, image, folder):
    """An image's bytes, wherever they are: a bufferView, a data URI or a file;
    a file that is not there (the input lacked it too) stands as its URI."""
    if "bufferView" in image:
        return view_bytes(doc, buffers, image["bufferView"])
    uri = image.get("uri", "")
    if uri.startswith("data:"):
        return base64.b64decode(uri.split(",", 1)[1])
    path = os.path.join(folder, urllib.parse.unquote(uri))
    if not os.path.exists(path):
        return ("missing " + uri).encode()
    with open(path, "rb") as f:
        return f.read()


def resolve(o, doc, buf, tangents_dropped, folder="."):
    """o (doc as order-preserving lists) with what may legitimately change
    left out (NORMAL attributes, TANGENT when dropped, the Draco extension's
    bufferView and NORMAL id), and every other accessor and bufferView index
    replaced by what it stands for, so that vn removing unused ones and
    renumbering the rest is not a change: an accessor by its JSON (less
    where its data lie) and its element bytes, an image by its bytes (be
    they in a bufferView, a data URI or a file: a GLB embeds what a .gltf
    refers to) and the rest of its JSON. The accessors, bufferViews and
    buffers arrays themselves go."""
    normals = normal_accessors(doc) | normal_accessors(doc, True)
    accessors = get(o, "accessors") or []

    def accessor(i):
        if i in normals:
            return "NORMAL"
        acc = copy.deepcopy(accessors[i])
        drop(acc, "bufferView", "byteOffset")
        sparse = get(acc, "sparse")
        for part in [get(sparse, "indices"), get(sparse, "values")] if sparse else []:
            drop(part, "bufferView", "byteOffset")
        return acc + [["data", accessor_bytes(doc, buf, i).hex()]]

    def members(obj):
        for kv in obj or []:
            kv[1] = accessor(kv[1])

    def key(obj, k, f):
        for kv in obj or []:
            if kv[0] == k:
                kv[1] = f(kv[1])

    for k, v in o:
        if k == "meshes":
            for mesh in v:
                for prim in get(mesh, "primitives") or []:
                    for attributes in [get(prim, "attributes")] + (get(prim, "targets") or []):
                        drop(attributes, "NORMAL", *(["TANGENT"] if tangents_dropped else []))
                        members(attributes)
                    key(prim, "indices", accessor)
                    draco = get(get(prim, "extensions") or [], "KHR_draco_mesh_compression")
                    if draco is not None:
                        drop(draco, "bufferView")
                        drop(get(draco, "attributes") or [], "NORMAL")
        if k == "skins":
            for skin in v:
                key(skin, "inverseBindMatrices", accessor)
        if k == "animations":
            for animation in v:
                for sampler in get(animation, "samplers") or []:
                    key(sampler, "input", accessor)
                    key(sampler, "output", accessor)
        if k == "nodes":
            for node in v:
                members(get(get(get(node, "extensions") or [], "EXT_mesh_gpu_instancing") or [], "attributes"))
        if k == "images":
            for n, image in enumerate(v):
                data = image_bytes(doc, buf, doc["images"][n], folder).hex()
                drop(image, "bufferView", "uri", "mimeType")
                image.append(["data", data])
    drop(o, "accessors", "bufferViews", "buffers")
    return o


def first_difference(x, y, path="/"):
    """Where resolved documents x and y first differ (None: nowhere)."""
    if isinstance(x, list) and isinstance(y, list):
        for i, (u, v) in enumerate(zip(x, y)):
            pair = isinstance(u, list) and len(u) == 2 and isinstance(u[0], str)  # an object's key, value
            if pair and isinstance(v, list) and len(v) == 2 and u[0] == v[0]:
                d = first_difference(u[1], v[1], "%s%s/" % (path, u[0]))
            else:
                d = first_difference(u, v, "%s%d/" % (path, i))
            if d is not None:
                return d
        return None if len(x) == len(y) else "%s (%d vs %d entries)" % (path, len(x), len(y))
    return None if x == y else path


def cmd_diff(a, b, tangents_dropped):
    problems = []
    text_a, in_doc, in_buf = load(a)
    text_b, out_doc, out_buf = load(b)
    where = first_difference(resolve(ordered(text_a), in_doc, in_buf, tangents_dropped, os.path.dirname(a)),
                             resolve(ordered(text_b), out_doc, out_buf, tangents_dropped, os.path.dirname(b)))
    if where is not None:
        problems.append("JSON or non-NORMAL data differ at %s" % where)
    # A primitive's NORMAL is a unit vector per vertex.
    for _, _, prim in primitives(out_doc):
        if "POSITION" in prim["attributes"] and prim.get("mode", 4) >= 4 and "NORMAL" not in prim["attributes"]:
            problems.append("a triangle primitive has no NORMAL")
    for i in normal_accessors(out_doc):
        acc = out_doc["accessors"][i]
        if "bufferView" not in acc and "sparse" not in acc:
            continue  # in Draco data
        tolerance = 1e-6 if acc["componentType"] == 5126 else 0.02
        for x, y, z in accessor_values(out_doc, out_buf, i):
            if abs(math.sqrt(x * x + y * y + z * z) - 1) > tolerance:
                problems.append("accessor %d has a non-unit normal (%g, %g, %g)" % (i, x, y, z))
                break
    for p in problems:
        print("%s -> %s: %s" % (a, b, p))
    return 1 if problems else 0


def cmd_seams(path, expect):
    _, doc, buf = load(path)
    pairs = differ = 0
    for _, _, prim in primitives(doc):
        attributes = prim["attributes"]
        if prim.get("mode", 4) < 4 or "POSITION" not in attributes:
            continue
        first = {}
        positions = accessor_values(doc, buf, attributes["POSITION"])
        normals = accessor_values(doc, buf, attributes["NORMAL"])
        for p, n in zip(positions, normals):
            key = tuple(p)
            if key in first:
                pairs += 1
                differ += first[key] != n
            else:
                first[key] = n
    if pairs == 0:
        print("%s: no split vertices" % path)
        return 1
    ok = differ == 0 if expect == "same" else differ > 0
    if not ok:
        print("%s: %d of %d split vertex pairs have different normals (expected %s)" % (path, differ, pairs, expect))
    return 0 if ok else 1


def cmd_sphere(path, rings=8, segments=12, shapes=False):
    """A UV sphere: (segments + 1) columns so that u = 0 and u = 1 are split
    copies with different UVs; the poles are split too. Normals are the
    input's (+Z everywhere, deliberately wrong)."""
    pos, uv, idx = [], [], []
    for r in range(rings + 1):
        theta = math.pi * r / rings
        for s in range(segments + 1):
            phi = 2 * math.pi * (s % segments) / segments
            pos.append((math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)))
            uv.append((s / segments, r / rings))
    cols = segments + 1
    for r in range(rings):
        for s in range(segments):
            a, b, c, d = r * cols + s, r * cols + s + 1, (r + 1) * cols + s, (r + 1) * cols + s + 1
            idx += [a, c, b, b, c, d]
    n = len(pos)
    data = b"".join(struct.pack("<3f", *p) for p in pos)
    data += b"".join(struct.pack("<3f", 0, 0, 1) for _ in pos)
    data += b"".join(struct.pack("<2f", *t) for t in uv)
    data += struct.pack("<%dH" % len(idx), *idx)
    f32 = [struct.unpack("<3f", struct.pack("<3f", *p)) for p in pos]
    doc = {
        "asset": {"version": "2.0", "generator": "vn tests"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": "sphere"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3",
             "min": [min(p[i] for p in f32) for i in range(3)], "max": [max(p[i] for p in f32) for i in range(3)]},
            {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": n, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": len(idx), "type": "SCALAR"}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 12 * n, "target": 34962},
            {"buffer": 0, "byteOffset": 12 * n, "byteLength": 12 * n, "target": 34962},
            {"buffer": 0, "byteOffset": 24 * n, "byteLength": 8 * n, "target": 34962},
            {"buffer": 0, "byteOffset": 32 * n, "byteLength": 2 * len(idx), "target": 34963}],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
    }
    if shapes:
        half = len(idx) // 2
        strip = [v for s in range(segments + 1) for v in (3 * cols + s, 4 * cols + s)]
        data += struct.pack("<%dH" % len(strip), *strip)
        data += b"\0" * (-len(data) % 4)
        doc["accessors"] += [
            {"bufferView": 3, "componentType": 5123, "count": half, "type": "SCALAR"},
            {"bufferView": 3, "byteOffset": 2 * half, "componentType": 5123, "count": half, "type": "SCALAR"},
            {"bufferView": 4, "componentType": 5123, "count": len(strip), "type": "SCALAR"}]
        doc["bufferViews"].append({"buffer": 0, "byteOffset": 32 * n + 2 * len(idx), "byteLength": 2 * len(strip),
                                   "target": 34963})
        doc["buffers"] = [{"byteLength": len(data),
                           "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}]
        doc["meshes"] = [{"primitives": [
            {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 4},
            {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 5},
            {"attributes": {"POSITION": 0, "TEXCOORD_0": 2}, "indices": 3},
            {"attributes": {"POSITION": 0}, "indices": 6, "mode": 5},
            {"attributes": {"POSITION": 0}, "mode": 0}]}]
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)
    return 0


def cmd_quantized(path):
    cmd_sphere(path)
    with open(path) as f:
        doc = json.load(f)
    _, _, (data,) = load(path)
    n = doc["accessors"][0]["count"]
    pos = [struct.unpack_from("<3f", data, 12 * i) for i in range(n)]
    q = [tuple(round(c * 1000) for c in p) for p in pos]
    out = b"".join(struct.pack("<3hxx", *p) for p in q)
    out += b"".join(struct.pack("<3bx", 0, 0, 127) for _ in range(n))
    out += data[24 * n:]
    doc["extensionsUsed"] = doc["extensionsRequired"] = ["KHR_mesh_quantization"]
    doc["nodes"][0]["scale"] = [0.001, 0.001, 0.001]
    doc["accessors"][0].update(componentType=5122, min=[min(p[i] for p in q) for i in range(3)],
                               max=[max(p[i] for p in q) for i in range(3)])
    doc["accessors"][1].update(componentType=5120, normalized=True)
    lengths = [8 * n, 4 * n, 8 * n, doc["bufferViews"][3]["byteLength"]]
    offset = 0
    for view, length, stride in zip(doc["bufferViews"], lengths, [8, 4, None, None]):
        view.update(byteOffset=offset, byteLength=length)
        if stride:
            view["byteStride"] = stride
        offset += length
    doc["buffers"][0] = {"byteLength": len(out),
                         "uri": "data:application/octet-stream;base64," + base64.b64encode(out).decode()}
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)
    return 0


def triangles(doc, buf, prim):
    """The corners of a TRIANGLES primitive, 3 per triangle."""
    if "indices" in prim:
        return [i for (i,) in accessor_values(doc, buf, prim["indices"])]
    return list(range(doc["accessors"][prim["attributes"]["POSITION"]]["count"]))


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def unit(v):
    length = math.sqrt(sum(x * x for x in v))
    return [x / length for x in v]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def face_normal(p):
    """The triangle's unit normal, None when it is degenerate."""
    n = cross(sub(p[1], p[0]), sub(p[2], p[0]))
    return unit(n) if any(n) else None


def close(a, b, tolerance):
    return all(abs(x - y) <= tolerance for x, y in zip(a, b))


def vnconvert_normals(vnconvert, method, positions, corners):
    """Normals vnconvert computes for an OFF mesh, on its vertices as given (--no-weld)."""
    import subprocess
    import tempfile
    with tempfile.TemporaryDirectory() as folder:
        src, dst = os.path.join(folder, "in.off"), os.path.join(folder, "out.off")
        with open(src, "w") as f:
            f.write("OFF\n%d %d 0\n" % (len(positions), len(corners) // 3))
            f.writelines("%.17g %.17g %.17g\n" % tuple(p) for p in positions)
            f.writelines("3 %d %d %d\n" % tuple(corners[i:i + 3]) for i in range(0, len(corners), 3))
        subprocess.run([vnconvert, src, dst, "-m", method, "-q", "--no-weld"], check=True)
        rows = [l.split() for l in open(dst) if l.strip()]
        return [list(map(float, r[3:6])) for r in rows[2:2 + len(positions)]]


def cmd_morph(path, vnconvert, method, weld):
    """Base normals and base + every target's NORMAL displacement against
    vnconvert on an OFF of the (morphed) positions: welded by equal base
    position (weld), or as split in the file (split: right when every split
    is a hard edge, as in a cube with one vertex per face corner)."""
    _, doc, buf = load(path)
    problems, checked = [], 0
    for m, p, prim in primitives(doc):
        if prim.get("mode", 4) != 4 or not prim.get("targets"):
            continue
        base = accessor_values(doc, buf, prim["attributes"]["POSITION"])
        normals = accessor_values(doc, buf, prim["attributes"]["NORMAL"])
        corners = triangles(doc, buf, prim)
        rep = list(range(len(base)))
        if weld:
            first = {}
            rep = [first.setdefault(tuple(q), i) for i, q in enumerate(base)]
        shapes = [("base", base, [[0.0] * 3] * len(base))]
        for t, target in enumerate(prim["targets"]):
            if "POSITION" in target:
                moved = [[a + b for a, b in zip(q, d)] for q, d in zip(base, accessor_values(doc, buf, target["POSITION"]))]
                if "NORMAL" not in target:
                    problems.append("meshes[%d].primitives[%d].targets[%d] has no NORMAL" % (m, p, t))
                    continue
                shapes.append(("target %d" % t, moved, accessor_values(doc, buf, target["NORMAL"])))
        for name, shape, delta in shapes:
            expected = vnconvert_normals(vnconvert, method, [shape[i] for i in rep], [rep[c] for c in corners])
            used = set(corners)
            for i in used:
                got = [a + b for a, b in zip(normals[i], delta[i])]
                if not close(got, expected[rep[i]], 1e-5):
                    problems.append("meshes[%d].primitives[%d] %s vertex %d: %s, expected %s" %
                                    (m, p, name, i, got, expected[rep[i]]))
                    break
            checked += name != "base"
    if not checked:
        problems.append("no morph target checked")
    for q in problems:
        print("%s: %s" % (path, q))
    return 1 if problems else 0


def cmd_flat(path):
    """Every corner's normal is its triangle's face normal (to 1e-6), in
    every TRIANGLES primitive (degenerate triangles aside)."""
    _, doc, buf = load(path)
    for m, p, prim in primitives(doc):
        if prim.get("mode", 4) != 4:
            continue
        positions = accessor_values(doc, buf, prim["attributes"]["POSITION"])
        normals = accessor_values(doc, buf, prim["attributes"]["NORMAL"])
        corners = triangles(doc, buf, prim)
        for k in range(0, len(corners), 3):
            n = face_normal([positions[i] for i in corners[k:k + 3]])
            if n is None:
                continue
            for i in corners[k:k + 3]:
                if not close(normals[i], n, 1e-6):
                    print("%s: meshes[%d].primitives[%d] vertex %d has %s, its face %s" % (path, m, p, i, normals[i], n))
                    return 1
    return 0


def cmd_crease(a, b, splits, vnconvert, method):
    """b is the cylinder a with --crease-angle between 30 and 90 degrees: the
    primitive has `splits` more vertices; every corner carries its input
    corner's POSITION, TEXCOORD_0, COLOR_0 and target POSITION; cap corners
    have normal +-Z, side corners vnconvert's normal of the side alone (an
    OFF of its triangles), in the base shape and the morphed one (base +
    NORMAL displacement)."""
    _, din, bin_ = load(a)
    _, dout, bout = load(b)
    pi, po = din["meshes"][0]["primitives"][0], dout["meshes"][0]["primitives"][0]
    problems = []
    count = lambda d, prim: d["accessors"][prim["attributes"]["POSITION"]]["count"]
    if count(dout, po) != count(din, pi) + splits:
        problems.append("%d vertices, expected %d + %d" % (count(dout, po), count(din, pi), splits))
    cin, cout = triangles(din, bin_, pi), triangles(dout, bout, po)
    values = lambda d, buf, prim: [accessor_values(d, buf, prim["attributes"][k]) for k in ("POSITION", "TEXCOORD_0", "COLOR_0")] + \
        [accessor_values(d, buf, prim["targets"][0]["POSITION"])]
    vin, vout = values(din, bin_, pi), values(dout, bout, po)
    if len(cin) != len(cout) or any(x[i] != y[j] for i, j in zip(cin, cout) for x, y in zip(vin, vout)):
        problems.append("corners do not carry their input vertex's data")
    normals = accessor_values(dout, bout, po["attributes"]["NORMAL"])
    delta = accessor_values(dout, bout, po["targets"][0]["NORMAL"])
    morphed = [[p + d for p, d in zip(q, e)] for q, e in zip(vin[0], vin[3])]
    side = [c for k in range(0, len(cin), 3) if abs(face_normal([vin[0][i] for i in cin[k:k + 3]])[2]) < 0.99
            for c in cin[k:k + 3]]
    for shape, n, points in (("base", normals, vin[0]),
                             ("morphed", [[x + y for x, y in zip(u, d)] for u, d in zip(normals, delta)], morphed)):
        smooth = vnconvert_normals(vnconvert, method, points, side)
        for k in range(0, len(cout), 3):
            f = face_normal([points[i] for i in cin[k:k + 3]])
            for i, j in zip(cin[k:k + 3], cout[k:k + 3]):
                expected = [0, 0, round(f[2])] if abs(f[2]) > 0.99 else smooth[i]
                if not close(n[j], expected, 1e-5):
                    problems.append("%s vertex %d: %s, expected %s" % (shape, j, n[j], expected))
    for q in problems[:5]:
        print("%s: %s" % (b, q))
    return 1 if problems else 0


def write_gltf(path, doc, data):
    doc["buffers"] = [{"byteLength": len(data),
                       "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}]
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)
    return 0


def cmd_uvtriangle(path):
    data = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<6H", 0, 0, 65535, 1000, 0, 65535)
    data += b"".join(struct.pack("<2B2x", u, v) for u, v in ((0, 10), (255, 20), (0, 255)))
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1, "TEXCOORD_1": 2}}]}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                          "min": [0, 0, 0], "max": [1, 1, 0]},
                         {"bufferView": 1, "componentType": 5123, "normalized": True, "count": 3, "type": "VEC2"},
                         {"bufferView": 2, "componentType": 5121, "normalized": True, "count": 3, "type": "VEC2"}],
           "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                           {"buffer": 0, "byteOffset": 36, "byteLength": 12},
                           {"buffer": 0, "byteOffset": 48, "byteLength": 12, "byteStride": 4}]}
    return write_gltf(path, doc, data)


def cmd_morphsphere(path):
    """The seam sphere with one morph target that stretches its upper half
    (z > 0) by 1.5 along z: POSITION as a sparse accessor without
    bufferView, no NORMAL (so the output must add one)."""
    cmd_sphere(path)
    with open(path) as f:
        doc = json.load(f)
    _, _, (data,) = load(path)
    positions = [struct.unpack_from("<3f", data, 12 * i) for i in range(doc["accessors"][0]["count"])]
    moved = [i for i, p in enumerate(positions) if p[2] > 1e-6]
    values = [(0.0, 0.0, 0.5 * positions[i][2]) for i in moved]
    data += b"\0" * (-len(data) % 4)
    at = len(data)
    data += struct.pack("<%dH" % len(moved), *moved) + b"\0" * (-2 * len(moved) % 4)
    data += b"".join(struct.pack("<3f", *v) for v in values)
    f32 = [struct.unpack("<3f", struct.pack("<3f", *v)) for v in values]
    doc["bufferViews"] += [{"buffer": 0, "byteOffset": at, "byteLength": 2 * len(moved)},
                           {"buffer": 0, "byteOffset": len(data) - 12 * len(values), "byteLength": 12 * len(values)}]
    doc["accessors"].append({"componentType": 5126, "count": len(positions), "type": "VEC3",
                             "min": [0.0, 0.0, 0.0], "max": [0.0, 0.0, max(v[2] for v in f32)],
                             "sparse": {"count": len(moved),
                                        "indices": {"bufferView": 4, "componentType": 5123},
                                        "values": {"bufferView": 5}}})
    doc["meshes"][0]["primitives"][0]["targets"] = [{"POSITION": len(doc["accessors"]) - 1}]
    doc["meshes"][0]["weights"] = [0.0]
    return write_gltf(path, doc, data)


def cmd_cylinder(path, segments=12):
    """A closed cylinder (radius 1, height 1, `segments` sides) with one
    vertex per position: rings 0.. and segments.., cap centres 2 * segments
    and 2 * segments + 1. TEXCOORD_0 (float), COLOR_0 (normalized ubyte VEC3,
    byteStride 4), NORMAL +Z everywhere, and one morph target raising the
    top by 0.5."""
    pos, uv, color = [], [], []
    for z in (0.0, 1.0):
        for s in range(segments):
            phi = 2 * math.pi * s / segments
            pos.append((math.cos(phi), math.sin(phi), z))
            uv.append((s / segments, z))
            color.append((s * 20 % 256, int(z * 255), 7))
    pos += [(0.0, 0.0, 0.0), (0.0, 0.0, 1.0)]
    uv += [(0.5, 0.0), (0.5, 1.0)]
    color += [(1, 2, 3), (4, 5, 6)]
    idx = []
    for s in range(segments):
        a, b = s, (s + 1) % segments
        c, d = a + segments, b + segments
        idx += [a, b, d, a, d, c, 2 * segments, b, a, 2 * segments + 1, c, d]
    n = len(pos)
    up = [(0.0, 0.0, 0.5 if p[2] > 0.5 else 0.0) for p in pos]
    data = b"".join(struct.pack("<3f", *p) for p in pos)
    data += b"".join(struct.pack("<3f", 0, 0, 1) for _ in pos)
    data += b"".join(struct.pack("<2f", *t) for t in uv)
    data += b"".join(struct.pack("<3Bx", *c) for c in color)
    data += b"".join(struct.pack("<3f", *u) for u in up)
    data += struct.pack("<%dH" % len(idx), *idx)
    views = [(12 * n, None), (12 * n, None), (8 * n, None), (4 * n, 4), (12 * n, None), (2 * len(idx), None)]
    doc = {
        "asset": {"version": "2.0", "generator": "vn tests"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": "cylinder"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2, "COLOR_0": 3},
                                    "indices": 5, "targets": [{"POSITION": 4}]}], "weights": [0.0]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3",
             "min": [-1.0, -1.0, 0.0], "max": [1.0, 1.0, 1.0]},
            {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": n, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5121, "normalized": True, "count": n, "type": "VEC3"},
            {"bufferView": 4, "componentType": 5126, "count": n, "type": "VEC3",
             "min": [0.0, 0.0, 0.0], "max": [0.0, 0.0, 0.5]},
            {"bufferView": 5, "componentType": 5123, "count": len(idx), "type": "SCALAR"}],
        "bufferViews": [],
    }
    doc["accessors"][0]["min"] = [min(struct.unpack("<3f", struct.pack("<3f", *p))[i] for p in pos) for i in range(3)]
    doc["accessors"][0]["max"] = [max(struct.unpack("<3f", struct.pack("<3f", *p))[i] for p in pos) for i in range(3)]
    offset = 0
    for k, (length, stride) in enumerate(views):
        view = {"buffer": 0, "byteOffset": offset, "byteLength": length, "target": 34963 if k == 5 else 34962}
        if stride:
            view["byteStride"] = stride
        doc["bufferViews"].append(view)
        offset += length
    return write_gltf(path, doc, data)


def bowl():
    """The front of the double-sided bowl: positions, exact normals, triangles."""
    pos, nor, idx = [], [], []
    for j in range(7):
        for i in range(7):
            x, y = i / 3 - 1, j / 3 - 1
            pos.append((x, y, 0.3 * (x * x + y * y)))
            nor.append(unit((-0.6 * x, -0.6 * y, 1.0)))
    for j in range(6):
        for i in range(6):
            a = 7 * j + i
            idx += [a, a + 1, a + 8, a, a + 8, a + 7]
    return pos, nor, idx


def cmd_twosided(path):
    pos, nor, idx = bowl()
    n = len(pos)
    pos2 = pos + pos
    nor2 = nor + [tuple(-c for c in v) for v in nor]
    idx2 = idx + [n + i for i in reversed(idx)]
    data = b"".join(struct.pack("<3f", *p) for p in pos2)
    data += b"".join(struct.pack("<3f", *v) for v in nor2)
    data += struct.pack("<%dH" % len(idx2), *idx2)
    f32 = [struct.unpack("<3f", struct.pack("<3f", *p)) for p in pos2]
    doc = {
        "asset": {"version": "2.0", "generator": "vn tests"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": "two-sided bowl"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 2 * n, "type": "VEC3",
             "min": [min(p[i] for p in f32) for i in range(3)], "max": [max(p[i] for p in f32) for i in range(3)]},
            {"bufferView": 1, "componentType": 5126, "count": 2 * n, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": len(idx2), "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 24 * n, "target": 34962},
                        {"buffer": 0, "byteOffset": 24 * n, "byteLength": 24 * n, "target": 34962},
                        {"buffer": 0, "byteOffset": 48 * n, "byteLength": 2 * len(idx2), "target": 34963}],
    }
    return write_gltf(path, doc, data)


def cmd_twosided_shared(path):
    pos, _, idx = bowl()
    idx2 = idx + list(reversed(idx))
    data = b"".join(struct.pack("<3f", *p) for p in pos)
    data += b"".join(struct.pack("<2f", p[0], p[1]) for p in pos)
    data += struct.pack("<%dH" % len(idx2), *idx2)
    f32 = [struct.unpack("<3f", struct.pack("<3f", *p)) for p in pos]
    n = len(pos)
    doc = {
        "asset": {"version": "2.0", "generator": "vn tests"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": "two-sided bowl, shared vertices"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3",
             "min": [min(p[i] for p in f32) for i in range(3)], "max": [max(p[i] for p in f32) for i in range(3)]},
            {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": len(idx2), "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 12 * n, "target": 34962},
                        {"buffer": 0, "byteOffset": 12 * n, "byteLength": 8 * n, "target": 34962},
                        {"buffer": 0, "byteOffset": 20 * n, "byteLength": 2 * len(idx2), "target": 34963}],
    }
    return write_gltf(path, doc, data)


def cmd_twosided_shared_check(path, degrees):
    _, doc, buf = load(path)
    prim = doc["meshes"][0]["primitives"][0]
    pos = accessor_values(doc, buf, prim["attributes"]["POSITION"])
    normals = accessor_values(doc, buf, prim["attributes"]["NORMAL"])
    uv = accessor_values(doc, buf, prim["attributes"]["TEXCOORD_0"])
    idx = [i for (i,) in accessor_values(doc, buf, prim["indices"])]
    bad = 0
    if len(pos) != 98:
        print("%s: %d vertices, not 98 (each vertex split between the sides)" % (path, len(pos)))
        bad = 1
    for i, (p, t) in enumerate(zip(pos, uv)):
        if not close(t, p[:2], 1e-6):
            print("%s: vertex %d at %s has TEXCOORD_0 %s" % (path, i, p, t))
            bad = 1
    half = len(idx) // 2
    front = {}
    for k in range(half):
        v = idx[k]
        x, y, _ = pos[v]
        exact = unit((-0.6 * x, -0.6 * y, 1.0))
        angle = math.degrees(math.acos(max(-1.0, min(1.0, sum(a * b for a, b in zip(unit(normals[v]), exact))))))
        front[tuple(pos[v])] = normals[v]
        if angle > degrees:
            print("%s: front corner %d (vertex %d): %s, %.3g degrees from the exact normal" % (path, k, v, normals[v], angle))
            bad = 1
    for k in range(half, len(idx)):
        v = idx[k]
        f = front.get(tuple(pos[v]))
        if f is None or not close(normals[v], tuple(-c for c in f), 1e-7):
            print("%s: back corner %d (vertex %d): %s, the front's there %s" % (path, k, v, normals[v], f))
            bad = 1
    return bad


def cmd_twosided_check(path, degrees):
    _, doc, buf = load(path)
    prim = doc["meshes"][0]["primitives"][0]
    normals = accessor_values(doc, buf, prim["attributes"]["NORMAL"])
    _, exact, _ = bowl()
    n, bad = len(exact), 0
    for i in range(n):
        front, back = normals[i], normals[n + i]
        angle = math.degrees(math.acos(max(-1.0, min(1.0, sum(a * b for a, b in zip(unit(front), exact[i]))))))
        if angle > degrees or not close(back, tuple(-c for c in front), 1e-7):
            print("%s: vertex %d: front %s (%.3g degrees from the exact normal), back %s" % (path, i, front, angle, back))
            bad = 1
    return bad


def cmd_samenormals(a, b, degrees):
    _, doc_a, buf_a = load(a)
    _, doc_b, buf_b = load(b)
    bad = 0
    for (m, p, pa), (_, _, pb) in zip(primitives(doc_a), primitives(doc_b)):
        if "NORMAL" not in pa["attributes"]:
            continue
        na = accessor_values(doc_a, buf_a, pa["attributes"]["NORMAL"])
        nb = accessor_values(doc_b, buf_b, pb["attributes"]["NORMAL"])
        for i, (x, y) in enumerate(zip(na, nb)):
            angle = math.degrees(math.acos(max(-1.0, min(1.0, sum(u * v for u, v in zip(unit(x), unit(y)))))))
            if angle > degrees:
                print("%s: meshes[%d].primitives[%d] vertex %d: %s, %.3g degrees from %s's %s" % (b, m, p, i, y, angle, a, x))
                bad = 1
        if len(na) != len(nb):
            print("%s: meshes[%d].primitives[%d] has %d normals, %s %d" % (b, m, p, len(nb), a, len(na)))
            bad = 1
    return bad


def uv_corners(path):
    """The distinct (x, y, z, u, v) of the file's triangle corners."""
    if path.endswith(".obj"):
        v, vt, out = [], [], set()
        for line in open(path, encoding="utf-8"):
            w = line.split("#")[0].split()
            if w and w[0] in ("v", "vt"):
                (v if w[0] == "v" else vt).append([float(x) for x in w[1:4 if w[0] == "v" else 3]])
            elif w and w[0] == "f":
                for c in w[1:]:
                    r = (c.split("/") + [""])[:2]
                    p, t = int(r[0]), int(r[1]) if r[1] else 0
                    p, t = p + (len(v) + 1 if p < 0 else 0), t + (len(vt) + 1 if t < 0 else 0)
                    out.add(tuple(v[p - 1] + (vt[t - 1] if t else [])))
        return out
    _, doc, buf = load(path)
    out = set()
    for _, _, prim in primitives(doc):
        if prim.get("mode", 4) != 4 or "TEXCOORD_0" not in prim["attributes"]:
            continue
        pos = accessor_values(doc, buf, prim["attributes"]["POSITION"])
        uv = accessor_values(doc, buf, prim["attributes"]["TEXCOORD_0"])
        out.update(tuple(pos[i] + uv[i]) for i in triangles(doc, buf, prim))
    return out


def cmd_uvcorners(a, b, tolerance, position_tolerance):
    sets = uv_corners(a), uv_corners(b)
    bad = 0
    for (x, y), (one, other) in zip((sets, sets[::-1]), ((a, b), (b, a))):
        for c in sorted(x):
            if not any(len(c) == len(d) and close(c[:3], d[:3], position_tolerance) and close(c[3:], d[3:], tolerance)
                       for d in y):
                print("%s: corner %s: none in %s within %g" % (one, c, other, tolerance))
                bad = 1
    if not sets[0]:
        print("%s: no textured corner" % a)
        bad = 1
    return bad


def cmd_drc(path, stem):
    _, doc, buf = load(path)
    k = 0
    for _, _, prim in primitives(doc):
        draco = prim.get("extensions", {}).get("KHR_draco_mesh_compression")
        if draco:
            with open("%s_%d.drc" % (stem, k), "wb") as f:
                f.write(view_bytes(doc, buf, draco["bufferView"]))
            k += 1
    if not k:
        print("%s: no Draco-compressed primitive" % path)
    return 0 if k else 1


def cmd_nodraco(path):
    text = load(path)[0]
    if "KHR_draco_mesh_compression" in text:
        print("%s still mentions KHR_draco_mesh_compression" % path)
        return 1
    return 0


def png(width, height, rgb):
    """A valid PNG of one colour (the validator reads image headers)."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    rows = b"".join(b"\0" + bytes(rgb) * width for _ in range(height))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def cmd_scattered(folder):
    """The seam sphere spread as real files are: FOLDER/a/model.gltf with
    three buffers (geometry.bin, a data URI, sub/extra.bin), TEXCOORD_0,
    COLOR_0 (normalized bytes), an application-specific _TEMPERATURE, and
    two images, one outside the model's folder (../tex/checker.png) and one
    in a subfolder (img/inside.png); POSITION's min/max are wider than its
    values, as some exporters write them."""
    tmp = os.path.join(folder, "sphere.gltf")
    os.makedirs(os.path.join(folder, "a", "sub"), exist_ok=True)
    os.makedirs(os.path.join(folder, "a", "img"), exist_ok=True)
    os.makedirs(os.path.join(folder, "tex"), exist_ok=True)
    cmd_sphere(tmp)
    _, doc, buf = load(tmp)
    os.remove(tmp)
    n = doc["accessors"][0]["count"]
    positions, normals, uvs, indices = (accessor_bytes(doc, buf, i) for i in range(4))
    colours = b"".join(bytes((i * 7 % 256, i * 13 % 256, i * 29 % 256, 255 - i % 64)) for i in range(n))
    temperature = b"".join(struct.pack("<f", 20 + 0.25 * i) for i in range(n))
    geometry = positions + indices + b"\0" * (-len(indices) % 4)
    extra = uvs + colours + temperature
    doc["accessors"] += [{"bufferView": 4, "componentType": 5121, "normalized": True, "count": n, "type": "VEC4"},
                         {"bufferView": 5, "componentType": 5126, "count": n, "type": "SCALAR"}]
    doc["accessors"][0]["min"] = [round(v - 0.05, 1) for v in doc["accessors"][0]["min"]]
    doc["accessors"][0]["max"] = [round(v + 0.05, 1) for v in doc["accessors"][0]["max"]]
    doc["bufferViews"] = [
        {"buffer": 0, "byteOffset": 0, "byteLength": 12 * n, "target": 34962},
        {"buffer": 1, "byteOffset": 0, "byteLength": 12 * n, "target": 34962},
        {"buffer": 2, "byteOffset": 0, "byteLength": 8 * n, "target": 34962},
        {"buffer": 0, "byteOffset": 12 * n, "byteLength": len(indices), "target": 34963},
        {"buffer": 2, "byteOffset": 8 * n, "byteLength": 4 * n, "target": 34962},
        {"buffer": 2, "byteOffset": 12 * n, "byteLength": 4 * n, "target": 34962}]
    doc["meshes"][0]["primitives"][0]["attributes"].update({"COLOR_0": 4, "_TEMPERATURE": 5})
    doc["meshes"][0]["primitives"][0]["material"] = 0
    doc["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}, "emissiveTexture": {"index": 1},
                         "emissiveFactor": [1, 1, 1]}]
    doc["textures"] = [{"source": 0}, {"source": 1}]
    doc["images"] = [{"uri": "../tex/checker.png"}, {"uri": "img/inside.png"}]
    doc["buffers"] = [{"byteLength": len(geometry), "uri": "geometry.bin"},
                      {"byteLength": len(normals),
                       "uri": "data:application/octet-stream;base64," + base64.b64encode(normals).decode()},
                      {"byteLength": len(extra), "uri": "sub/extra.bin"}]
    for name, data in [("a/geometry.bin", geometry), ("a/sub/extra.bin", extra),
                       ("tex/checker.png", png(4, 4, (200, 30, 30))), ("a/img/inside.png", png(2, 2, (0, 90, 200)))]:
        with open(os.path.join(folder, name), "wb") as f:
            f.write(data)
    with open(os.path.join(folder, "a", "model.gltf"), "w") as f:
        json.dump(doc, f, indent=1)
    return 0


def cmd_metadata(a, b):
    def tables(path):
        _, doc, buf = load(path)
        out = {}
        for t, table in enumerate(doc["extensions"]["EXT_structural_metadata"]["propertyTables"]):
            for name, prop in table["properties"].items():
                for k in ("values", "arrayOffsets", "stringOffsets"):
                    if k in prop:
                        out[(t, name, k)] = view_bytes(doc, buf, prop[k])
        return out
    before, after = tables(a), tables(b)
    for k in sorted(before):
        if after.get(k) != before[k]:
            print("%s: property table %d, %s's %s: %r, %s's %r" % (b, k[0], k[1], k[2], after.get(k), a, before[k]))
            return 1
    return 0 if before and before.keys() == after.keys() else 1


def cmd_packed(path):
    """Every byte of every buffer lies in a bufferView but for padding (fewer
    than 4 bytes between views), and every accessor and bufferView is used:
    nothing unused was left behind."""
    _, doc, buf = load(path)
    problems = []
    for b, data in enumerate(buf):
        spans = sorted((v.get("byteOffset", 0), v.get("byteOffset", 0) + v["byteLength"])
                       for v in doc.get("bufferViews", []) if v["buffer"] == b)
        end = 0
        for start, stop in spans:
            if start - end >= 4:
                problems.append("buffer %d: bytes %d to %d are in no bufferView" % (b, end, start))
            end = max(end, stop)
        if len(data) - end >= 4:
            problems.append("buffer %d: its last %d bytes are in no bufferView" % (b, len(data) - end))
    used_accessors, used_views = set(), set()
    for _, _, prim in primitives(doc):
        for attributes in [prim["attributes"]] + prim.get("targets", []):
            used_accessors.update(attributes.values())
        if "indices" in prim:
            used_accessors.add(prim["indices"])
        draco = prim.get("extensions", {}).get("KHR_draco_mesh_compression")
        if draco:
            used_views.add(draco["bufferView"])
    for skin in doc.get("skins", []):
        used_accessors.add(skin.get("inverseBindMatrices"))
    for animation in doc.get("animations", []):
        for sampler in animation.get("samplers", []):
            used_accessors.update((sampler["input"], sampler["output"]))
    for image in doc.get("images", []):
        used_views.add(image.get("bufferView"))
    for i, a in enumerate(doc.get("accessors", [])):
        if i not in used_accessors:
            problems.append("accessors[%d] is unused" % i)
        used_views.add(a.get("bufferView"))
        for part in ("indices", "values"):
            used_views.add(a.get("sparse", {}).get(part, {}).get("bufferView"))
    for i in range(len(doc.get("bufferViews", []))):
        if i not in used_views:
            problems.append("bufferViews[%d] is unused" % i)
    for p in problems:
        print("%s: %s" % (path, p))
    return 1 if problems else 0


def cmd_bounds(path):
    """Every accessor with min/max declares its values' exact bounds."""
    _, doc, buf = load(path)
    bad = 0
    for i, a in enumerate(doc.get("accessors", [])):
        if "min" not in a or ("bufferView" not in a and "sparse" not in a):
            continue
        doc["accessors"][i] = {k: v for k, v in a.items() if k != "normalized"}  # bounds are of the stored values
        values = accessor_values(doc, buf, i)
        for c in range(len(a["min"])):
            lo, hi = min(v[c] for v in values), max(v[c] for v in values)
            if a["min"][c] != lo or a["max"][c] != hi:
                print("%s: accessors[%d] component %d declares [%r, %r], its values span [%r, %r]"
                      % (path, i, c, a["min"][c], a["max"][c], lo, hi))
                bad += 1
    return 1 if bad else 0


def stored_triangles(path):
    """(positions as stored, corners, normals as they stand for) of each
    uncompressed TRIANGLES primitive of the file."""
    _, doc, buf = load(path)
    for _, _, prim in primitives(doc):
        if prim.get("mode", 4) != 4 or "KHR_draco_mesh_compression" in prim.get("extensions", {}):
            continue
        a = prim["attributes"]
        raw = copy.deepcopy(doc)
        raw["accessors"][a["POSITION"]].pop("normalized", None)
        normals = accessor_values(doc, buf, a["NORMAL"]) if "NORMAL" in a else None
        yield accessor_values(raw, buf, a["POSITION"]), triangles(doc, buf, prim), normals


def cmd_prims(path, stem):
    k = 0
    for positions, corners, _ in stored_triangles(path):
        with open("%s_%d.off" % (stem, k), "w") as f:
            f.write("OFF\n%d %d 0\n" % (len(positions), len(corners) // 3))
            f.writelines("%.17g %.17g %.17g\n" % tuple(p) for p in positions)
            f.writelines("3 %d %d %d\n" % tuple(corners[i:i + 3]) for i in range(0, len(corners), 3))
        k += 1
    return 0 if k else 1


def off_normals_agree(what, positions, corners, normals, vnconvert, method, degrees):
    """Prints and counts the vertices whose normal is more than `degrees`
    from vnconvert's on the OFF of positions and corners (but those no
    face contributes to, which get a fallback)."""
    bad = 0
    for i, (n, r) in enumerate(zip(normals, vnconvert_normals(vnconvert, method, positions, corners))):
        if not any(r):
            continue
        cosine = sum(x * y for x, y in zip(unit(n), unit(r)))
        if cosine < math.cos(math.radians(degrees)):
            print("%s: vertex %d has normal %s, vnconvert computes %s" % (what, i, n, r))
            bad += 1
    return bad


def cmd_ownnormals(path, vnconvert, method, degrees):
    bad = 0
    for k, (positions, corners, normals) in enumerate(stored_triangles(path)):
        bad += off_normals_agree("%s primitive %d" % (path, k), positions, corners, normals, vnconvert, method, degrees)
    return 1 if bad else 0


def cmd_drcnormals(path, vnconvert, method, degrees):
    with open(path) as f:
        d = json.load(f)
    p, n = d["positions"], d["normals"]
    return 1 if off_normals_agree(path, [p[i:i + 3] for i in range(0, len(p), 3)], d["indices"],
                                  [n[i:i + 3] for i in range(0, len(n), 3)], vnconvert, method, degrees) else 0


def cmd_materials(path):
    _, doc, buf = load(path)
    seen = {}
    for _, _, prim in primitives(doc):
        if prim.get("mode", 4) != 4:
            continue
        m = doc["materials"][prim["material"]] if "material" in prim else {"name": "(none)"}
        pbr = m.get("pbrMetallicRoughness", {})

        def image(tex):
            if tex is None:
                return "-"
            img = doc["images"][doc["textures"][tex["index"]]["source"]]
            data = image_bytes(doc, buf, img, os.path.dirname(path))
            return "%s %s" % (img.get("mimeType", "?"), hashlib.sha1(data).hexdigest())
        key = "%s | colour %s | metallic %.6f | roughness %.6f | %s | image %s | normal %s %.6f | emissive %s %s" % (
            m.get("name", "?"), " ".join("%.6f" % c for c in pbr.get("baseColorFactor", [1, 1, 1, 1])),
            pbr.get("metallicFactor", 1), pbr.get("roughnessFactor", 1), m.get("alphaMode", "OPAQUE"),
            image(pbr.get("baseColorTexture")), image(m.get("normalTexture")),
            m.get("normalTexture", {}).get("scale", 1), " ".join("%.6f" % c for c in m.get("emissiveFactor", [0, 0, 0])),
            image(m.get("emissiveTexture")))
        pos = accessor_values(doc, buf, prim["attributes"]["POSITION"])
        corners = triangles(doc, buf, prim)
        points, area = seen.setdefault(key, (set(), [0.0]))
        for t in range(0, len(corners) - 2, 3):
            p = [pos[i] for i in corners[t:t + 3]]
            c = cross(sub(p[1], p[0]), sub(p[2], p[0]))
            area[0] += 0.5 * math.sqrt(sum(x * x for x in c))
            points.update(tuple(round(x, 5) + 0.0 for x in q) for q in p)
    for key in sorted(seen):
        points, area = seen[key]
        print("%s | area %.6f | %d positions %s" % (key, area[0], len(points),
                                                    hashlib.sha1(repr(sorted(points)).encode()).hexdigest()))
    return 0


def main(argv):
    if len(argv) == 4 and argv[1] == "drc":
        return cmd_drc(argv[2], argv[3])
    if len(argv) == 3 and argv[1] == "nodraco":
        return cmd_nodraco(argv[2])
    if len(argv) >= 4 and argv[1] == "diff":
        return cmd_diff(argv[2], argv[3], "--tangents-dropped" in argv[4:])
    if len(argv) == 4 and argv[1] == "seams" and argv[3] in ("same", "differ"):
        return cmd_seams(argv[2], argv[3])
    if len(argv) == 3 and argv[1] == "quantized":
        return cmd_quantized(argv[2])
    if len(argv) == 7 and argv[1] == "crease":
        return cmd_crease(argv[2], argv[3], int(argv[4]), argv[5], argv[6])
    if len(argv) == 6 and argv[1] == "morph" and argv[5] in ("weld", "split"):
        return cmd_morph(argv[2], argv[3], argv[4], argv[5] == "weld")
    if len(argv) == 3 and argv[1] in ("flat", "morphsphere", "cylinder", "twosided", "twosided-shared", "uvtriangle"):
        return {"flat": cmd_flat, "morphsphere": cmd_morphsphere, "cylinder": cmd_cylinder,
                "twosided": cmd_twosided, "twosided-shared": cmd_twosided_shared,
                "uvtriangle": cmd_uvtriangle}[argv[1]](argv[2])
    if len(argv) in (5, 6) and argv[1] == "uvcorners":
        return cmd_uvcorners(argv[2], argv[3], float(argv[4]), float(argv[-1]))
    if len(argv) == 4 and argv[1] == "metadata":
        return cmd_metadata(argv[2], argv[3])
    if len(argv) == 5 and argv[1] == "samenormals":
        return cmd_samenormals(argv[2], argv[3], float(argv[4]))
    if len(argv) == 4 and argv[1] in ("twosided-check", "twosided-shared-check"):
        return {"twosided-check": cmd_twosided_check,
                "twosided-shared-check": cmd_twosided_shared_check}[argv[1]](argv[2], float(argv[3]))
    if len(argv) == 3 and argv[1] in ("scattered", "packed", "bounds", "materials"):
        return {"scattered": cmd_scattered, "packed": cmd_packed, "bounds": cmd_bounds,
                "materials": cmd_materials}[argv[1]](argv[2])
    if len(argv) == 4 and argv[1] == "prims":
        return cmd_prims(argv[2], argv[3])
    if len(argv) == 6 and argv[1] in ("ownnormals", "drcnormals"):
        return {"ownnormals": cmd_ownnormals, "drcnormals": cmd_drcnormals}[argv[1]](argv[2], argv[3], argv[4], float(argv[5]))
    if len(argv) == 3 and argv[1] in ("sphere", "shapes"):
        return cmd_sphere(argv[2], shapes=argv[1] == "shapes")
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
