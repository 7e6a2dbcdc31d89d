#!/usr/bin/env bash
# EXT_meshopt_compression and KHR_meshopt_compression: the files of
# tests/data/gltf/meshopt/ (made by gltfpack and glTF-Transform, see its README)
# converted with --meshopt keep and off to .glb and .gltf, and checked with the
# Khronos glTF-Validator (no code the input did not have), with the npm
# meshoptimizer decoder (tests/gltf/meshopt.mjs: every accessor but NORMAL
# decodes to the input's values, NORMALs are unit vectors matching --meshopt
# off's, fallback data match the compressed data, keep keeps what was
# compressed, off leaves no extension) and on the output's JSON; damaged and
# newer streams are refused in one line.
#   test_gltf_meshopt.sh PATH/TO/vnconvert NODE_MODULES_DIR
set -u
VNC=$1
MODULES=$2
HERE=$(cd "$(dirname "$0")" && pwd)
D=$HERE/data/gltf/meshopt
. "$HERE/lib.sh"
for p in gltf-validator meshoptimizer; do
  if [ ! -d "$MODULES/$p" ]; then
    echo "FAIL: $MODULES/$p is missing: run .ci/setup (npm install $p)"
    exit 1
  fi
done

# decoded IN OUT [OPTION...]: tests/gltf/meshopt.mjs's checks of OUT against IN.
decoded() { node "$HERE/gltf/meshopt.mjs" "$MODULES" "$@"; }

mkdir -p "$T/out"
# The NORMAL accessors of the primitives whose views keep the extension (vn wrote
# them in place), and the fallback buffers' uris (none: no data).
normals_compressed="all('extensions' in d['bufferViews'][d['accessors'][p['attributes']['NORMAL']]['bufferView']] for m in d['meshes'] for p in m['primitives'])"
fallback_uris="[b.get('uri') for b in d['buffers'] if 'extensions' in b]"
filters="[e.get('filter') for v in d['bufferViews'] for e in v.get('extensions', {}).values()]"
for in in duck-cc.glb duck-c/duck-c.gltf duck-c/duck-khr.gltf morph-cc.glb morph-cf/morph-cf.gltf morph-vnf.glb man-cc.glb \
  duck-gt.glb exp-separate.gltf; do
  name=$(basename "${in%.*}")
  for mode in off keep; do
    for e in glb gltf; do
      o=$T/out/$name-$mode.$e
      run "$VNC" "$D/$in" "$o" --meshopt $mode
      check "$name --meshopt $mode -> .$e: exit 0" [ $rc -eq 0 ]
    done
    check "$name --meshopt $mode: no new validator code" quietly node "$HERE/gltf/validate.mjs" "$MODULES" "$D/$in" \
      "$T/out/$name-$mode.glb" "$T/out/$name-$mode.gltf"
  done
  for e in glb gltf; do
    check "$name off -> .$e: decodes as the input, no meshopt left" quietly decoded "$D/$in" "$T/out/$name-off.$e" --plain
    check "$name keep -> .$e: decodes as the input, compressed as it was, NORMAL as off's" \
      quietly decoded "$D/$in" "$T/out/$name-keep.$e" --kept --normals "$T/out/$name-off.glb"
    check "$name keep -> .$e: NORMAL compressed" [ "$(q "$T/out/$name-keep.$e" "$normals_compressed")" = True ]
    check "$name keep -> .$e: the extensions as they were" [ "$(q "$T/out/$name-keep.$e" "d['extensionsUsed'], d.get('extensionsRequired')")" = "$(q "$D/$in" "d['extensionsUsed'], d.get('extensionsRequired')")" ]
  done
  # vn reads its own output: converted again, it decodes as the first.
  run "$VNC" "$T/out/$name-keep.glb" "$T/out/$name-again.glb"
  check "$name keep, again: exit 0" [ $rc -eq 0 ]
  check "$name keep, again: decodes as the first" quietly decoded "$T/out/$name-keep.glb" "$T/out/$name-again.glb" --kept
  # The mesh path decodes too: glTF to OFF as from the plain output.
  run "$VNC" "$D/$in" "$T/out/$name.off"
  run "$VNC" "$T/out/$name-off.glb" "$T/out/$name-plain.off"
  check "$name -> .off: as from --meshopt off's output" cmp -s "$T/out/$name.off" "$T/out/$name-plain.off"
done
# A fallback without data stays so (GLB: after the BIN chunk's buffer); one with data holds the new data.
check "duck-cc keep: the fallback stays without data" [ "$(q "$T/out/duck-cc-keep.glb" "$fallback_uris")" = "[None]" ]
check "duck-c keep -> .gltf: the fallback stays without data" [ "$(q "$T/out/duck-c-keep.gltf" "$fallback_uris")" = "[None]" ]
check "morph-cf keep -> .gltf: the fallback keeps its file" [ "$(q "$T/out/morph-cf-keep.gltf" "$fallback_uris")" = "['morph-cf-keep_1.bin']" ]
check "morph-cf keep -> .glb: the fallback merged into the BIN chunk" [ "$(q "$T/out/morph-cf-keep.glb" "[b.get('uri') for b in d['buffers']]")" = "[None]" ]
check "duck-cc: the normals encoded again, OCTAHEDRAL" [ "$(q "$T/out/duck-cc-keep.glb" "$filters")" = "['OCTAHEDRAL', None, None]" ]
check "duck-cc off: the fallback is the BIN chunk" [ "$(q "$T/out/duck-cc-off.glb" "d['buffers']")" = "[{'byteLength': 52752}]" ]
check "duck-c off -> .gltf: one .bin, the fallback's data" [ "$(q "$T/out/duck-c-off.gltf" "d['buffers']")" = "[{'byteLength': 52752, 'uri': 'duck-c-off.bin'}]" ]
check "morph-vnf: float normals encoded again, EXPONENTIAL" [ "$(q "$T/out/morph-vnf-keep.glb" "$filters")" = "['EXPONENTIAL', None, None, None]" ]
check "exp-separate: EXPONENTIAL would move _DATA: NONE" [ "$(q "$T/out/exp-separate-keep.gltf" "$filters")" = "[None]" ]
check "man-cc: the filters kept" [ "$(q "$T/out/man-cc-keep.glb" "$filters")" = "$(q "$D/man-cc.glb" "$filters")" ]

# --crease-angle splits every vertex's data into new, plain accessors: the
# meshopt views go, and the extension with them.
run "$VNC" "$D/duck-cc.glb" "$T/out/crease.glb" --crease-angle 30
check "duck-cc --crease-angle: exit 0" [ $rc -eq 0 ]
check "duck-cc --crease-angle: no new validator code" quietly node "$HERE/gltf/validate.mjs" "$MODULES" "$D/duck-cc.glb" "$T/out/crease.glb"
check "duck-cc --crease-angle: the extension gone with its views" [ "$(q "$T/out/crease.glb" "d['extensionsRequired'], len(d['buffers'])")" = "(['KHR_mesh_quantization'], 1)" ]
check "duck-cc --crease-angle: the buffer holds only the views" [ "$(q "$T/out/crease.glb" "d['buffers'][0]['byteLength'] <= sum(v['byteLength'] + 3 for v in d['bufferViews'])")" = True ]

# In place, --meshopt off gives the fallback a file of its own, never one of the input's.
mkdir -p "$T/inplace" && cp "$D"/duck-c/duck-c.* "$T/inplace/"
run "$VNC" "$T/inplace/duck-c.gltf" "$T/inplace/duck-c.gltf" --in-place --meshopt off
check "duck-c --in-place --meshopt off: exit 0" [ $rc -eq 0 ]
check "duck-c --in-place --meshopt off: the input's .bin untouched" cmp -s "$D/duck-c/duck-c.bin" "$T/inplace/duck-c.bin"
check "duck-c --in-place --meshopt off: decodes as the input" quietly decoded "$D/duck-c/duck-c.gltf" "$T/inplace/duck-c.gltf" --plain
check "duck-c --in-place --meshopt off: a new .bin" [ "$(q "$T/inplace/duck-c.gltf" "[b.get('uri') for b in d['buffers']]")" = "['duck-c_1.bin']" ]

# Options: glTF to glTF only, keep or off.
run "$VNC" "$D/duck-cc.glb" "$T/out/x.off" --meshopt off
check "--meshopt to OFF: usage error" [ $rc -eq 2 ] && check "--meshopt to OFF: one line" one_line_err
run "$VNC" "$D/duck-cc.glb" "$T/out/x.glb" --meshopt on
check "--meshopt on: usage error" [ $rc -eq 2 ] && check "--meshopt on: says the values" grep -q "keep or off" "$T/stderr"

# patch IN OUT PYTHON: OUT is IN (a GLB) with its JSON d and BIN chunk b (a
# bytearray) changed by PYTHON.
patch() {
  python3 - "$1" "$2" "$3" <<'EOF'
import json, struct, sys
raw = open(sys.argv[1], "rb").read()
n = struct.unpack("<I", raw[12:16])[0]
d, b = json.loads(raw[20:20 + n]), bytearray(raw[28 + n:])
stream = lambda v: d["bufferViews"][v]["extensions"]["EXT_meshopt_compression"]
exec(sys.argv[3])
text = json.dumps(d).encode()
text += b" " * (-len(text) % 4)
open(sys.argv[2], "wb").write(struct.pack("<III", 0x46546C67, 2, 28 + len(text) + len(b)) +
                              struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(b), 0x004E4942) + b)
EOF
}
# refused NAME WHAT MESSAGE: converting $T/NAME.glb fails in one line with MESSAGE.
refused() {
  check_rejected "$VNC" "$T/$1.glb" "$T/none.glb" "$T/keep.glb"
  check "$1: $2" grep -q "$3" "$T/stderr"
}
patch "$D/duck-cc.glb" "$T/truncated.glb" "stream(1)['byteLength'] -= 40"
refused truncated "names the damaged view" "truncated.glb: bufferViews\[1\]: its EXT_meshopt_compression data are damaged"
patch "$D/duck-cc.glb" "$T/damaged.glb" "s = stream(2); b[s['byteOffset'] + 1:s['byteOffset'] + 200] = bytes(199)"
refused damaged "names the damaged view" "bufferViews\[2\]: its EXT_meshopt_compression data are damaged (meshoptimizer cannot decode them as TRIANGLES)"
patch "$D/duck-cc.glb" "$T/short.glb" "stream(1)['byteLength'] = 100"
refused short "too few bytes" "bufferViews\[1\].extensions.EXT_meshopt_compression: its 100 bytes of data are too few for 2290 elements of 8 bytes"
patch "$D/duck-cc.glb" "$T/vertex-v1.glb" "b[stream(0)['byteOffset']] = 0xa1"
refused vertex-v1 "names the version" "bufferViews\[0\]: EXT_meshopt_compression vertex data of bitstream version 1, which vn's meshoptimizer 0.18 cannot decode"
patch "$D/duck-cc.glb" "$T/index-v2.glb" "b[stream(2)['byteOffset']] = 0xe2"
refused index-v2 "names the version" "bufferViews\[2\]: EXT_meshopt_compression index data of bitstream version 2, which"
cp "$D/morph-khr-v1.glb" "$T/khr-v1.glb"
refused khr-v1 "names the version" "khr-v1.glb: bufferViews\[0\]: KHR_meshopt_compression vertex data of bitstream version 1, which vn's meshoptimizer 0.18 cannot decode"
patch "$D/duck-cc.glb" "$T/color.glb" "stream(0)['filter'] = 'COLOR'"
refused color "names the filter" "bufferViews\[0\].extensions.EXT_meshopt_compression.filter is COLOR, which vn's meshoptimizer 0.18 cannot decode"
patch "$D/duck-cc.glb" "$T/stride.glb" "stream(0)['byteStride'] = 6"
refused stride "names the rule" "bufferViews\[0\].extensions.EXT_meshopt_compression: byteStride 6 and count 2290 do not suit mode ATTRIBUTES, filter OCTAHEDRAL"
patch "$D/duck-cc.glb" "$T/overlap.glb" "d['bufferViews'][0]['buffer'] = 0"
refused overlap "says what overlaps" "bufferViews\[0\]: its data in buffers\[0\] overlap compressed data"
patch "$D/duck-cc.glb" "$T/huge.glb" "d['buffers'][1]['byteLength'] = 2**40; d['bufferViews'][0]['byteOffset'] = 2**39"
refused huge "bounds the memory" "buffers\[1\]: its meshopt views end at byte"
finish
