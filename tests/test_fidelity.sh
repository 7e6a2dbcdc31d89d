#!/usr/bin/env bash
# glTF files as they are found in practice (several buffers, images outside
# the model's folder, extra attributes, in-place edits, bad bounds, NaN):
# nothing lost, nothing left behind, nothing written outside OUT's folder.
#   test_fidelity.sh PATH/TO/vnconvert NODE_MODULES_DIR GLTF_SAMPLE_DIR
set -u
VNC=$1
MODULES=$2
DATA=$3
HERE=$(cd "$(dirname "$0")" && pwd)
CHECK="python3 $HERE/gltf/gltfcheck.py"
VALIDATE="node $HERE/gltf/validate.mjs $MODULES"
. "$(dirname "$0")/lib.sh"
in_json() { python3 -c "import sys; sys.path.insert(0, '$HERE/gltf'); import gltfcheck as g
_, d, b = g.load(sys.argv[1]); sys.exit(0 if eval(sys.argv[2]) else 1)" "$@"; }

$CHECK scattered "$T/s"
M=$T/s/a/model.gltf

# A GLB holds everything in its BIN chunk: three buffers merged, both images
# embedded (no DATA_URI_GLB or URI_GLB from the validator), nothing else
# changed, no unused bytes.
run "$VNC" "$M" "$T/s/out.glb" -q
check "scattered -> glb exits 0" [ $rc -eq 0 ]
check "glb: one buffer, no uri" in_json "$T/s/out.glb" "len(d['buffers']) == 1 and 'uri' not in d['buffers'][0]"
check "glb: images embedded with their type" in_json "$T/s/out.glb" \
  "all('uri' not in i and i['mimeType'] == 'image/png' and 'bufferView' in i for i in d['images'])"
check "glb: structure and bytes" $CHECK diff "$M" "$T/s/out.glb"
check "glb: packed" $CHECK packed "$T/s/out.glb"
check "glb: no new validator issue, info included" $VALIDATE "$M" "$T/s/out.glb"

# .gltf into another folder: images go inside OUT's folder; one that was
# outside the model's folder (../tex) is copied in under its own name.
mkdir -p "$T/s/b/c"
run "$VNC" "$M" "$T/s/b/c/out.gltf" -q
check "scattered -> b/c/out.gltf exits 0" [ $rc -eq 0 ]
check "../tex image copied into OUT's folder" cmp -s "$T/s/tex/checker.png" "$T/s/b/c/checker.png"
check "subfolder image copied with its folder" cmp -s "$T/s/a/img/inside.png" "$T/s/b/c/img/inside.png"
check "nothing written outside OUT's folder" [ ! -e "$T/s/b/tex" ] && check "only b/c in b" [ "$(ls -A "$T/s/b")" = c ]
check "the image URI points inside" in_json "$T/s/b/c/out.gltf" "d['images'][0]['uri'] == 'checker.png'"
check "b/c/out.gltf: structure and bytes" $CHECK diff "$M" "$T/s/b/c/out.gltf"
check "b/c/out.gltf: packed" $CHECK packed "$T/s/b/c/out.gltf"
# Split accessors declare their own bounds, not the input's wrong ones.
run "$VNC" "$M" "$T/s/b/c/crease.gltf" -q --crease-angle 10
check "split accessors: exact bounds" $CHECK bounds "$T/s/b/c/crease.gltf"

# OUT a link into another folder: the .gltf replaces the link's target, and
# its buffer and images go beside it there, where its URIs point.
mkdir -p "$T/real" "$T/links" && ln -s ../real/linked.gltf "$T/links/m.gltf"
run "$VNC" "$DATA/Duck/Duck.gltf" "$T/links/m.gltf" -q
check "through a link: exits 0" [ $rc -eq 0 ]
check "through a link: the link stays" [ -L "$T/links/m.gltf" ]
check "through a link: buffer and image beside the target" [ -f "$T/real/linked.bin" ] && [ -f "$T/real/DuckCM.png" ]
check "through a link: nothing beside the link" [ "$(ls -A "$T/links")" = m.gltf ]
check "through a link: structure" $CHECK diff "$DATA/Duck/Duck.gltf" "$T/real/linked.gltf"

# A .gltf written beside its input under another name never replaces the
# input's buffer files (geometry.gltf would be written as geometry.bin).
cp "$T/s/a/geometry.bin" "$T/geometry.before"
run "$VNC" "$M" "$T/s/a/geometry.gltf" -q
check "beside the input: exits 0" [ $rc -eq 0 ]
check "the input's geometry.bin is untouched" cmp -s "$T/geometry.before" "$T/s/a/geometry.bin"
check "its own buffers have other names" in_json "$T/s/a/geometry.gltf" \
  "'geometry.bin' not in [x.get('uri') for x in d['buffers']]"
check "beside the input: structure" $CHECK diff "$M" "$T/s/a/geometry.gltf"

# --in-place on a .gltf keeps its buffer and image URIs: the same files are
# replaced (atomically), none is added.
mkdir -p "$T/duck" && cp "$DATA/Duck/"* "$T/duck/"
before=$(ls "$T/duck")
run "$VNC" "$T/duck/Duck.gltf" "$T/duck/Duck.gltf" --in-place -q
check "in place exits 0" [ $rc -eq 0 ]
check "in place: the same files, none added" [ "$(ls -A "$T/duck")" = "$before" ]
check "in place: buffer URI kept" in_json "$T/duck/Duck.gltf" "d['buffers'][0]['uri'] == 'Duck0.bin'"
check "in place: structure" $CHECK diff "$DATA/Duck/Duck.gltf" "$T/duck/Duck.gltf"
check "in place: normals changed" not cmp -s "$DATA/Duck/Duck0.bin" "$T/duck/Duck0.bin"

# Nothing vn adds or replaces stays unused: a primitive without NORMAL under
# --draco on (the NORMAL accessor vn adds, then compresses), a split sphere,
# a multi-buffer file whose first buffer ends up with no view.
$CHECK sphere "$T/sp.gltf"
python3 - "$HERE/gltf" "$T/sp.gltf" "$T/nonormal.gltf" <<'EOF'
import base64, json, sys
sys.path.insert(0, sys.argv[1])
import gltfcheck as g
_, d, b = g.load(sys.argv[2])
# Without NORMAL's accessor, bufferView and bytes: the input has nothing unused.
data = g.accessor_bytes(d, b, 0) + g.accessor_bytes(d, b, 2) + g.accessor_bytes(d, b, 3)
n = d["accessors"][0]["count"]
d["accessors"] = [dict(d["accessors"][i], bufferView=k) for k, i in enumerate((0, 2, 3))]
d["bufferViews"] = [{"buffer": 0, "byteOffset": 0, "byteLength": 12 * n, "target": 34962},
                    {"buffer": 0, "byteOffset": 12 * n, "byteLength": 8 * n, "target": 34962},
                    {"buffer": 0, "byteOffset": 20 * n, "byteLength": len(data) - 20 * n, "target": 34963}]
d["meshes"][0]["primitives"][0]["attributes"] = {"POSITION": 0, "TEXCOORD_0": 1}
d["meshes"][0]["primitives"][0]["indices"] = 2
d["buffers"] = [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}]
json.dump(d, open(sys.argv[3], "w"))
EOF
check "the input without NORMAL is packed itself" $CHECK packed "$T/nonormal.gltf"
for args in "--draco on" "--crease-angle 10" "--crease-angle 10 --draco on" ""; do
  for o in x.glb x.gltf; do
    for f in "$T/nonormal.gltf" "$M"; do
      run "$VNC" "$f" "$T/$o" -q $args
      check "$(basename "$f") -> $o $args: exits 0" [ $rc -eq 0 ]
      check "$(basename "$f") -> $o $args: packed" $CHECK packed "$T/$o"
    done
  done
done
# --draco on: the validator does not read Draco data, so it calls the
# compressed bufferView unused and the extension unsupported.
run "$VNC" "$M" "$T/don.glb" -q --draco on
check "--draco on: no other new validator issue" $VALIDATE --allow UNUSED_OBJECT --allow UNSUPPORTED_EXTENSION "$M" "$T/don.glb"

# --crease-angle on a Draco-compressed primitive: decoded, split, encoded
# again; the same split as on the uncompressed primitive.
"$VNC" "$T/sp.gltf" "$T/spd.glb" -q --draco on
for mode in keep on off; do
  run "$VNC" "$T/spd.glb" "$T/spd-$mode.glb" --crease-angle 10 --draco $mode --stats
  check "Draco --crease-angle ($mode) exits 0" [ $rc -eq 0 ]
  check "Draco --crease-angle ($mode): vertices split" grep -q "^split vertices: *[1-9]" "$T/stdout"
  check "Draco --crease-angle ($mode): packed" $CHECK packed "$T/spd-$mode.glb"
done
"$VNC" "$T/spd-keep.glb" "$T/spd-keep-off.glb" -q --draco off --no-weld
off_count() { in_json "$1" "print(d['accessors'][d['meshes'][0]['primitives'][0]['attributes']['POSITION']]['count']) or True"; }
check "Draco split keeps as many vertices as split uncompressed" [ "$(off_count "$T/spd-keep-off.glb")" = "$(off_count "$T/spd-off.glb")" ]
check "Draco split: valid" $VALIDATE "$T/sp.gltf" "$T/spd-off.glb" "$T/spd-keep-off.glb"

# Attributes across formats: glTF -> OFF keeps TEXCOORD_0 and COLOR_0 and
# names what OFF cannot hold; glTF -> Draco -> glTF keeps all three.
run "$VNC" "$M" "$T/m.off"
check "glTF -> OFF exits 0" [ $rc -eq 0 ]
check "glTF -> OFF: colours and texture coordinates" grep -q "^STCNOFF$" "$T/m.off"
check "glTF -> OFF: names what it cannot hold" grep -q "warning: .*_TEMPERATURE" "$T/stderr"
run "$VNC" "$M" "$T/m.drc" -q && run "$VNC" "$T/m.drc" "$T/m2.glb" -q
check "glTF -> drc -> glb exits 0" [ $rc -eq 0 ]
check "glTF -> drc -> glb: TEXCOORD_0, COLOR_0 and _TEMPERATURE" in_json "$T/m2.glb" \
  "set(d['meshes'][0]['primitives'][0]['attributes']) == {'POSITION', 'NORMAL', 'TEXCOORD_0', 'COLOR_0', '_TEMPERATURE'}"
check "glTF -> drc -> glb: _TEMPERATURE values kept (lossless)" in_json "$T/m2.glb" \
  "sorted(v[0] for v in g.accessor_values(d, b, d['meshes'][0]['primitives'][0]['attributes']['_TEMPERATURE'])) == \
   sorted(20 + 0.25 * i for i in range(117))"
check "glTF -> drc -> glb: valid" $VALIDATE "$T/sp.gltf" "$T/m2.glb"
printf 'COFF\n3 1 0\n0 0 0 255 0 0 128\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2\n' >"$T/c.off"
run "$VNC" "$T/c.off" "$T/c.glb" -q
check "COFF -> glb: COLOR_0 as normalized bytes with alpha" in_json "$T/c.glb" \
  "[v for v in g.accessor_values(d, b, d['meshes'][0]['primitives'][0]['attributes']['COLOR_0'])][0] == [1.0, 0.0, 0.0, 128 / 255]"

# Non-finite positions: one behaviour for every output format, a clear
# error, no output and no temporary left.
python3 - "$T/sp.gltf" "$T/nan.gltf" <<'EOF'
import base64, json, struct, sys
d = json.load(open(sys.argv[1]))
uri = d["buffers"][0]["uri"]
data = bytearray(base64.b64decode(uri.split(",", 1)[1]))
struct.pack_into("<f", data, 12 * 5, float("nan"))
d["buffers"][0]["uri"] = uri.split(",", 1)[0] + "," + base64.b64encode(bytes(data)).decode()
json.dump(d, open(sys.argv[2], "w"))
EOF
mkdir -p "$T/nan"
for o in n.glb n.gltf n.drc n.off; do
  run "$VNC" "$T/nan.gltf" "$T/nan/$o"
  check "NaN position -> $o exits 1" [ $rc -eq 1 ]
  check "NaN position -> $o: one line naming the vertex" grep -q "vertex 5 is not finite" "$T/stderr"
done
for args in "--draco on" "--draco off"; do
  run "$VNC" "$T/nan.gltf" "$T/nan/n.glb" $args
  check "NaN position $args exits 1" [ $rc -eq 1 ]
done
check "NaN: no output, no temporary" [ -z "$(ls -A "$T/nan")" ]

# Messages for files that are not glTF.
: >"$T/empty.glb"
head -c 300 /dev/urandom >"$T/random.glb"
printf '{"asset":' >"$T/cut.gltf"
run "$VNC" "$T/empty.glb" "$T/msg.glb"
check "empty .glb: says so" grep -q "empty.glb: the file is empty" "$T/stderr"
run "$VNC" "$T/random.glb" "$T/msg.glb"
check "random .glb: not glTF, in plain words" grep -q "neither a GLB .* nor glTF JSON" "$T/stderr"
check "random .glb: no JSON library text" not grep -q "json.exception" "$T/stderr"
run "$VNC" "$T/cut.gltf" "$T/msg.glb"
check "cut JSON: where" grep -q "malformed at byte 10: unexpected end of input" "$T/stderr"
check "no output for any" [ ! -e "$T/msg.glb" ]

finish
