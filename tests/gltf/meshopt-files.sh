#!/usr/bin/env bash
# Writes the meshopt test files of tests/data/gltf/meshopt/ (see its README) with the real tools:
#   meshopt-files.sh NODE_MODULES_DIR [OUTDIR]
# NODE_MODULES_DIR holds gltfpack, @gltf-transform/cli and meshoptimizer (npm install gltfpack
# @gltf-transform/cli meshoptimizer);
# OUTDIR defaults to tests/data/gltf/meshopt. Not run by the tests: its outputs are committed.
set -euo pipefail
BIN=$(cd "$1/.bin" && pwd)
HERE=$(cd "$(dirname "$0")" && pwd)
OUT=$(mkdir -p "${2:-$HERE/../data/gltf/meshopt}" && cd "${2:-$HERE/../data/gltf/meshopt}" && pwd)
M=$HERE/../data/models/gltf
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT

# untextured IN OUT: a GLB without its images (what keeps the test files small).
untextured() {
  python3 - "$1" "$2" <<'PY'
import json, struct, sys
raw = open(sys.argv[1], "rb").read()
n = struct.unpack("<I", raw[12:16])[0]
d = json.loads(raw[20:20 + n])
for key in ("images", "textures", "samplers"):
    d.pop(key, None)
for m in d.get("materials", []):
    for part in (m, m.get("pbrMetallicRoughness", {})):
        for k in [k for k in part if k.endswith("Texture")]:
            del part[k]
text = json.dumps(d).encode()
text += b" " * (-len(text) % 4)
bin_chunk = raw[20 + n:]
open(sys.argv[2], "wb").write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + len(bin_chunk)) +
                              struct.pack("<II", len(text), 0x4E4F534A) + text + bin_chunk)
PY
}
untextured "$M/Duck.glb" "$T/duck.glb"
untextured "$M/CesiumMan.glb" "$T/man.glb"

# The Duck with its image replaced by a 1 x 1 PNG (a data URI), textured still:
# gltfpack quantizes its texture coordinates and puts their dequantization in
# the material's KHR_texture_transform.
python3 - "$M/Duck.glb" "$T/duck-tiny.glb" <<'PY'
import base64, json, struct, sys, zlib
raw = open(sys.argv[1], "rb").read()
n = struct.unpack("<I", raw[12:16])[0]
d = json.loads(raw[20:20 + n])
def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 1, 1, 8, 2, 0, 0, 0)) +
       chunk(b"IDAT", zlib.compress(b"\x00\xff\xc8\x00")) + chunk(b"IEND", b""))
d["images"] = [{"uri": "data:image/png;base64," + base64.b64encode(png).decode()}]
text = json.dumps(d).encode()
text += b" " * (-len(text) % 4)
bin_chunk = raw[20 + n:]
open(sys.argv[2], "wb").write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + len(bin_chunk)) +
                              struct.pack("<II", len(text), 0x4E4F534A) + text + bin_chunk)
PY
"$BIN/gltfpack" -i "$T/duck-tiny.glb" -o "$OUT/duck-tt.glb"

# EXT_meshopt_compression in a GLB, fallback without data: OCTAHEDRAL normals, TRIANGLES indices.
"$BIN/gltfpack" -i "$T/duck.glb" -o "$OUT/duck-cc.glb" -cc
# .gltf with its .bin, fallback without data, no filters.
mkdir -p "$OUT/duck-c"
"$BIN/gltfpack" -i "$T/duck.glb" -o "$OUT/duck-c/duck-c.gltf" -c
# A fallback buffer with data (.fallback.bin): the extension is used, not required.
mkdir -p "$OUT/morph-cf"
"$BIN/gltfpack" -i "$M/AnimatedMorphCube/AnimatedMorphCube.gltf" -o "$OUT/morph-cf/morph-cf.gltf" -cf
# Morph targets (their NORMALs too) and a weights animation.
"$BIN/gltfpack" -i "$M/AnimatedMorphCube/AnimatedMorphCube.gltf" -o "$OUT/morph-cc.glb" -cc
# Skin and animations: QUATERNION rotations, EXPONENTIAL translations and scales, 64-byte matrices.
"$BIN/gltfpack" -i "$T/man.glb" -o "$OUT/man-cc.glb" -cc
# Float normals: EXPONENTIAL, in one view with the morph targets' NORMALs.
"$BIN/gltfpack" -i "$M/AnimatedMorphCube/AnimatedMorphCube.gltf" -o "$OUT/morph-vnf.glb" -cc -vnf
# glTF-Transform's encoder (its own bufferView order and filters).
"$BIN/gltf-transform" meshopt "$T/duck.glb" "$OUT/duck-gt.glb" >/dev/null
# KHR_meshopt_compression as gltfpack writes it: vertex data of bitstream version 1.
"$BIN/gltfpack" -i "$M/AnimatedMorphCube/AnimatedMorphCube.gltf" -o "$OUT/morph-khr-v1.glb" -cc -ce khr
# KHR_meshopt_compression of version 0 data: the EXT file with the extension renamed, the
# conversion the KHR specification names lossless.
sed 's/EXT_meshopt_compression/KHR_meshopt_compression/g' "$OUT/duck-c/duck-c.gltf" > "$OUT/duck-c/duck-khr.gltf"
# A triangle whose NORMAL shares an EXPONENTIAL view with an attribute `_DATA` whose components
# have exponents of their own (the filter's Separate mode), written with npm's meshoptimizer
# encoder: the view cannot keep its filter when the normals are encoded again.
node --input-type=module - "$1" "$OUT/exp-separate.gltf" <<'JS'
import { createRequire } from 'node:module';
import { writeFileSync } from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
const [modules, out] = process.argv.slice(2);
const where = createRequire(path.join(path.resolve(modules), 'x.js')).resolve('meshoptimizer/encoder');
const { MeshoptEncoder } = await import(pathToFileURL(where));
await MeshoptEncoder.ready;
const view = new Float32Array([1, 0, 0, 1, 0, 0, 1, 0, 0, 1000, 0.001, 3, 1e5, 1e-5, 7, 0.5, 2e-6, 9]);
const filtered = MeshoptEncoder.encodeFilterExp(view, 6, 12, 23, 'Separate');
const compressed = MeshoptEncoder.encodeGltfBuffer(filtered, 6, 12, 'ATTRIBUTES', 0);
const positions = Buffer.from(new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0]).buffer);
const data = Buffer.concat([positions, Buffer.from(compressed)]);
const gltf = {
  asset: { version: '2.0', generator: 'tests/gltf/meshopt-files.sh' },
  extensionsUsed: ['EXT_meshopt_compression'],
  extensionsRequired: ['EXT_meshopt_compression'],
  scene: 0, scenes: [{ nodes: [0] }], nodes: [{ mesh: 0 }],
  meshes: [{ primitives: [{ attributes: { POSITION: 0, NORMAL: 1, _DATA: 2 } }] }],
  accessors: [
    { bufferView: 0, componentType: 5126, count: 3, type: 'VEC3', min: [0, 0, 0], max: [1, 1, 0] },
    { bufferView: 1, componentType: 5126, count: 3, type: 'VEC3' },
    { bufferView: 1, byteOffset: 36, componentType: 5126, count: 3, type: 'VEC3' },
  ],
  bufferViews: [
    { buffer: 0, byteLength: 36, target: 34962 },
    { buffer: 1, byteLength: 72, byteStride: 12, target: 34962, extensions: { EXT_meshopt_compression: {
      buffer: 0, byteOffset: 36, byteLength: compressed.length, byteStride: 12, mode: 'ATTRIBUTES',
      filter: 'EXPONENTIAL', count: 6 } } },
  ],
  buffers: [
    { byteLength: data.length, uri: `data:application/octet-stream;base64,${data.toString('base64')}` },
    { byteLength: 72, extensions: { EXT_meshopt_compression: { fallback: true } } },
  ],
};
writeFileSync(out, JSON.stringify(gltf, null, 2) + '\n');
JS
