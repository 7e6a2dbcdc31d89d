#!/usr/bin/env bash
# glTF in vnconvert: fidelity (structural diff, untouched accessors bit for
# bit), seams, shared accessors, primitive modes, errors, OFF round trip.
#   test_gltf.sh PATH/TO/vnconvert GLTF_SAMPLE_DIR PATH/TO/tinygltf_load
# GLTF_SAMPLE_DIR holds the Khronos sample models (tests/data/models/gltf);
# tinygltf_load (tests/gltf/tinygltf_load.cpp) reads files with Debian's tinygltf.
set -u
VNC=$1
DATA=$2
TINYGLTF_LOAD=$3
HERE=$(cd "$(dirname "$0")" && pwd)
CHECK="python3 $HERE/gltf/gltfcheck.py"
SAMPLES=$HERE/../samples
. "$(dirname "$0")/lib.sh"
no_tangent() { python3 -c "import sys; sys.path.insert(0, '$HERE/gltf'); import gltfcheck as g
_, d, _ = g.load(sys.argv[1]); sys.exit(any('TANGENT' in p['attributes'] for _, _, p in g.primitives(d)))" "$1"; }

# Every sample, every method, to .glb and to .gltf: the output differs from
# the input only in its normals (Draco primitives: in their Draco data, which
# test_draco.sh decodes).
models=()
while IFS= read -r f; do models+=("$f"); done < <(find "$DATA" \( -name '*.gltf' -o -name '*.glb' \) | sort)
check "found the sample models" [ ${#models[@]} -ge 10 ]
for f in "${models[@]}"; do
  name=$(basename "${f%.*}")
  for m in $("$VNC" --list-methods | cut -d' ' -f1); do
    mkdir -p "$T/$m"
    run "$VNC" "$f" "$T/$m/$name.glb" -m "$m" -q
    check "$name -> glb ($m) exits 0" [ $rc -eq 0 ]
    check "$name -> glb ($m) structure" $CHECK diff "$f" "$T/$m/$name.glb"
    run "$VNC" "$f" "$T/$m/${name}_out.gltf" -m "$m" -q
    check "$name -> gltf ($m) exits 0" [ $rc -eq 0 ]
    # tinygltf 2.7 insists on a bufferView for indices, which Draco primitives lack.
    if ! grep -q KHR_draco_mesh_compression "$T/$m/${name}_out.gltf"; then
      check "$name ($m): tinygltf reads both outputs" "$TINYGLTF_LOAD" "$T/$m/$name.glb" "$T/$m/${name}_out.gltf"
    fi
    check "$name -> gltf ($m) structure" $CHECK diff "$f" "$T/$m/${name}_out.gltf"
  done
done
# glb -> gltf -> glb: the JSON comes back byte for byte.
run "$VNC" "$DATA/Duck.glb" "$T/d1.gltf" -q && run "$VNC" "$T/d1.gltf" "$T/d2.glb" -q && run "$VNC" "$T/d2.glb" "$T/d3.glb" -q
check "glb -> gltf -> glb -> glb exits 0" [ $rc -eq 0 ]
run "$VNC" "$DATA/Duck.glb" "$T/d0.glb" -q
check "chained conversions give the same GLB" cmp -s "$T/d0.glb" "$T/d3.glb"
check ".gltf buffers are written beside the output" [ -f "$T/d1.bin" ]
# External images travel with a .gltf written to another folder.
check "images copied next to the output" cmp -s "$DATA/Duck/DuckCM.png" "$T/mwa/DuckCM.png"
mkdir -p "$T/clash" && echo "not the duck" >"$T/clash/DuckCM.png"
run "$VNC" "$DATA/Duck/Duck.gltf" "$T/clash/Duck.gltf"
check "a different existing image is an error" [ $rc -eq 1 ]; check "image clash: one line" one_line_err
check "image clash: no output" [ ! -e "$T/clash/Duck.gltf" ] && check "image clash: nothing replaced" grep -q "not the duck" "$T/clash/DuckCM.png"
check "image clash: no temporaries" [ "$(ls -A "$T/clash")" = "DuckCM.png" ]
# An image whose file is missing (a .gltf fetched without a texture) stays
# referred to by its URI, with a warning: the normals are still fixed, and
# the images that are there are embedded or copied as ever.
mkdir -p "$T/noimg" "$T/noimg-out" && cp "$DATA/Duck/Duck0.bin" "$DATA/Duck/DuckCM.png" "$T/noimg/"
python3 -c "import json, sys; d = json.load(open(sys.argv[1])); d['images'].append({'uri': 'gone%20away.png'}); json.dump(d, open(sys.argv[2], 'w'))" \
  "$DATA/Duck/Duck.gltf" "$T/noimg/Duck.gltf"
for ext in glb gltf; do
  run "$VNC" "$T/noimg/Duck.gltf" "$T/noimg-out/Duck.$ext"
  check "missing image -> $ext: exits 0" [ $rc -eq 0 ]
  check "missing image -> $ext: the warning" [ "$err" = "vnconvert: warning: $T/noimg/Duck.gltf: images[1] ('gone away.png') cannot be read beside the input: the output refers to it by URI, as the input does" ]
  check "missing image -> $ext: structure" $CHECK diff "$T/noimg/Duck.gltf" "$T/noimg-out/Duck.$ext"
  check "missing image -> $ext: its URI kept" [ "$(q "$T/noimg-out/Duck.$ext" "d['images'][1]")" = "{'uri': 'gone%20away.png'}" ]
done
check "missing image -> glb: the other image embedded" [ "$(q "$T/noimg-out/Duck.glb" "sorted(d['images'][0])")" = "['bufferView', 'mimeType']" ]
check "missing image -> gltf: the other image copied" cmp -s "$DATA/Duck/DuckCM.png" "$T/noimg-out/DuckCM.png"

# TANGENT: a warning by default; --tangents drop removes the attribute and its data.
run "$VNC" "$DATA/sphere/sphere.gltf" "$T/sp.glb"
check "TANGENT warning" grep -q "warning: 1 primitive has TANGENT" "$T/stderr"
run "$VNC" "$DATA/sphere/sphere.gltf" "$T/spd.glb" --tangents drop --stats
check "--tangents drop: no warning" [ ! -s "$T/stderr" ]
check "--tangents drop: its accessor and bufferView removed" \
  grep -q "^removed unused: *1 accessor, 1 bufferView$" "$T/stdout"
check "--tangents drop: structure" $CHECK diff "$DATA/sphere/sphere.gltf" "$T/spd.glb" --tangents-dropped
check "--tangents drop: TANGENT gone" no_tangent "$T/spd.glb"

# Seams: split copies of a vertex get one normal when welded, not without.
$CHECK sphere "$T/seam.gltf"
run "$VNC" "$T/seam.gltf" "$T/seam.glb" -q
check "welded seams agree" $CHECK seams "$T/seam.glb" same
run "$VNC" "$T/seam.gltf" "$T/seam-nw.glb" -q --no-weld
check "--no-weld seams differ" $CHECK seams "$T/seam-nw.glb" differ
run "$VNC" "$T/seam.gltf" "$T/seam-eps.glb" -q --weld-epsilon 1e-6 --stats
check "--weld-epsilon works" $CHECK seams "$T/seam-eps.glb" same
run "$VNC" "$T/seam.gltf" "$T/x.glb" --weld-epsilon -1
check "negative --weld-epsilon exits 2" [ $rc -eq 2 ]

# EXT_structural_metadata (3D Tiles 1.1 content) keeps a property table's
# values and string offsets in bufferViews: when vn removes the data it
# replaced (--draco on), those are renumbered and read the same bytes, and
# there is no warning about an extension vn does not know.
python3 - "$T/seam.gltf" "$T/metadata.gltf" <<'EOF'
import base64, json, struct, sys
doc = json.load(open(sys.argv[1]))
data = b"abcde\0\0\0" + struct.pack("<3I", 0, 2, 5)
doc["buffers"].append({"byteLength": len(data), "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()})
doc["bufferViews"] += [{"buffer": 1, "byteOffset": 0, "byteLength": 5}, {"buffer": 1, "byteOffset": 8, "byteLength": 12}]
doc["extensionsUsed"] = ["EXT_structural_metadata"]
doc["extensions"] = {"EXT_structural_metadata": {
    "schema": {"id": "s", "classes": {"c": {"properties": {"name": {"type": "STRING"}}}}},
    "propertyTables": [{"class": "c", "count": 2, "properties": {"name": {"values": 4, "stringOffsets": 5, "stringOffsetType": "UINT32"}}}]}}
json.dump(doc, open(sys.argv[2], "w"))
EOF
run "$VNC" "$T/metadata.gltf" "$T/metadata.glb" --draco on --stats
check "EXT_structural_metadata: no warning, the replaced data removed" [ "$rc|$(cat "$T/stderr")|$(grep -c '^removed unused: *[1-9]' "$T/stdout")" = "0||1" ]
check "EXT_structural_metadata: its table's bufferViews renumbered" [ "$(q "$T/metadata.glb" "d['extensions']['EXT_structural_metadata']['propertyTables'][0]['properties']['name']")" = "{'values': 0, 'stringOffsets': 1, 'stringOffsetType': 'UINT32'}" ]
check "EXT_structural_metadata: its table's bytes as they were" $CHECK metadata "$T/metadata.gltf" "$T/metadata.glb"
# Pruning: a sparse NORMAL cannot be rewritten in place, so a new accessor
# replaces it; the old one and its 3 bufferViews (data, sparse indices and
# values) are removed, what the input itself left unused (accessors "unused"
# and "odd", whose view starts at an odd offset, which packing keeps modulo
# 4) stays, and the rest is renumbered.
python3 - "$T/seam.gltf" "$T/sparse-normal.gltf" <<'EOF'
import base64, json, struct, sys
doc = json.load(open(sys.argv[1]))
head, data = doc["buffers"][0]["uri"].split(",")
data = base64.b64decode(data)
def view(payload):
    global data
    data += b"\0" * (-len(data) % 4)
    doc["bufferViews"].append({"buffer": 0, "byteOffset": len(data), "byteLength": len(payload)})
    data += payload
    return len(doc["bufferViews"]) - 1
unused = view(struct.pack("<4f", 1, 2, 3, 4))
doc["accessors"].append({"bufferView": unused, "componentType": 5126, "count": 4, "type": "SCALAR", "name": "unused"})
odd = view(bytes([0, 7, 8, 9]))  # a view at an odd offset: packing keeps offsets modulo 4
doc["bufferViews"][odd]["byteOffset"] += 1
doc["bufferViews"][odd]["byteLength"] = 3
doc["accessors"].append({"bufferView": odd, "componentType": 5121, "count": 3, "type": "SCALAR", "name": "odd"})
normal = doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"]]
normal["sparse"] = {"count": 1, "indices": {"bufferView": view(bytes([0])), "componentType": 5121},
                    "values": {"bufferView": view(struct.pack("<3f", 1, 0, 0))}}
doc["buffers"][0] = {"byteLength": len(data), "uri": head + "," + base64.b64encode(data).decode()}
json.dump(doc, open(sys.argv[2], "w"))
EOF
run "$VNC" "$T/sparse-normal.gltf" "$T/sparse-normal.glb" --stats
check "sparse NORMAL replaced" grep -q "^appended accessors: *1$" "$T/stdout"
check "sparse NORMAL: the old accessor and its 3 bufferViews removed" \
  grep -q "^removed unused: *1 accessor, 3 bufferViews$" "$T/stdout"
check "sparse NORMAL: structure" $CHECK diff "$T/sparse-normal.gltf" "$T/sparse-normal.glb"
kept_unused() {
  python3 - "$HERE/gltf" "$1" <<'EOF'
import sys
sys.path.insert(0, sys.argv[1])
import gltfcheck
_, doc, buf = gltfcheck.load(sys.argv[2])
named = {a.get("name"): i for i, a in enumerate(doc["accessors"])}
odd = doc["bufferViews"][doc["accessors"][named["odd"]]["bufferView"]]
sys.exit(gltfcheck.accessor_values(doc, buf, named["unused"]) != [[1], [2], [3], [4]] or
         gltfcheck.accessor_values(doc, buf, named["odd"]) != [[7], [8], [9]] or odd["byteOffset"] % 4 != 1)
EOF
}
check "what the input left unused stays, data and all" kept_unused "$T/sparse-normal.glb"

# KHR_mesh_quantization: SHORT positions, normalized BYTE normals with a
# byteStride, rewritten in place in the same format.
$CHECK quantized "$T/quantized.gltf"
run "$VNC" "$T/quantized.gltf" "$T/quantized.glb" -q --stats
check "quantized exits 0" [ $rc -eq 0 ]
check "quantized normals rewritten in place" grep -q "^appended accessors: *0$" "$T/stdout"
check "quantized: structure" $CHECK diff "$T/quantized.gltf" "$T/quantized.glb"
check "quantized: welded seams agree" $CHECK seams "$T/quantized.glb" same

# Shared accessors, modes, primitives without NORMAL.
$CHECK shapes "$T/shapes.gltf"
run "$VNC" "$T/shapes.gltf" "$T/shapes.glb" --stats
check "shapes exits 0" [ $rc -eq 0 ]
check "shapes: 4 triangle primitives, POINTS skipped" grep -q "^primitives: *4 processed, 1 skipped (1 point, 0 lines" "$T/stdout"
check "shapes: missing NORMAL added, the shared one kept" grep -q "^appended accessors: *2$" "$T/stdout"
check "shapes: unused vertices counted" grep -q "^zero normals: *[1-9]" "$T/stdout"
# Its first two primitives draw the halves of one vertex array with one
# NORMAL accessor (as Cesium's batched tiles do, a primitive a material):
# computed together, the accessor stays theirs and holds the whole sphere's
# normals, the equator's included (computed apart, each half gave the
# equator its own normals: a crease where the file had none).
check "shapes: halves on one vertex array share their NORMAL" [ "$(q "$T/shapes.glb" "[p['attributes']['NORMAL'] for p in d['meshes'][0]['primitives'][:2]]")" = "[1, 1]" ]
check "shapes: halves on one vertex array: the whole sphere's normals" $CHECK samenormals "$T/seam.glb" "$T/shapes.glb" 1e-5
run "$VNC" "$T/seam.gltf" "$T/seam-c25.glb" -q --crease-angle 25
run "$VNC" "$T/shapes.gltf" "$T/shapes-c25.glb" --crease-angle 25 --stats
check "shapes --crease-angle 25: vertices split" grep -q "^split vertices: *[1-9]" "$T/stdout"
check "shapes --crease-angle 25: halves on one vertex array: the whole sphere's split normals" $CHECK samenormals "$T/seam-c25.glb" "$T/shapes-c25.glb" 1e-5
# Two meshes drawing one geometry (one vertex array, the same indices), as
# exporters write material variants: computed once, each gets the whole
# sphere's normals (split at a crease angle as one primitive alone is).
python3 - "$T/seam.gltf" "$T/twice.gltf" <<'EOF'
import json, sys
doc = json.load(open(sys.argv[1]))
doc["meshes"].append(json.loads(json.dumps(doc["meshes"][0])))
doc["nodes"].append({"mesh": 1})
doc["scenes"][0]["nodes"].append(1)
json.dump(doc, open(sys.argv[2], "w"))
EOF
run "$VNC" "$T/twice.gltf" "$T/twice.glb" --stats
check "one geometry twice: its NORMAL shared, the sphere's normals" [ "$rc|$(grep '^appended' "$T/stdout" | tr -s ' ')|$(q "$T/twice.glb" "[m['primitives'][0]['attributes']['NORMAL'] for m in d['meshes']]")" = "0|appended accessors: 0|[1, 1]" ]
check "one geometry twice: the sphere's normals" $CHECK samenormals "$T/seam.glb" "$T/twice.glb" 1e-5
run "$VNC" "$T/twice.gltf" "$T/twice-c25.glb" -q --crease-angle 25
check "one geometry twice, --crease-angle 25: both split as the sphere alone" python3 - "$HERE/gltf" "$T/seam-c25.glb" "$T/twice-c25.glb" <<'EOF'
import sys
sys.path.insert(0, sys.argv[1])
import gltfcheck as g
_, da, ba = g.load(sys.argv[2])
_, db, bb = g.load(sys.argv[3])
one = g.accessor_values(da, ba, da["meshes"][0]["primitives"][0]["attributes"]["NORMAL"])
both = [g.accessor_values(db, bb, m["primitives"][0]["attributes"]["NORMAL"]) for m in db["meshes"]]
sys.exit(not (len(one) > 117 and both[0] == both[1] == one))
EOF
check "shapes: structure" $CHECK diff "$T/shapes.gltf" "$T/shapes.glb"
run "$VNC" "$T/shapes.gltf" "$T/shapes-mesh.glb" --weld-scope mesh --stats
check "--weld-scope mesh: structure" $CHECK diff "$T/shapes.gltf" "$T/shapes-mesh.glb"
check "--weld-scope mesh welds across primitives" [ "$(grep '^welded' "$T/stdout" | tr -dc 0-9)" -gt 80 ]
run "$VNC" "$DATA/Box.glb" "$T/box.glb" --stats
check "--stats counts" grep -q "^triangles: *12$" "$T/stdout"
check "--stats: the cube's 12 edges kept hard" grep -q "^hard edges kept: *12$" "$T/stdout"
check "--stats: nothing split" grep -q "^split vertices: *0$" "$T/stdout"

# Hard edges already in the file stay hard: the box's split copies (one per
# face) keep their face's normal; welded seams (equal input normals) do not.
check "Box keeps its hard edges" $CHECK flat "$T/box.glb"

# A double-sided surface as exporters write it (each side on its own copies,
# the back's faces reversed and its normals negated): the sides are not
# welded, and each keeps its own smooth normals (welded, their sums cancelled
# to noise: front normals 87 degrees off).
$CHECK twosided "$T/twosided.gltf"
for m in mwa jet adaptive; do
  run "$VNC" "$T/twosided.gltf" "$T/twosided-$m.glb" -m $m --stats
  check "two-sided bowl ($m): the sides not welded" grep -q "^welded vertices: *0$" "$T/stdout"
  check "two-sided bowl ($m): each side its own normals" $CHECK twosided-check "$T/twosided-$m.glb" 6
done
# Both sides on the same vertices (each face and its reverse; no normals, so
# nothing else tells them apart): summed together they cancelled to noise.
# The sides are computed apart and every vertex is split between them, its
# TEXCOORD_0 with it.
$CHECK twosided-shared "$T/twosided-shared.gltf"
for m in mwa adaptive; do
  run "$VNC" "$T/twosided-shared.gltf" "$T/twosided-shared-$m.glb" -m $m --stats
  check "two-sided bowl on shared vertices ($m): 49 split" grep -q "^split vertices: *49$" "$T/stdout"
  check "two-sided bowl on shared vertices ($m): each side its own normals" $CHECK twosided-shared-check "$T/twosided-shared-$m.glb" 6
done
# The same from Blender's exporter (tests/data/gltf/blender): each side welds
# its own seam and pole copies (38), and MWA gives back Blender's own
# angle-weighted normals, to float rounding, on both sides.
DOME=$HERE/data/gltf/blender/two-sided-dome.glb
run "$VNC" "$DOME" "$T/dome.glb" -m mwa --stats
check "Blender's two-sided dome: each side welds its own seams" grep -q "^welded vertices: *38$" "$T/stdout"
check "Blender's two-sided dome: Blender's normals on both sides" $CHECK samenormals "$DOME" "$T/dome.glb" 0.1

# Texture coordinates: glTF's (0, 0) is the image's top left, OBJ's, PLY's,
# OFF's and Draco files' its bottom left, so v is 1 - v between them. By
# hand: a quad's vt, and the glTF it must give.
printf '%s\n' "v 0 0 0" "v 1 0 0" "v 1 1 0" "v 0 1 0" "vt 0.1 0.2" "vt 0.9 0.2" "vt 0.9 0.7" "vt 0.1 0.7" \
  "f 1/1 2/2 3/3" "f 1/1 3/3 4/4" >"$T/uvquad.obj"
sed 's/0\.2$/0.8/; s/0\.7$/0.3/' "$T/uvquad.obj" >"$T/uvquad-gltf.obj"
run "$VNC" "$T/uvquad.obj" "$T/uvquad.glb" -q
check "OBJ to glTF: v is 1 - v" $CHECK uvcorners "$T/uvquad.glb" "$T/uvquad-gltf.obj" 3e-8
# Blender's own exporters (tests/data/gltf/blender/make_sphere.py): vn's GLB
# of Blender's OBJ has the corners of Blender's GLB of it, and vn's OBJ of
# Blender's GLB those of Blender's OBJ (6 decimals).
BSPHERE=$HERE/data/gltf/blender/blender-sphere.glb
run "$VNC" "$HERE/data/obj/blender_sphere.obj" "$T/bsphere.glb" -q
check "Blender's OBJ to GLB: Blender's GLB corners" $CHECK uvcorners "$T/bsphere.glb" "$BSPHERE" 1e-6
run "$VNC" "$BSPHERE" "$T/bsphere.obj" -q
check "Blender's GLB to OBJ: Blender's OBJ corners" $CHECK uvcorners "$T/bsphere.obj" "$HERE/data/obj/blender_sphere.obj" 1e-6
# Normalized integers flip exactly: k becomes 255 - k or 65535 - k.
$CHECK uvtriangle "$T/uvtri.gltf"
run "$VNC" "$T/uvtri.gltf" "$T/uvtri.ply" -q
check "normalized TEXCOORD_0 to PLY: t = 1 - k / 65535" \
  [ "$(for i in 0 1 2; do python3 "$HERE/plytool.py" column "$T/uvtri.ply" t $i; done | tr '\n' ' ')" = "1.0 0.9847409725189209 0.0 " ]
check "normalized TEXCOORD_1 to PLY: 255 - k" \
  [ "$(for i in 0 1 2; do python3 "$HERE/plytool.py" column "$T/uvtri.ply" texcoord_1_1 $i; done | tr '\n' ' ')" = "245.0 235.0 0.0 " ]
run "$VNC" "$T/uvtri.gltf" "$T/uvtri.drc" -q
run "$VNC" "$T/uvtri.drc" "$T/uvtri.glb" -q
check "normalized TEXCOORD_1 through Draco: the same bytes" python3 -c "import sys; sys.path.insert(0, '$HERE/gltf'); import gltfcheck as g
a = [g.load(f) for f in sys.argv[1:]]
sys.exit([g.accessor_bytes(d, b, d['meshes'][0]['primitives'][0]['attributes']['TEXCOORD_1']) for _, d, b in a] != [bytes([0, 10, 255, 20, 0, 255])] * 2)" "$T/uvtri.gltf" "$T/uvtri.glb"
# A material's KHR_texture_transform (offset, rotation, scale) gives the
# coordinates of the set its texture reads, which a format without materials
# carries; by hand, offset (0.5, 0.25), 90 degrees, scale (2, 0.5) on the
# triangle above: u' = 0.5 v + 0.5, v' = 0.25 - 2 u, then OBJ's 1 - v'.
python3 - "$T/uvtri.gltf" "$T/uvtt.gltf" <<'EOF'
import json, math, sys
d = json.load(open(sys.argv[1]))
d["meshes"][0]["primitives"][0]["material"] = 0
d["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {
    "offset": [0.5, 0.25], "rotation": math.pi / 2, "scale": [2, 0.5]}}}}}]
d["textures"], d["images"] = [{"source": 0}], [{"uri": "none.png"}]
d["extensionsUsed"] = ["KHR_texture_transform"]
json.dump(d, open(sys.argv[2], "w"))
EOF
printf '%s\n' "v 0 0 0" "v 1 0 0" "v 0 1 0" "vt 0.5 0.75" "vt 0.507629510948348 2.75" "vt 1 0.75" "f 1/1 2/2 3/3" >"$T/uvtt-expected.obj"
run "$VNC" "$T/uvtt.gltf" "$T/uvtt.obj" -q
check "KHR_texture_transform applied to TEXCOORD_0" $CHECK uvcorners "$T/uvtt.obj" "$T/uvtt-expected.obj" 1e-7
# gltfpack's quantized Duck (tests/data/gltf/meshopt/duck-tt.glb: unsigned
# shorts, dequantized by the material's transform) has the Duck's own
# texture coordinates, to gltfpack's quantization.
run "$VNC" "$HERE/data/gltf/meshopt/duck-tt.glb" "$T/duck-tt.obj" --apply-transforms -q
run "$VNC" "$DATA/Duck.glb" "$T/duck-plain.obj" --apply-transforms -q
check "gltfpack's Duck: the Duck's texture coordinates" $CHECK uvcorners "$T/duck-tt.obj" "$T/duck-plain.obj" 3e-4 2e-4

# Morph targets: base + NORMAL displacement is the scheme's normal of the
# morphed positions, computed by vnconvert on an OFF of them (the cube's
# copies are all hard edges: as split; the sphere: welded by position).
# The sphere's target has a sparse POSITION without bufferView and no NORMAL.
$CHECK morphsphere "$T/morph.gltf"
for m in mwe mwa mwselr; do
  run "$VNC" "$DATA/AnimatedMorphCube/AnimatedMorphCube.gltf" "$T/amc-$m.glb" -q -m $m
  check "AnimatedMorphCube targets ($m)" $CHECK morph "$T/amc-$m.glb" "$VNC" $m split
  run "$VNC" "$T/morph.gltf" "$T/morph-$m.glb" -q -m $m
  check "sparse morph target ($m)" $CHECK morph "$T/morph-$m.glb" "$VNC" $m weld
  check "sparse morph target ($m): structure" $CHECK diff "$T/morph.gltf" "$T/morph-$m.glb"
done

# --crease-angle: a cylinder with one vertex per position splits exactly its
# 24 rim vertices (cap and side corners), duplicating TEXCOORD_0, COLOR_0
# (ubyte, padded) and the target's POSITION; 10 degrees keeps the 30-degree
# side edges hard too.
$CHECK cylinder "$T/cyl.gltf"
for m in mwe mwa mwselr; do
  run "$VNC" "$T/cyl.gltf" "$T/cyl-$m.glb" -q -m $m --crease-angle 60
  check "--crease-angle 60 ($m) splits the rims" $CHECK crease "$T/cyl.gltf" "$T/cyl-$m.glb" 24 "$VNC" $m
done
run "$VNC" "$T/cyl.gltf" "$T/cyl-stats.glb" -q --crease-angle 60 --stats
check "--stats: 24 split vertices" grep -q "^split vertices: *24$" "$T/stdout"
run "$VNC" "$T/cyl.gltf" "$T/cyl-flat.glb" -q --crease-angle 10
check "--crease-angle 10: every face flat" $CHECK flat "$T/cyl-flat.glb"
run "$VNC" "$T/cyl.gltf" "$T/cyl-smooth.glb" -q --crease-angle 180
check "--crease-angle 180 splits nothing" $CHECK diff "$T/cyl.gltf" "$T/cyl-smooth.glb"
run "$VNC" "$T/cyl.gltf" "$T/cyl-none.glb" -q
check "no --crease-angle splits nothing" $CHECK diff "$T/cyl.gltf" "$T/cyl-none.glb"
run "$VNC" "$T/shapes.gltf" "$T/shapes-crease.glb" -q --crease-angle 1
check "--crease-angle on strips and shared accessors" $CHECK flat "$T/shapes-crease.glb"
for bad in -1 181 x; do
  run "$VNC" "$T/cyl.gltf" "$T/x.glb" --crease-angle $bad
  check "--crease-angle $bad exits 2" [ $rc -eq 2 ]
done

# Errors: exit 1, one line naming the file, no output, an old output untouched.
head -c 1000 "$DATA/Box.glb" >"$T/truncated.glb"
python3 - "$DATA/Box.glb" "$T/seam.gltf" "$T" <<'EOF'
import json, struct, sys
box, seam, t = sys.argv[1:]
d = bytearray(open(box, "rb").read())
struct.pack_into("<I", d, 12, struct.unpack_from("<I", d, 12)[0] + 4096)
open(t + "/chunklength.glb", "wb").write(d)
doc = json.load(open(seam)); doc["accessors"][0]["count"] += 10
json.dump(doc, open(t + "/accessor.gltf", "w"))
doc = json.load(open(seam)); doc["bufferViews"][0]["byteLength"] += 100000
json.dump(doc, open(t + "/bufferview.gltf", "w"))
open(t + "/json.gltf", "w").write(open(seam).read()[:300])
EOF
cp "$DATA/Duck/Duck.gltf" "$T/missingbin.gltf"
for bad in truncated.glb chunklength.glb accessor.gltf bufferview.gltf missingbin.gltf json.gltf; do
  check_rejected "$VNC" "$T/$bad" "$T/none.glb" "$T/keep.gltf"
done
check "no temporary files left" [ -z "$(find "$T" -type f -name '.*')" ]

# OFF -> glTF/GLB -> OFF keeps positions (float32) and faces.
for ext in glb gltf; do
  run "$VNC" "$SAMPLES/torus.off" "$T/torus.$ext" -q && run "$VNC" "$T/torus.$ext" "$T/torus-$ext.off" -q
  check "OFF -> $ext -> OFF exits 0" [ $rc -eq 0 ]
  check "OFF -> $ext -> OFF keeps positions and faces" python3 - "$SAMPLES/torus.off" "$T/torus-$ext.off" <<'EOF'
import sys
def read(path):
    rows = [l.split() for l in open(path) if l.strip() and not l.startswith("#")]
    nv, nf = int(rows[1][0]), int(rows[1][1])
    return [list(map(float, r[:3])) for r in rows[2:2 + nv]], [r for r in rows[2 + nv:2 + nv + nf]]
(pa, fa), (pb, fb) = read(sys.argv[1]), read(sys.argv[2])
sys.exit(not (len(pa) == len(pb) and fa == fb and
              all(abs(x - y) <= 1e-6 * max(1, abs(x)) for p, q in zip(pa, pb) for x, y in zip(p, q))))
EOF
done
# To OFF, primitives on one vertex array (the same accessor for every
# attribute) share its vertices, written once: shapes' two halves (117
# vertices), its strip and points (117), its whole sphere with UVs (117).
run "$VNC" "$T/shapes.gltf" "$T/shapes.off" -q
check "shapes to OFF: each vertex array once" [ "$(sed -n 2p "$T/shapes.off" | cut -d' ' -f1)" = 351 ]
check "shapes to OFF: both halves on the first 117 vertices" [ "$(awk 'NR > 353 && NR <= 353 + 192 { for (i = 2; i <= 4; ++i) if ($i > m) m = $i } END { print m }' "$T/shapes.off")" = 116 ]
# Texture coordinates under different KHR_texture_transforms are different
# vertices: the halves with UVs, one under a transform, keep theirs apart.
python3 - "$T/shapes.gltf" "$T/halves-uv.gltf" "$T/halves-uvt.gltf" <<'EOF'
import json, sys
doc = json.load(open(sys.argv[1]))
halves = doc["meshes"][0]["primitives"][:2]
for k, p in enumerate(halves):
    p["attributes"]["TEXCOORD_0"] = 2
    p["material"] = k
doc["meshes"][0]["primitives"] = halves
doc["images"] = [{"uri": "x.png"}]
doc["textures"] = [{"source": 0}]
doc["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}} for _ in range(2)]
json.dump(doc, open(sys.argv[2], "w"))
doc["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {"KHR_texture_transform": {"scale": [2, 2]}}
json.dump(doc, open(sys.argv[3], "w"))
EOF
run "$VNC" "$T/halves-uv.gltf" "$T/halves-uv.off" -q
check "halves with UVs to OFF: one vertex array" [ "$(sed -n 2p "$T/halves-uv.off" | cut -d' ' -f1)" = 117 ]
run "$VNC" "$T/halves-uvt.gltf" "$T/halves-uvt.off" -q
check "halves with UVs, one under a texture transform, to OFF: two" [ "$(sed -n 2p "$T/halves-uvt.off" | cut -d' ' -f1)" = 234 ]
run "$VNC" "$SAMPLES/sphere-quads.off" "$T/sq.glb" -q && run "$VNC" "$T/sq.glb" "$T/sq.off" --stats
check "quads are fan-triangulated" grep -q "^faces: *528 (triangles)" "$T/stdout"

# A glTF with no mesh at all, to OFF: an empty mesh (no vertex: the copy of
# its normals was a memcpy from NULL, which UBSan reported).
printf '{"asset":{"version":"2.0"}}' >"$T/nothing.gltf"
run "$VNC" "$T/nothing.gltf" "$T/nothing.off"
check "a glTF with no mesh to OFF: an empty OFF" [ "$rc $(sed -n 2p "$T/nothing.off")" = "0 0 0 0" ]
run "$VNC" "$T/nothing.gltf" "$T/nothing.ply"
check "a glTF with no mesh to PLY: an empty PLY" [ "$rc $(head -c 200 "$T/nothing.ply" | grep -a "^element" | tr '\n' ' ')" = "0 element vertex 0 element face 0 " ]
# To OBJ and STL (refused before: "nothing to write"): an empty file of the
# format, which reads back empty; to glTF through the mesh (from PLY): a
# scene without nodes (test_gltf_validate.sh validates it). Draco has no empty file
# (its encoder crashes on one): one line saying so, and no file.
run "$VNC" "$T/nothing.gltf" "$T/nothing.obj"
check "a glTF with no mesh to OBJ: one comment" [ "$rc|$(cat "$T/nothing.obj")" = "0|# no vertices and no faces" ]
run "$VNC" "$T/nothing.gltf" "$T/nothing.stl" -q
check "a glTF with no mesh to STL: a header and a count of 0" [ "$rc|$(stat -c %s "$T/nothing.stl")|$(tail -c 4 "$T/nothing.stl" | od -An -tx1 | tr -d ' ')" = "0|84|00000000" ]
for ext in obj stl; do
  run "$VNC" "$T/nothing.$ext" "$T/nothing-$ext.off" -q
  check "an empty $ext read back" [ "$rc|$(grep -v "^#" "$T/nothing-$ext.off" | sed -n 2p)" = "0|0 0 0" ]
done
run "$VNC" "$T/nothing.ply" "$T/nothing-ply.glb"
check "an empty PLY to GLB: says it is empty" [ "$rc|$err" = "0|vnconvert: warning: $T/nothing.ply has no vertices and no faces: $T/nothing-ply.glb is written empty" ]
check "an empty PLY to GLB: no mesh, no buffer" [ "$(python3 -c 'import json,struct,sys; b=open(sys.argv[1],"rb").read(); n=struct.unpack("<I",b[12:16])[0]; j=json.loads(b[20:20+n]); print(len(b) == 20 + n, sorted(j))' "$T/nothing-ply.glb")" = "True ['asset', 'scene', 'scenes']" ]
check "an empty PLY to GLB: tinygltf reads it" "$TINYGLTF_LOAD" "$T/nothing-ply.glb"
run "$VNC" "$T/nothing.gltf" "$T/nothing.drc"
check "a glTF with no mesh to Draco: exit 1" [ $rc -eq 1 ]
check "a glTF with no mesh to Draco: one line" one_line_err
check "a glTF with no mesh to Draco: says why" grep -q "nothing.drc: vn read no vertices and no faces from .*nothing.gltf, and Draco has no empty file: write OFF, PLY, OBJ, STL or glTF to keep an empty mesh$" "$T/stderr"
check "a glTF with no mesh to Draco: no file" [ ! -e "$T/nothing.drc" ]
# POINTS primitives are read as vertices without faces (every attribute, the
# input's normals kept: vn computes none without faces; a glTF of POINTS
# alone is a point cloud, which an OFF came out empty of); LINES, which only
# glTF output keeps, are named when another format leaves them out.
python3 - "$T/points.gltf" "$T/mixed.gltf" <<'PYEOF'
import base64, json, struct, sys
pos = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
nrm = struct.pack("<9f", 0.6, 0, 0.8, 0, -0.6, 0.8, 0, 0, -1)
col = struct.pack("<12B", 255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 128)
tri = struct.pack("<9f", 2, 0, 0, 3, 0, 0, 2, 1, 0)
data = pos + nrm + col + tri
def doc(prims):
    return {"asset": {"version": "2.0"},
            "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 36},
                            {"buffer": 0, "byteOffset": 72, "byteLength": 12}, {"buffer": 0, "byteOffset": 84, "byteLength": 36}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                          {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
                          {"bufferView": 2, "componentType": 5121, "normalized": True, "count": 3, "type": "VEC4"},
                          {"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC3", "min": [2, 0, 0], "max": [3, 1, 0]}],
            "meshes": [{"primitives": prims}]}
points = {"attributes": {"POSITION": 0, "NORMAL": 1, "COLOR_0": 2}, "mode": 0}
json.dump(doc([points, {"attributes": {"POSITION": 0}, "mode": 3}]), open(sys.argv[1], "w"))
json.dump(doc([{"attributes": {"POSITION": 3}}, points]), open(sys.argv[2], "w"))
PYEOF
run "$VNC" "$T/points.gltf" "$T/points.off"
check "POINTS and LINES to OFF: exit 0" [ $rc -eq 0 ]
check "POINTS and LINES to OFF: the LINES named" grep -qxF "vnconvert: warning: $T/points.gltf: primitives left out (vn reads triangles and points): 1 LINES (or LINE_LOOP, LINE_STRIP)" "$T/stderr"
check "POINTS and LINES to OFF: a point cloud" grep -qxF "vnconvert: warning: $T/points.gltf has no faces (a point cloud): vn computes no normals; the input's are kept" "$T/stderr"
check "POINTS to OFF: the 3 points, their normals and colours" [ "$(sed 1d "$T/points.off")" = "3 0 0
0 0 0 0.6000000238418579 0 0.800000011920929 255 0 0 255
1 0 0 0 -0.6000000238418579 0.800000011920929 0 255 0 255
0 1 0 0 0 -1 0 0 255 128" ]
run "$VNC" "$T/mixed.gltf" "$T/mixed.ply"
check "a triangle and POINTS to PLY: exit 0" [ $rc -eq 0 ]
check "a triangle and POINTS to PLY: 6 vertices, 1 face" [ "$(python3 "$HERE/plytool.py" count "$T/mixed.ply")" = "6 1 1" ]
check "a triangle and POINTS to PLY: the points keep their normals" [ "$(for i in 3 4 5; do python3 "$HERE/plytool.py" column "$T/mixed.ply" nz $i; done | tr '\n' ' ')" = "0.800000011920929 0.800000011920929 -1.0 " ]
# COLOR_0 as floats or unsigned shorts that are bytes over 255 (exporters
# widen byte colours: k / 255 as float, k * 257 as unsigned short) reaches
# PLY as uchar, which MeshLab and Open3D read (float PLY colours: white in
# MeshLab, divided by 255 again in Open3D); other values stay float.
python3 - "$T/colour" <<'PYEOF'
import base64, json, struct, sys
pos = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
kinds = {"float": (5126, struct.pack("<9f", *[k / 255 for k in (209, 0, 122, 255, 255, 255, 0, 0, 1)])),
         "ushort": (5123, struct.pack("<9H", *[k * 257 for k in (209, 0, 122, 255, 255, 255, 0, 0, 1)]) + b"\0\0"),
         "other": (5126, struct.pack("<9f", 0.3, 0, 0, 1, 1, 1, 0, 0, 1))}
for name, (component, col) in kinds.items():
    data = pos + col
    json.dump({"asset": {"version": "2.0"},
               "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
               "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": len(col)}],
               "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                             {"bufferView": 1, "componentType": component, "normalized": component != 5126, "count": 3, "type": "VEC3"}],
               "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "COLOR_0": 1}}]}]}, open(f"{sys.argv[1]}-{name}.gltf", "w"))
PYEOF
declare -A colours
for kind in float ushort other; do
  run "$VNC" "$T/colour-$kind.gltf" "$T/colour-$kind.ply" -q
  colours[$kind]="$(grep -a '^property .* red$' "$T/colour-$kind.ply") $(python3 "$HERE/plytool.py" column "$T/colour-$kind.ply" red 0) $(python3 "$HERE/plytool.py" column "$T/colour-$kind.ply" blue 0)"
done
check "float COLOR_0 of bytes to PLY: uchar" [ "${colours[float]}" = "property uchar red 209.0 122.0" ]
check "unsigned short COLOR_0 of bytes to PLY: uchar" [ "${colours[ushort]}" = "property uchar red 209.0 122.0" ]
check "other float COLOR_0 to PLY: float" [ "${colours[other]}" = "property float red 0.30000001192092896 0.0" ]
run "$VNC" "$T/points.gltf" "$T/points.stl"
check "POINTS and LINES to STL: refused, naming what holds a point cloud" [ "$rc $(tail -1 "$T/stderr")" = "1 vnconvert: error: $T/points.stl: $T/points.gltf has 3 vertices and no faces (a point cloud), and vn writes STL only with faces: write OFF, PLY, OBJ, glTF or Draco to keep a point cloud" ]
# A point cloud written as glTF is one POINTS primitive, and reads back the same.
for e in gltf glb; do
  run "$VNC" "$T/points.off" "$T/points-off.$e"
  check "point cloud OFF -> $e: exit 0" [ $rc -eq 0 ]
  check "point cloud OFF -> $e: tinygltf reads it" "$TINYGLTF_LOAD" "$T/points-off.$e"
  check "point cloud OFF -> $e: one POINTS primitive, no indices" python3 -c "import sys; sys.path.insert(0, '$HERE/gltf'); import gltfcheck as g
_, d, _ = g.load(sys.argv[1]); p = [p for _, _, p in g.primitives(d)]
sys.exit(not (len(p) == 1 and p[0]['mode'] == 0 and 'indices' not in p[0] and sorted(p[0]['attributes']) == ['COLOR_0', 'NORMAL', 'POSITION']))" "$T/points-off.$e"
  run "$VNC" "$T/points-off.$e" "$T/points-back.off"
  check "point cloud OFF -> $e -> OFF: the same file" cmp "$T/points.off" "$T/points-back.off"
done
# A bufferView past its buffer's end (invalid: BUFFER_VIEW_TOO_LONG; assimp's
# IncorrectVertexArrays/Cube.gltf): the triangle is read, with a warning,
# and the new NORMAL view starts after the furthest view (it started at the
# buffer's end, under the long view, whose accessor then read the normals).
python3 - "$T/long-view.gltf" <<'PYEOF'
import base64, json, struct, sys
data = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
json.dump({"asset": {"version": "2.0"},
           "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
           "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 48}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                          "min": [0, 0, 0], "max": [1, 1, 0]},
                         {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}]}, open(sys.argv[1], "w"))
PYEOF
for ext in gltf glb; do
  run "$VNC" "$T/long-view.gltf" "$T/long-view-out.$ext"
  check "a view past its buffer's end -> $ext: exits 0" [ $rc -eq 0 ]
  check "a view past its buffer's end -> $ext: warns" \
    grep -q "bufferViews\[1\] ends at byte 84, past the end of buffers\[0\] (36 bytes).*new data goes after byte 84" "$T/stderr"
  check "a view past its buffer's end -> $ext: the new view after it" \
    [ "$(q "$T/long-view-out.$ext" "[v.get('byteOffset', 0) for v in d['bufferViews']]")" = "[0, 36, 84]" ]
done
# Three buffers, one of which vn empties (--tangents drop: it held only
# TANGENT; --draco on: the mesh data), to .glb: every bufferView in the one
# BIN chunk, POSITION's floats as they were. The buffer left out renumbered
# the views' buffer as signed JSON integers, which the GLB merge skipped:
# views of "buffer": 1 in a GLB with one buffer (glTF's teapots_galore).
for o in "--tangents drop" "--draco on"; do
  run "$VNC" "$HERE/data/gltf/three-buffers.gltf" "$T/three.glb" $o -q
  check "three buffers, $o -> glb: exits 0" [ $rc -eq 0 ]
  check "three buffers, $o -> glb: every view in the BIN chunk" python3 - "$T/three.glb" "$o" <<'PYEOF'
import json, struct, sys
raw = open(sys.argv[1], "rb").read()
n = struct.unpack("<I", raw[12:16])[0]
d = json.loads(raw[20:20 + n])
binary = raw[20 + n + 8:]
assert len(d["buffers"]) == 1 and d["buffers"][0]["byteLength"] <= len(binary), d["buffers"]
for v in d["bufferViews"]:
    assert v["buffer"] == 0 and v.get("byteOffset", 0) + v["byteLength"] <= d["buffers"][0]["byteLength"], v
if sys.argv[2] == "--tangents drop":
    a = d["accessors"][d["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]
    v = d["bufferViews"][a["bufferView"]]
    at = v.get("byteOffset", 0) + a.get("byteOffset", 0)
    assert struct.unpack("<9f", binary[at:at + 36]) == (0, 0, 0, 1, 0, 0, 0, 1, 0)
PYEOF
done
# 256 vertices: indices 0..255, and 255 is the unsigned byte's primitive
# restart value (ACCESSOR_INDEX_PRIMITIVE_RESTART), so --draco on declares
# unsigned short indices, and --draco off writes them so (they were bytes).
run "$VNC" "$HERE/data/gltf/grid-256-vertices.gltf" "$T/g256.glb" --draco on -q
check "256 vertices, --draco on: unsigned short indices" \
  [ "$rc $(q "$T/g256.glb" "[d['accessors'][p['indices']]['componentType'] for m in d['meshes'] for p in m['primitives']]")" = "0 [5123]" ]
run "$VNC" "$T/g256.glb" "$T/g256-off.glb" --draco off -q
check "256 vertices, --draco off: unsigned short indices" \
  [ "$rc $(q "$T/g256-off.glb" "[d['accessors'][p['indices']]['componentType'] for m in d['meshes'] for p in m['primitives']]")" = "0 [5123]" ]
# Float colours in [0, 1] through --draco on and off stay in [0, 1]: Draco's
# default grid spans all components with one range, and a component whose
# minimum is above 0 decoded 1.0 as 1.00196 (ACCESSOR_NON_CLAMPED). On the
# unit grid every 8-bit step is k / 255.
run "$VNC" "$HERE/data/gltf/colour-floats.gltf" "$T/colour-on.glb" --draco on -q &&
  run "$VNC" "$T/colour-on.glb" "$T/colour-off.glb" --draco off -q
check "float colours through --draco on and off: exits 0" [ $rc -eq 0 ]
check "float colours through --draco on and off: within [0, 1], on 8-bit steps" python3 - "$T/colour-off.glb" <<'PYEOF'
import json, struct, sys
raw = open(sys.argv[1], "rb").read()
n = struct.unpack("<I", raw[12:16])[0]
d = json.loads(raw[20:20 + n])
binary = raw[20 + n + 8:]
a = d["accessors"][d["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"]]
v = d["bufferViews"][a["bufferView"]]
at = v.get("byteOffset", 0) + a.get("byteOffset", 0)
c = struct.unpack("<%df" % (4 * a["count"]), binary[at:at + 16 * a["count"]])
assert all(0 <= x <= 1 and abs(x * 255 - round(x * 255)) < 1e-4 for x in c), c
PYEOF
# A new indices accessor (split vertices; --draco on) keeps the name and
# extras the file gave the one it replaces, as the attribute accessors do.
python3 - "$T/twosided.gltf" "$T/labelled.gltf" <<'PYEOF'
import json, sys
d = json.load(open(sys.argv[1]))
d["accessors"][d["meshes"][0]["primitives"][0]["indices"]].update(name="bowl indices", extras={"k": 2})
json.dump(d, open(sys.argv[2], "w"))
PYEOF
label() { python3 -c "import json, sys; d = json.load(open(sys.argv[1])); a = d['accessors'][d['meshes'][0]['primitives'][0]['indices']]; print(a.get('name'), a.get('extras'))" "$1"; }
for o in "--crease-angle 1" "--draco on"; do
  run "$VNC" "$T/labelled.gltf" "$T/labelled-out.gltf" $o
  check "new indices accessor ($o): its name and extras kept" [ "$rc $(label "$T/labelled-out.gltf")" = "0 bowl indices {'k': 2}" ]
done
finish
