#!/usr/bin/env python3
"""Writes the small glTF files of tests/data/gltf/wild/, one per defect seen in
public files (issue 14), each valid for the Khronos glTF-Validator:

  no-buffers.gltf        no buffers array: a material whose image is a data-URI PNG
  no-binary.gltf         no binary data at all: a scene and a node
  unknown-ext.gltf       a square over three buffers (base64 data URI, percent-encoded
                         data URI, a file) and an image in a subfolder, under an
                         extension vn does not know that holds an accessor index
  extra-bytes.glb        a GLB with 4 bytes after its declared length (GLB_EXTRA_DATA)
  placeholder.glb        a GLB with an unused buffer that has no uri
  images.gltf            images as data URIs of PNG, WebP
                         (EXT_texture_webp) and KTX2 (without KHR_texture_basisu)
  ktx2-file.gltf         a KTX2 image by file, without KHR_texture_basisu
  two-vertices.gltf      a non-indexed TRIANGLES primitive of 2 vertices (no triangle)
  no-data.gltf           a buffer without uri that nothing reads (GLB output refused:
                         its buffer 0 would have to be a BIN chunk)
  gltf1.gltf             glTF 1.0 (refused, naming the version)

  wild.py FOLDER    writes them into FOLDER (magnum-2d-mips.ktx2 must be there:
                    a KTX2 image from mosra/magnum-plugins' tests, MIT)
"""
import base64
import json
import os
import struct
import sys
import urllib.parse

PNG = base64.b64decode("iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAIAAACQd1PeAAAADElEQVQYV2P4z/AfAAQAAf+I0P3MAAAAAElFTkSuQmCC")
WEBP = base64.b64decode("UklGRhoAAABXRUJQVlA4TA0AAAAvAAAAEAcQERGIiP4HAA==")

# A unit square: 4 positions, 4 normals, 2 triangles.
POSITIONS = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0)
NORMALS = struct.pack("<12f", *([0, 0, 1] * 4))
INDICES = struct.pack("<6H", 0, 1, 2, 0, 2, 3)


def square(buffer_of):
    """Accessors and views of the square; buffer_of(name) -> buffer index."""
    views = [
        {"buffer": buffer_of("positions"), "byteLength": 48, "target": 34962},
        {"buffer": buffer_of("normals"), "byteLength": 48, "target": 34962},
        {"buffer": buffer_of("indices"), "byteLength": 12, "target": 34963},
    ]
    accessors = [
        {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
        {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"},
    ]
    mesh = {"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}
    return views, accessors, mesh


def document(**parts):
    d = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}]}
    d.update(parts)
    return d


def glb(doc, binary):
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    binary += b"\0" * (-len(binary) % 4)
    total = 12 + 8 + len(text) + 8 + len(binary)
    return (struct.pack("<III", 0x46546C67, 2, total) + struct.pack("<II", len(text), 0x4E4F534A) + text +
            struct.pack("<II", len(binary), 0x004E4942) + binary)


def textured(images, extensions=None, samplers=True):
    """A material per image, unused by any mesh (the images are what is tested)."""
    textures = []
    for i, image in enumerate(images):
        t = {"source": i}
        if image.pop("_webp", False):
            t = {"extensions": {"EXT_texture_webp": {"source": i}}}
        textures.append(t)
    d = {"asset": {"version": "2.0"}, "images": images, "textures": textures,
         "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": i}}} for i in range(len(images))]}
    if extensions:
        d["extensionsUsed"] = extensions
    return d


def main(folder):
    def write(name, data):
        with open(os.path.join(folder, name), "wb") as f:
            f.write(data)

    def write_json(name, doc):
        write(name, (json.dumps(doc, indent=1) + "\n").encode())

    with open(os.path.join(folder, "magnum-2d-mips.ktx2"), "rb") as f:
        ktx2 = f.read()

    write_json("no-buffers.gltf", textured([{"uri": "data:image/png;base64," + base64.b64encode(PNG).decode()}]))
    write_json("no-binary.gltf", {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
                                  "nodes": [{"name": "empty"}]})

    # Three buffers: base64 data URI, percent-encoded data URI (RFC 2397 without
    # ;base64), a file; and an image in a subfolder.
    views, accessors, mesh = square({"positions": 0, "normals": 2, "indices": 1}.get)
    os.makedirs(os.path.join(folder, "wild-textures"), exist_ok=True)
    write("wild-textures/pixel.png", PNG)
    write("unknown-ext-normals.bin", NORMALS)
    write_json("unknown-ext.gltf", document(
        extensionsUsed=["VN_test_unknown"],
        nodes=[{"mesh": 0, "extensions": {"VN_test_unknown": {"accessor": 0}}}],
        meshes=[mesh], materials=[{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        textures=[{"source": 0}], images=[{"uri": "wild-textures/pixel.png"}],
        accessors=accessors, bufferViews=views,
        buffers=[{"byteLength": 48, "uri": "data:application/octet-stream;base64," + base64.b64encode(POSITIONS).decode()},
                 {"byteLength": 12, "uri": "data:application/gltf-buffer," + urllib.parse.quote(INDICES, safe="")},
                 {"byteLength": 48, "uri": "unknown-ext-normals.bin"}]))

    views, accessors, mesh = square(lambda name: 0)
    for i, v in enumerate(views):
        v["byteOffset"] = [0, 48, 96][i]
    binary = POSITIONS + NORMALS + INDICES
    one = document(meshes=[mesh], accessors=accessors, bufferViews=views, buffers=[{"byteLength": len(binary)}])
    write("extra-bytes.glb", glb(one, binary) + b"\0\0\0\0")
    two = document(meshes=[mesh], accessors=accessors, bufferViews=views,
                   buffers=[{"byteLength": len(binary)}, {"byteLength": 8, "name": "placeholder"}])
    write("placeholder.glb", glb(two, binary))

    write_json("images.gltf", textured([
        {"uri": "data:image/png;base64," + base64.b64encode(PNG).decode()},
        {"uri": "data:image/webp;base64," + base64.b64encode(WEBP).decode(), "_webp": True},
        {"uri": "data:image/ktx2;base64," + base64.b64encode(ktx2).decode()}], ["EXT_texture_webp"]))
    write_json("ktx2-file.gltf", textured([{"uri": "magnum-2d-mips.ktx2"}]))

    two_vertices = struct.pack("<6f", 0, 0, 0, 1, 0, 0)
    views, accessors, mesh = square(lambda name: 0)
    for i, v in enumerate(views):
        v["byteOffset"] = [0, 48, 96][i]
    views.append({"buffer": 0, "byteOffset": 108, "byteLength": 24, "target": 34962})
    accessors.append({"bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC3", "min": [0, 0, 0], "max": [1, 0, 0]})
    mesh["primitives"].append({"attributes": {"POSITION": 3}})
    payload = POSITIONS + NORMALS + INDICES + two_vertices
    write_json("two-vertices.gltf", document(
        meshes=[mesh], accessors=accessors, bufferViews=views,
        buffers=[{"byteLength": len(payload), "uri": "data:application/octet-stream;base64," + base64.b64encode(payload).decode()}]))

    write_json("no-data.gltf", {"asset": {"version": "2.0"}, "buffers": [{"byteLength": 4}]})
    write_json("gltf1.gltf", {"asset": {"version": "1.0"}, "buffers": {"b": {"uri": "b.bin", "byteLength": 4}},
                              "scene": "s", "scenes": {"s": {"nodes": []}}})


if __name__ == "__main__":
    main(sys.argv[1])
