#!/usr/bin/env bash
# glTF as found in public files (issue 14): one small file per defect, in
# tests/data/gltf/wild/ (written by tests/gltf/wild.py), converted to .glb and
# .gltf in another folder and checked with the Khronos glTF-Validator (no code
# the input did not have) and on the output's JSON.
#   test_gltf_wild.sh PATH/TO/vnconvert NODE_MODULES_DIR
set -u
VNC=$1
MODULES=$2
HERE=$(cd "$(dirname "$0")" && pwd)
W=$HERE/data/gltf/wild
. "$HERE/lib.sh"
if [ ! -d "$MODULES/gltf-validator" ]; then
  echo "FAIL: $MODULES/gltf-validator is missing: run .ci/setup (npm install gltf-validator)"
  exit 1
fi

# convert NAME [ALLOW...]: NAME to $T/out/NAME.glb and .gltf; both valid with no
# new validator code but the ALLOWed ones, which the .glb may add.
convert() {
  local name=$1 in out
  shift
  in=$(ls "$W/$name".gl*)
  mkdir -p "$T/out"
  for out in "$T/out/$name.glb" "$T/out/$name.gltf"; do
    run "$VNC" "$in" "$out"
    check "$name -> ${out##*.}: exit 0" [ $rc -eq 0 ]
  done
  local allow=()
  for a in "$@"; do allow+=(--allow "$a"); done
  check "$name -> .glb: no new validator code${*:+ but $*}" quietly node "$HERE/gltf/validate.mjs" "${allow[@]}" "$MODULES" "$in" "$T/out/$name.glb"
  check "$name -> .gltf: no new validator code" quietly node "$HERE/gltf/validate.mjs" "$MODULES" "$in" "$T/out/$name.gltf"
}

# 1. No buffers array: none is made where nothing needs one ("buffers": null
#    was invalid), and the GLB gets one for the data-URI image.
convert no-buffers
check "no-buffers.gltf: no buffers key" [ "$(q "$T/out/no-buffers.gltf" "'buffers' in d")" = False ]
check "no-buffers.glb: the image in the BIN chunk" [ "$(q "$T/out/no-buffers.glb" "(len(d['buffers']), 'uri' in d['buffers'][0], d['images'][0])")" = "(1, False, {'mimeType': 'image/png', 'bufferView': 0})" ]
convert no-binary
for e in glb gltf; do
  check "no-binary.$e: no buffers key" [ "$(q "$T/out/no-binary.$e" "'buffers' in d or 'bufferViews' in d")" = False ]
done

# 2, 8. An extension vn does not know: the GLB still merges every buffer (a
#    percent-encoded data URI among them) and embeds the image; the
#    extension's accessor index stays; .gltf keeps its data URIs (base64).
convert unknown-ext
check "unknown-ext.glb: one buffer, the BIN chunk" [ "$(q "$T/out/unknown-ext.glb" "[b.get('uri') for b in d['buffers']]")" = "[None]" ]
check "unknown-ext.glb: every view in it" [ "$(q "$T/out/unknown-ext.glb" "sorted(set(v['buffer'] for v in d['bufferViews']))")" = "[0]" ]
check "unknown-ext.glb: the image embedded" [ "$(q "$T/out/unknown-ext.glb" "d['images'][0]")" = "{'mimeType': 'image/png', 'bufferView': 3}" ]
check "unknown-ext.glb: the extension as it was" [ "$(q "$T/out/unknown-ext.glb" "d['nodes'][0]['extensions']")" = "{'VN_test_unknown': {'accessor': 0}}" ]
check "unknown-ext.gltf: data URIs stay, as base64 of their media type" [ "$(q "$T/out/unknown-ext.gltf" "[b['uri'].split(',')[0] for b in d['buffers'][:2]]")" = "['data:application/octet-stream;base64', 'data:application/gltf-buffer;base64']" ]
check "unknown-ext.gltf: the image copied beside it" cmp "$W/wild-textures/pixel.png" "$T/out/wild-textures/pixel.png"
check "unknown-ext: the indices read from the percent-encoded URI" [ "$(q "$T/out/unknown-ext.glb" "d['accessors'][2]['count']")" = 6 ]

# 6. Bytes after the GLB's declared length: read as the header says, with a warning.
run "$VNC" "$W/extra-bytes.glb" "$T/out/extra.glb"
check "extra-bytes.glb: exit 0" [ $rc -eq 0 ]
check "extra-bytes.glb: warns" grep -q "warning: .*extra-bytes.glb: the GLB header says 836 bytes, the file has 840: the 4 bytes after them are ignored" "$T/stderr"
check "extra-bytes.glb: the output is as long as it says" [ "$(stat -c %s "$T/out/extra.glb")" = "$(python3 -c 'import struct,sys; print(struct.unpack("<I", open(sys.argv[1],"rb").read()[8:12])[0])' "$T/out/extra.glb")" ]
convert extra-bytes
run "$VNC" -q "$W/extra-bytes.glb" "$T/out/quiet.glb"
check "extra-bytes.glb -q: no warning" [ ! -s "$T/stderr" ]

# 7. A GLB with an unused buffer that has no uri.
convert placeholder
check "placeholder.glb: the placeholder stays, without data" [ "$(q "$T/out/placeholder.glb" "d['buffers'][1]")" = "{'byteLength': 8, 'name': 'placeholder'}" ]
check "placeholder.gltf: no file for it" [ "$(q "$T/out/placeholder.gltf" "'uri' in d['buffers'][1]")" = False ]

# 4, 9. Images as data URIs: PNG and WebP (EXT_texture_webp) go into the BIN
#    chunk; KTX2 without KHR_texture_basisu stays a data URI (a bufferView may
#    not hold it: that would be an error), as does a KTX2 file (copied).
convert images URI_GLB DATA_URI_GLB
check "images.glb: PNG and WebP embedded, KTX2 as it was" [ "$(q "$T/out/images.glb" "[(i.get('mimeType'), 'bufferView' in i, i.get('uri', '')[:16]) for i in d['images']]")" = "[('image/png', True, ''), ('image/webp', True, ''), (None, False, 'data:image/ktx2;')]" ]
convert ktx2-file URI_GLB
check "ktx2-file.glb: kept by URI and copied beside it" cmp "$W/magnum-2d-mips.ktx2" "$T/out/magnum-2d-mips.ktx2"
# An image of no bytes (magnum's invalid-uri.gltf: "data:image/png;base64,")
# stays a data URI: a bufferView holds a byte at least (it was embedded as
# one of 0 bytes, from a memcpy of NULL that UBSan reported).
printf '{"asset": {"version": "2.0"}, "images": [{"uri": "data:image/png;base64,"}]}' >"$T/empty-image.gltf"
run "$VNC" "$T/empty-image.gltf" "$T/out/empty-image.glb" -q
check "empty image -> .glb: kept as a data URI" [ "$rc|$(q "$T/out/empty-image.glb" "[d['images'], d.get('bufferViews')]")" = "0|[[{'uri': 'data:image/png;base64,'}], None]" ]
# A buffer without data beside the one vn makes for the new normals, and a
# data URI of no bytes: both copied from NULL, which UBSan reports (so these
# abort under CI's sanitizer build before the fix); found by fuzz_gltf with
# its dictionary from the Khronos validator's test files.
printf '{"asset": {"version": "2.0"}, "buffers": [{"byteLength": 4}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
  "accessors": [{"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 0]}]}' >"$T/no-data-and-new.gltf"
run "$VNC" "$T/no-data-and-new.gltf" "$T/out/no-data-and-new.glb" -q
check "a buffer without data and a new one -> .glb" [ "$rc|$(q "$T/out/no-data-and-new.glb" "d['buffers']")" = "0|[{'byteLength': 36}, {'byteLength': 4}]" ]
printf '{"asset": {"version": "2.0"}, "buffers": [{"uri": "data:,", "byteLength": 0}]}' >"$T/empty-data-uri.gltf"
run "$VNC" "$T/empty-data-uri.gltf" "$T/out/empty-data-uri.gltf" -q
check "a data URI of no bytes -> .gltf: still one" [ "$rc|$(q "$T/out/empty-data-uri.gltf" "d['buffers']")" = "0|[{'uri': 'data:application/octet-stream;base64,', 'byteLength': 0}]" ]

# A triangle primitive of 2 vertices (no triangle): its vertices keep their
# normal (here none: (0, 0, 1)); found by the fuzzer under UBSan.
convert two-vertices

# Refused in one line: a GLB whose buffer 0 would have no data, glTF 1.0.
run "$VNC" "$W/no-data.gltf" "$T/out/no-data.glb"
check "no-data.gltf -> .glb: refused" [ $rc -eq 1 ] && check "no-data: one line" one_line_err
check "no-data: says why" grep -q "buffers\[0\] has no data (no uri, and no extension that gives it), and buffer 0 without uri is a GLB's BIN chunk: write .gltf" "$T/stderr"
check "no-data: no output" [ ! -e "$T/out/no-data.glb" ]
run "$VNC" "$W/no-data.gltf" "$T/out/no-data.gltf"
check "no-data.gltf -> .gltf: kept" [ $rc -eq 0 ] && check "no-data.gltf: the buffer as it was" [ "$(q "$T/out/no-data.gltf" "d['buffers']")" = "[{'byteLength': 4}]" ]
check_rejected "$VNC" "$W/gltf1.gltf" "$T/none.glb" "$T/keep.glb"
check "gltf1.gltf: names the version" grep -q "gltf1.gltf: glTF 1.0 (vn reads glTF 2.0)" "$T/stderr"
# Early glTF 1.0 writes the version as a number (assimp's CesiumMilkTruck):
# named as 1.0 too (it was "buffers is not an array").
printf '{"asset": {"version": 1}, "buffers": {"b": {"uri": "b.bin", "byteLength": 4}}}' >"$T/gltf1-number.gltf"
check_rejected "$VNC" "$T/gltf1-number.gltf" "$T/none.glb" "$T/keep.glb"
check "gltf1-number.gltf: names the version" grep -q "gltf1-number.gltf: glTF 1.0 (vn reads glTF 2.0)" "$T/stderr"
# A buffer whose uri is "" (flywave's Splatting/uncompressed.gltf): said so
# (it named the glTF's folder: "cannot read: Is a directory").
printf '{"asset": {"version": "2.0"}, "buffers": [{"uri": "", "byteLength": 4}]}' >"$T/empty-uri.gltf"
check_rejected "$VNC" "$T/empty-uri.gltf" "$T/none.glb" "$T/keep.glb"
check "empty-uri.gltf: says the uri is empty" grep -q "empty-uri.gltf: buffers\[0\].uri is empty: it names no file$" "$T/stderr"
# A number no double holds (the validator's infinite_transform.gltf): said
# so, without the JSON library's exception id.
printf '{"asset": {"version": "2.0"}, "nodes": [{"translation": [1e309, 0, 0]}]}' >"$T/infinite.gltf"
check_rejected "$VNC" "$T/infinite.gltf" "$T/none.glb" "$T/keep.glb"
check "infinite.gltf: says which number" grep -q "infinite.gltf: the glTF JSON has a number beyond the range of a double, '1e309': glTF's numbers are finite$" "$T/stderr"

finish
