#!/usr/bin/env bash
# Draco (.drc) in vnconvert: every sample and method decodes with Debian's
# draco_decoder and with the npm draco3d decoder to the input's points and
# triangles within a quantization step; OFF round trips; quantization flags;
# the normal quantization statistics; corrupt streams. KHR_draco_mesh_compression
# in glTF: re-encoded primitives decode to the input's points and triangles;
# --draco off and on; a primitive without NORMAL; refusals.
#   test_draco.sh PATH/TO/vnconvert NODE_MODULES DRACO_SAMPLE_DIR GLTF_SAMPLE_DIR
# NODE_MODULES holds draco3d (build-node/node_modules, from .ci/setup);
# DRACO_SAMPLE_DIR the .drc files (tests/data/models/draco),
# GLTF_SAMPLE_DIR the glTF ones (tests/data/models/gltf).
set -u
VNC=$1
NODE_MODULES=$2
DATA=$3
GLTF=$4
HERE=$(cd "$(dirname "$0")" && pwd)
SAMPLES=$HERE/../samples
. "$(dirname "$0")/lib.sh"
COMPARE="python3 $HERE/draco/compare.py"
GLTFCHECK="python3 $HERE/gltf/gltfcheck.py"
# decode IN.drc OUT_STEM: OUT_STEM.obj (draco_decoder) and OUT_STEM.json (draco3d).
decode() {
  draco_decoder -i "$1" -o "$2.obj" >/dev/null &&
    node "$HERE/draco/decode.mjs" "$NODE_MODULES" "$1" >"$2.json"
}
# decode_each IN.drc OUT_STEM [IN.drc OUT_STEM]...: decode for many files, with
# one draco3d start (most of a small file's time).
decode_each() {
  local pairs=()
  while [ $# -ge 2 ]; do
    draco_decoder -i "$1" -o "$2.obj" >/dev/null || return 1
    pairs+=("$1" "$2.json")
    shift 2
  done
  node "$HERE/draco/decode.mjs" "$NODE_MODULES" --to "${pairs[@]}"
}
stat_of() { sed -n "s/^$1 *//p" "$T/stdout"; }

check "draco_decoder is installed" command -v draco_decoder
check "draco3d is installed" [ -f "$NODE_MODULES/draco3d/package.json" ]
inputs=("$DATA"/*.drc)
check "found the .drc samples" [ ${#inputs[@]} -ge 3 ]

# Every sample, every method: both decoders get the input's points and
# triangles back (through the same decoder), and unit normals. The input's
# quantization is kept, so every method's output has the same qp.
for f in "${inputs[@]}"; do
  name=$(basename "$f" .drc)
  check "$name: decodes" decode "$f" "$T/in-$name"
  outs=()
  pairs=()
  qps=
  for m in $("$VNC" --list-methods | cut -d' ' -f1); do
    run "$VNC" "$f" "$T/$name-$m.drc" -m "$m" --stats
    check "$name -> drc ($m) exits 0" [ $rc -eq 0 ]
    qps="$qps $(stat_of "draco settings:" | sed 's/.*qp=\([0-9]*\).*/\1/')"
    outs+=("$T/out-$name-$m")
    pairs+=("$T/$name-$m.drc" "$T/out-$name-$m")
  done
  check "$name (every method): decoders read it" decode_each "${pairs[@]}"
  qp=$(echo $qps | tr ' ' '\n' | sort -u)
  check "$name: one qp for every method ($qps)" [ "$(echo "$qp" | wc -w)" -eq 1 ]
  for ext in obj json; do
    check "$name (every method): same points and triangles, unit normals ($ext)" \
      $COMPARE --each "$T/in-$name.$ext" "$qp" "${outs[@]/%/.$ext}"
  done
  run "$VNC" "$f" "$T/$name.off" -q
  check "$name -> off: points, triangles, positions" $COMPARE "$T/in-$name.json" "$T/$name.off" 24
done

# A .drc input's quantization is kept; flags override it.
run "$VNC" "$SAMPLES/torus.off" "$T/q9.drc" --draco-qp 9 --draco-qn 7 --stats
check "flags set the bits" grep -q "^draco settings: *qp=9 qn=7 qt=12 qc=8 cl=7$" "$T/stdout"
run "$VNC" "$T/q9.drc" "$T/q9-again.drc" --stats
check "a .drc input's bits are kept" grep -q "^draco settings: *qp=9 qn=7 qt=12 qc=8 cl=7$" "$T/stdout"
run "$VNC" "$T/q9.drc" "$T/q9-cl.drc" --draco-cl 3 --draco-qn 12 --stats
check "flags override the input's bits" grep -q "^draco settings: *qp=9 qn=12 qt=12 qc=8 cl=3$" "$T/stdout"

# OFF -> DRC -> OFF: counts and positions within a step; more bits, less error.
for off in torus sphere-quads; do
  run "$VNC" "$SAMPLES/$off.off" "$T/$off.drc" -q && run "$VNC" "$T/$off.drc" "$T/$off-back.off" -q
  check "$off: OFF -> drc -> OFF exits 0" [ $rc -eq 0 ]
  check "$off: OFF -> drc -> OFF within a 14-bit step" $COMPARE "$SAMPLES/$off.off" "$T/$off-back.off" 14
done
for bits in 8 20; do
  run "$VNC" "$SAMPLES/torus.off" "$T/qp$bits.drc" -q --draco-qp "$bits" &&
    run "$VNC" "$T/qp$bits.drc" "$T/qp$bits.off" -q
  check "--draco-qp $bits round trip within its step" $COMPARE "$SAMPLES/torus.off" "$T/qp$bits.off" "$bits"
  $COMPARE "$SAMPLES/torus.off" "$T/qp$bits.off" "$bits" | sed -n 's/^max error //p' >"$T/err$bits"
done
check "--draco-qp 20 is closer than --draco-qp 8" \
  python3 -c "import sys; a, b = (float(open(f).read()) for f in sys.argv[1:]); sys.exit(not 0 <= a < b)" \
  "$T/err20" "$T/err8"

# More vertices than 3 per triangle (Draco 1.5.5's decoder refuses such streams):
# the .drc keeps only the vertices faces use, with a warning; both decoders
# read it.
printf 'OFF\n8 1 0\n0 0 0\n1 0 0\n0 1 0\n5 5 5\n6 6 6\n7 7 7\n8 8 8\n9 9 9\n3 0 1 2\n' >"$T/isolated.off"
run "$VNC" "$T/isolated.off" "$T/isolated.drc" --stats
check "isolated vertices to .drc exits 0" [ $rc -eq 0 ]
check "isolated vertices: warned" grep -q "warning: 8 vertices and 1 triangle: only the vertices faces use" "$T/stderr"
check "isolated vertices: decoders read it" decode "$T/isolated.drc" "$T/isolated"
check "isolated vertices: 3 points, 1 triangle" \
  python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); sys.exit(d["points"] != 3 or d["triangles"] != 1)' "$T/isolated.json"
check "isolated vertices: quantization error of the 3 kept normals" grep -q "(qn=10, 3 normals)$" "$T/stdout"

# --stats: the normal quantization error grows as --draco-qn shrinks.
for bits in 6 14; do
  run "$VNC" "$DATA/bunny_gltf.drc" "$T/qn$bits.drc" --draco-qn "$bits" --stats
  stat_of "draco normal quantization error:" |
    sed -n "s/^median \([0-9.]*\) deg, max \([0-9.]*\) deg (qn=$bits, [1-9][0-9]* normals)$/\1 \2/p" >"$T/qn$bits"
  check "--draco-qn $bits: stats line" [ -s "$T/qn$bits" ]
done
check "--draco-qn 6 errs more than --draco-qn 14" python3 -c "import sys
(m6, x6), (m14, x14) = (map(float, open(f).read().split()) for f in sys.argv[1:])
sys.exit(not (x6 > x14 and m6 > m14 and 0 < x6 < 10 and x14 < 0.1))" "$T/qn6" "$T/qn14"
# A mesh with GENERIC attributes of its own (CesiumMan's JOINTS_0/WEIGHTS_0 go
# to Draco as GENERIC): the error is measured through vn's own id attribute
# (before, through the mesh's first GENERIC: a median of 93 degrees, and a
# read past the end on BoxMetaDraco).
run "$VNC" "$GLTF/CesiumMan.glb" "$T/cesium.drc" --stats
check "GENERIC attributes: normal error within a 10-bit step" python3 -c "import re, sys
m = re.search(r'median ([0-9.]+) deg, max ([0-9.]+) deg \(qn=10, 3273 normals\)', open(sys.argv[1]).read())
sys.exit(not (m and float(m.group(1)) < 0.1 and float(m.group(2)) < 0.3))" "$T/stdout"

# Usage errors: exit 2.
for bad in "--draco-qp 0" "--draco-qn 1" "--draco-qn 31" "--draco-qt x" "--draco-cl 11"; do
  run "$VNC" "$SAMPLES/torus.off" "$T/u.drc" $bad
  check "$bad exits 2" [ $rc -eq 2 ]
done
run "$VNC" "$SAMPLES/torus.off" "$T/u.off" --draco-qp 12
check "--draco-qp with OFF output exits 2" [ $rc -eq 2 ]
check "usage errors write nothing" [ ! -e "$T/u.drc" ] && check "usage errors write no OFF" [ ! -e "$T/u.off" ]

# Corrupt streams and a point cloud: exit 1, one line naming the file, no
# output, an old output untouched, no temporaries.
bunny=$DATA/bunny_gltf.drc
head -c 60000 "$bunny" >"$T/truncated.drc"
head -c 20 "$bunny" >"$T/header.drc"
echo "not a Draco file" >"$T/text.drc"
python3 - "$bunny" "$T" <<'EOF'
import sys
data = open(sys.argv[1], "rb").read()
for offset in (12, 100, 1000):
    d = bytearray(data)
    for k in range(offset, offset + 4):
        d[k] ^= 0xFF
    open(f"{sys.argv[2]}/flipped{offset}.drc", "wb").write(d)
EOF
draco_encoder -point_cloud -i "$T/in-cube_att.obj" -o "$T/points.drc" >/dev/null
mkdir -p "$T/errors"
for bad in truncated header text flipped12 flipped100 flipped1000; do
  check_rejected "$VNC" "$T/$bad.drc" "$T/errors/none.drc" "$T/errors/keep.off"
done
# A Draco point cloud (draco_encoder -point_cloud: kd-tree, quantized) is
# read as draco_decoder decodes it: every point, in its order, with its
# normal, as OFF and PLY; written as Draco it stays a point cloud with
# every attribute (kd-tree sorts its points; the sequential method, level
# 10, keeps their order); as glTF it is a POINTS primitive, its normals
# made unit vectors (glTF's; Draco's decoded ones are not quite); STL output
# refuses it in one line.
draco_decoder -i "$T/points.drc" -o "$T/points-ref.ply" >/dev/null
for x in ply off drc glb; do
  run "$VNC" "$T/points.drc" "$T/points-out.$x" --stats
  check "point cloud -> $x: exits 0" [ $rc -eq 0 ]
  check "point cloud -> $x: says it computes no normals" grep -q "points.drc has no faces (a point cloud): vn computes no normals; the input's are kept" "$T/stderr"
  check "point cloud -> $x: --stats says the input's normals are kept" grep -q "^zero normals: *24 (the input's kept)$" "$T/stdout"
done
check "point cloud -> ply: draco_decoder's points and normals" python3 "$HERE/plytool.py" same_normals "$T/points-ref.ply" "$T/points-out.ply"
check "point cloud -> ply: no faces" [ "$(python3 "$HERE/plytool.py" count "$T/points-out.ply")" = "$(python3 "$HERE/plytool.py" count "$T/points-ref.ply" | cut -d' ' -f1) 0 0" ]
check "point cloud -> off: as many points, no faces" [ "$(sed -n 2p "$T/points-out.off")" = "$(python3 "$HERE/plytool.py" count "$T/points-ref.ply" | cut -d' ' -f1) 0 0" ]
check "point cloud -> drc: a point cloud stream" [ "$(od -An -tu1 -j7 -N1 "$T/points-out.drc" | tr -d ' ')" = 0 ]
# points.drc is kd-tree with normals quantized per component: read back
# with their grid, they keep it kd-tree (sequential before, unquantized).
check "point cloud -> drc: kd-tree, as its input" [ "$(od -An -tu1 -j8 -N1 "$T/points-out.drc" | tr -d ' ')" = 1 ]
draco_decoder -i "$T/points-out.drc" -o "$T/points-drc.ply" >/dev/null
check "point cloud -> drc: the same points and normals" python3 "$HERE/plytool.py" same_set "$T/points-ref.ply" "$T/points-drc.ply"
run "$VNC" "$T/points.drc" "$T/points-seq.drc" --draco-cl 10
draco_decoder -i "$T/points-seq.drc" -o "$T/points-seq.ply" >/dev/null
check "point cloud -> drc at level 10: in order" python3 "$HERE/plytool.py" same_normals "$T/points-ref.ply" "$T/points-seq.ply"
check "point cloud -> glb: no validator error or warning" grep -q '"errors":\[\],"warnings":\[\]' <(node "$HERE/gltf/validate.mjs" "$NODE_MODULES" "$T/points-out.glb")
run "$VNC" "$T/points-out.glb" "$T/points-glb.ply"
check "point cloud -> glb -> ply: as -> ply (every point in order, every attribute), the normals as unit vectors" python3 - "$HERE" "$T/points-out.ply" "$T/points-glb.ply" <<'EOF'
import sys
import numpy as np
sys.path.insert(0, sys.argv[1])
import plytool
a, b = (plytool.read(f)[2]["vertex"][1] for f in sys.argv[2:4])
same = sorted(a) == sorted(b) and all(np.array_equal(a[k], b[k]) for k in a if k not in ("nx", "ny", "nz"))
n, m = (np.array([v["nx"], v["ny"], v["nz"]], float).T for v in (a, b))
unit = n / np.linalg.norm(n, axis=1)[:, None]
sys.exit(not (same and np.abs(m - unit).max() < 1e-7 and abs(np.linalg.norm(m, axis=1) - 1).max() < 1e-6))
EOF
# A PLY point cloud to Draco and back: its points in order, within the
# quantization (20 bits on a box of 2: 2e-6); without normals, none are
# added (Draco would decode a zero normal as (1, 0, 0)).
run "$VNC" "$T/points-out.ply" "$T/points-ply.drc" --draco-cl 10 --draco-qp 20
draco_decoder -i "$T/points-ply.drc" -o "$T/points-ply.ply" >/dev/null
check "ply point cloud -> drc: its points, in order" python3 - "$HERE" "$T/points-ref.ply" "$T/points-ply.ply" <<'EOF'
import sys
import numpy as np
sys.path.insert(0, sys.argv[1])
import plytool
a, b = (plytool.read(f)[2]["vertex"][1] for f in sys.argv[2:4])
p, q = (np.array([v["x"], v["y"], v["z"]], float) for v in (a, b))
sys.exit(not (p.shape == q.shape and np.abs(p - q).max() <= 2e-6))
EOF
printf 'OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0.5\n' >"$T/bare.off"
run "$VNC" "$T/bare.off" "$T/bare.drc"
check "off point cloud -> drc: says no normals are written" grep -q "it has none, and none are written$" "$T/stderr"
draco_decoder -i "$T/bare.drc" -o "$T/bare.ply" >/dev/null
check "off point cloud -> drc: 3 points, no NORMAL" [ "$(grep -ac "property float n" "$T/bare.ply")" = 0 ] && check "off point cloud -> drc: 3 points" [ "$(python3 "$HERE/plytool.py" count "$T/bare.ply")" = "3 0 0" ]
mkdir -p "$T/cloud"
check_rejected "$VNC" "$T/points.drc" "$T/cloud/none.stl" "$T/cloud/keep.stl"
check "point cloud -> stl: says what holds one" grep -q "points.drc has 24 vertices and no faces (a point cloud), and vn writes STL only with faces: write OFF, PLY, OBJ, glTF or Draco to keep a point cloud" "$T/stderr"
# float64 attributes (PDAL's Draco writer stores coordinates so; they were
# refused: "a type or size vn does not handle"). PDAL's 1.2-with-color
# point cloud: 1065 points, float64 POSITION and GpsTime, uint16 colours
# and 9 more dimensions. Its coordinates are LAS integers times 0.01:
# read as doubles, each times 100 is an integer (as floats, 637012.24 is
# 0.01 off).
D64=$HERE/data/draco/pdal-1.2-with-color.drc
run "$VNC" "$D64" "$T/pdal.ply"
check "float64 point cloud -> ply: exits 0" [ $rc -eq 0 ]
check "float64 point cloud -> ply: 1065 double positions, hundredths exactly; GpsTime double" python3 - "$HERE" "$T/pdal.ply" <<'EOF'
import sys
import numpy as np
sys.path.insert(0, sys.argv[1])
import plytool
types, v = plytool.read(sys.argv[2])[2]["vertex"]
x = np.array([v["x"], v["y"], v["z"]], float).T
sys.exit(not ([types[k] for k in ("x", "y", "z", "gpstime")] == ["double"] * 4 and x.shape == (1065, 3) and
              np.abs(x * 100 - np.round(x * 100)).max() < 1e-6 and np.abs(x[0] - [637012.24, 849028.31, 431.66]).max() < 1e-6))
EOF
# .drc to .drc keeps every attribute as it is, float64 ones too.
run "$VNC" "$D64" "$T/pdal.drc"
check "float64 point cloud -> drc: exits 0" [ $rc -eq 0 ]
run "$VNC" "$T/pdal.drc" "$T/pdal-drc.ply"
check "float64 point cloud -> drc -> ply: as -> ply" python3 "$HERE/plytool.py" same_normals "$T/pdal.ply" "$T/pdal-drc.ply"
run "$VNC" "$D64" "$T/pdal.glb"
check "float64 point cloud -> glb: GpsTime said to be rounded" grep -q "pdal.glb: _GPSTIME is double, written as float: 1065 of its 1065 values rounded" "$T/stderr"
# A float64 tetrahedron (written by vn_drc_encode): normals computed on the
# doubles; .drc to .drc keeps them (--stats measures on them too; level
# 10 keeps the points in order).
run "$VNC" "$HERE/data/draco/float64-tetra.drc" "$T/f64.off"
check "float64 mesh -> off: its coordinates and normals" [ "$(sed -n '3p;6p' "$T/f64.off")" = "637012.24 849028.31 431.66 -0.577350269 -0.577350269 -0.577350269
637012.24 849028.31 432.66 -0.275421415 -0.275421415 0.921024478" ]
run "$VNC" "$HERE/data/draco/float64-tetra.drc" "$T/f64.drc" --stats --draco-cl 10
check "float64 mesh -> drc --stats: the quantization error on its positions" grep -qx "draco normal quantization error: median 0.1272 deg, max 0.1586 deg (qn=10, 4 normals)" "$T/stdout"
run "$VNC" "$T/f64.drc" "$T/f64-drc.off"
check "float64 mesh -> drc -> off: as -> off" cmp "$T/f64.off" "$T/f64-drc.off"
# In glTF no accessor describes float64 data: refused in one line (it was
# read as floats).
python3 - "$HERE/data/draco/float64-tetra.drc" "$T/f64.glb" <<'EOF'
import json, struct, sys
drc = open(sys.argv[1], "rb").read()
chunk = drc + b"\0" * (-len(drc) % 4)
doc = {"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_draco_mesh_compression"],
       "extensionsRequired": ["KHR_draco_mesh_compression"],
       "buffers": [{"byteLength": len(chunk)}], "bufferViews": [{"buffer": 0, "byteLength": len(drc)}],
       "accessors": [{"componentType": 5126, "count": 4, "type": "VEC3", "min": [637012.24, 849028.31, 431.66],
                      "max": [637013.24, 849029.31, 432.66]}, {"componentType": 5125, "count": 12, "type": "SCALAR"}],
       "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "extensions": {
           "KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": 0}}}}]}]}
text = json.dumps(doc).encode()
text += b" " * (-len(text) % 4)
open(sys.argv[2], "wb").write(struct.pack("<III", 0x46546C67, 2, 28 + len(text) + len(chunk)) +
                              struct.pack("<II", len(text), 0x4E4F534A) + text +
                              struct.pack("<II", len(chunk), 0x004E4942) + chunk)
EOF
mkdir -p "$T/f64errors"
check_rejected "$VNC" "$T/f64.glb" "$T/f64errors/none.glb" "$T/f64errors/keep.glb"
check "float64 Draco in glTF: says why" grep -q "f64.glb: meshes\[0\].primitives\[0\]: the Draco data's POSITION is float64, which no glTF accessor describes" "$T/stderr"
# A 163-byte stream declaring 387M faces (found by fuzzing: libdraco would
# allocate 4.6 GB before noticing) is refused before decoding.
check_rejected "$VNC" "$HERE/data/draco/hostile-counts.drc" "$T/errors/none.drc" "$T/errors/keep.off"
check "hostile counts: says why" grep -q "declares 387389207 faces .* in 163 bytes" "$T/stderr"
# 300 bytes on which libdraco spends seconds before failing (found by
# fuzzing): refused with libdraco's reason (and decoded once, not twice).
# Run once, not through check_rejected: it takes libdraco 14 s.
run "$VNC" "$HERE/data/draco/fuzz/slow-attributes.drc" "$T/errors/none.drc"
check "slow attributes: exits 1" [ $rc -eq 1 ]
check "slow attributes: one line" one_line_err
check "slow attributes: says why" grep -q "slow-attributes.drc: corrupt Draco stream (Failed to decode point attributes.)" "$T/stderr"
check "slow attributes: no output" [ ! -e "$T/errors/none.drc" ]
check "no temporary files left" [ "$(ls -A "$T/errors")" = keep.off ]
# A point cloud of 1,065 points with a float attribute on a 30-bit grid
# (found by fuzzing): Draco's entropy coder took 4 GB to encode its values
# again (4 bytes for every value up to the largest), so vn stores them
# without it. GNU time's peak, under 1 GB in sanitizer builds too.
peak_kib=$(/usr/bin/time -f %M "$VNC" -q "$HERE/data/draco/fuzz/wide-30-bit-cloud.drc" "$T/wide.drc" 2>&1 >/dev/null | tail -1)
check "30-bit attribute: converted within 1 GB (${peak_kib} KiB)" [ "${peak_kib:-0}" -gt 0 -a "${peak_kib:-0}" -lt 1048576 ]
check "30-bit attribute: Draco reads it back, 1065 points" \
  sh -c "draco_decoder -i '$T/wide.drc' -o '$T/wide.ply' >/dev/null && grep -q 'element vertex 1065' '$T/wide.ply'"
# A tetrahedron whose NORMAL is typed POSITION (found by fuzzing): Draco
# 1.5.5's encoder crashes on two POSITIONs, so .drc output refuses it; glTF
# output keeps the second as an attribute.
run "$VNC" "$HERE/data/draco/two-positions.drc" "$T/errors/two.drc"
check "two POSITIONs to .drc: exits 1, no crash" [ $rc -eq 1 ]
check "two POSITIONs: says why" grep -q "both POSITION, which Draco cannot encode" "$T/stderr"
check "two POSITIONs: no output, no temporary" [ "$(ls -A "$T/errors")" = keep.off ]
run "$VNC" "$HERE/data/draco/two-positions.drc" "$T/two.glb" -q
check "two POSITIONs to .glb: exits 0" [ $rc -eq 0 ]
# Integer POSITION (uint16, as gltfpack quantizes; make_uint16_position_drc.mjs):
# read in the stream's own units, the tetrahedron's corner normal at the origin
# is -(1, 1, 1)/sqrt(3) whatever the weighting.
run "$VNC" "$HERE/data/draco/uint16_position.drc" "$T/u16.off" -q
check "uint16 POSITION to OFF: exits 0" [ $rc -eq 0 ]
check "uint16 POSITION: coordinates and origin normal" [ "$(sed -n 3,4p "$T/u16.off")" = "0 0 0 -0.577350269 -0.577350269 -0.577350269
1000 0 0 0.921024478 -0.275421415 -0.275421415" ]

# .drc to .drc keeps everything but NORMAL: three conversions in a row give
# the input's attributes (unique ids, types, metadata) and, at every
# triangle corner, its decoded values exactly (the input's own quantization
# grid); both decoders read each output. Draco's 14-bit car (TEX_COORD),
# 11-bit cube-parts (GENERIC attributes with metadata), 10-bit tetra-rgba
# (uint8 COLOR), a bitstream 2.1 stream, uint16 POSITION.
ATTRS="node $HERE/draco/attributes.mjs $NODE_MODULES"
SAME="python3 $HERE/draco/same.py"
DD=$HERE/data/draco
for f in "$DATA/car.drc" "$DD/cube-parts.drc" "$DD/tetra-rgba.drc" "$DD/test_nm.obj.edgebreaker.1.1.0.drc" \
  "$DD/uint16_position.drc"; do
  name=$(basename "$f" .drc)
  prev=$f
  for k in 1 2 3; do
    run "$VNC" "$prev" "$T/keep-$name-$k.drc" -q
    check "$name: .drc -> .drc #$k exits 0" [ $rc -eq 0 ]
    prev=$T/keep-$name-$k.drc
  done
  check "$name: decoders read the third" decode "$prev" "$T/keep-$name"
  check "$name: unit normals" $COMPARE --normals "$T/keep-$name.json"
  $ATTRS "$f" >"$T/keep-$name-0.json"
  $ATTRS "$prev" >"$T/keep-$name-3.json"
  check "$name: three conversions change nothing but NORMAL" $SAME "$T/keep-$name-0.json" "$T/keep-$name-3.json"
done
check "cube-parts: GENERIC metadata kept" grep -q '"name":"sub_obj"' "$T/keep-cube-parts-3.json"
# Polygons kept by draco_encoder -preserve_polygons (an "added_edges" mark a
# point, read across the triangles' shared edges) come back as polygons from
# vn's stream: a 3 x 3 quad grid on shared vertices and an octagon (Draco's
# octagon_preserved.obj). Before, each point had a POSITION value of its
# own, edgebreaker saw every shared edge as a cut, and draco_decoder gave
# the octagon back as 4 triangles and a quad.
python3 - "$T/poly.obj" <<'EOF'
import math, sys
with open(sys.argv[1], "w") as o:
    for j in range(4):
        for i in range(4):
            o.write(f"v {i} {j} {0.1 * i * j}\n")
    for k in range(8):
        a = 2 * math.pi * k / 8
        o.write(f"v {6 + math.cos(a)} {1.5 + math.sin(a)} 0\n")
    for j in range(3):
        for i in range(3):
            v = 1 + 4 * j + i
            o.write(f"f {v} {v + 1} {v + 5} {v + 4}\n")
    o.write("f " + " ".join(str(17 + k) for k in range(8)) + "\n")
EOF
polygons() { grep '^f ' "$1" | awk '{print NF - 1}' | sort -n | uniq -c | tr -s ' \n' ' '; }
draco_encoder -i "$T/poly.obj" -o "$T/poly.drc" -preserve_polygons >/dev/null
check "preserved polygons: draco_encoder made the input" [ -s "$T/poly.drc" ]
draco_decoder -i "$T/poly.drc" -o "$T/poly-in.obj" >/dev/null
check "preserved polygons: the input decodes to 9 quads and an octagon" \
  [ "$(polygons "$T/poly-in.obj")" = " 9 4 1 8 " ]
run "$VNC" "$T/poly.drc" "$T/poly-out.drc" -q
check "preserved polygons: .drc -> .drc exits 0" [ $rc -eq 0 ]
draco_decoder -i "$T/poly-out.drc" -o "$T/poly-out.obj" >/dev/null
check "preserved polygons: vn's stream decodes to 9 quads and an octagon" \
  [ "$(polygons "$T/poly-out.obj")" = " 9 4 1 8 " ]
# New bits: a new grid, within a step of the new bits.
run "$VNC" "$DATA/car.drc" "$T/keep-car-qp10.drc" -q --draco-qp 10
check "--draco-qp 10 on a .drc: exits 0" [ $rc -eq 0 ]
$ATTRS "$T/keep-car-qp10.drc" >"$T/keep-car-qp10.json"
check "--draco-qp 10: positions moved (a new grid)" not $SAME "$T/keep-car-0.json" "$T/keep-car-qp10.json"
check "--draco-qp 10: within a 10-bit step" python3 -c "import sys; sys.exit(not float(sys.argv[1]) <= 1)" \
  "$($SAME "$T/keep-car-0.json" "$T/keep-car-qp10.json" 10 | sed -n 's/^max position step //p')"
# A .drc without NORMAL gets one (the next free unique id).
run "$VNC" "$DD/tetra-rgba.drc" "$T/keep-tetra.drc" --stats
check "no NORMAL: attributes counted" grep -q "^attributes: *3 " "$T/stdout"
check "no NORMAL: added with unique id 2" python3 -c "import json, sys
d = json.load(open(sys.argv[1]))
sys.exit([(a['unique_id'], a['type']) for a in d['attributes']] != [(0, 0), (1, 2), (2, 1)])" "$T/keep-tetra-rgba-3.json"

# Valid streams of older bitstream versions are read (2.1 above; 1.1 here),
# with their counts.
run "$VNC" "$DD/test_nm.obj.edgebreaker.1.1.0.drc" "$T/nm.off" -q
check "bitstream 2.1: exits 0" [ $rc -eq 0 ]
check "bitstream 2.1: 99 points, 170 triangles" grep -q "^99 170 0$" "$T/nm.off"
run "$VNC" "$DATA/cube_att.drc" "$T/cube-att.drc" -q
check "bitstream 1.1 -> .drc exits 0" [ $rc -eq 0 ]

# A NaN position: refused before anything is written (exit 1, one line
# naming the point), for .drc and every other output; no temporaries.
mkdir -p "$T/nan"
for nan in nan.drc nan.off nan.glb; do
  run "$VNC" "$DD/nan-position.drc" "$T/nan/$nan"
  check "NaN position -> $nan exits 1" [ $rc -eq 1 ]
  check "NaN position -> $nan: names the point" grep -q "point 2\|vertex 2" "$T/stderr"
done
check "NaN position: nothing written, no temporaries" [ -z "$(ls -A "$T/nan")" ]

# Attributes beyond POSITION and NORMAL reach glTF: TEXCOORD_0, Draco's
# GENERIC as _NAME (from its metadata), COLOR_0 as normalized bytes; and
# from glTF back to .drc.
glb_attributes() {
  python3 - "$HERE/gltf" "$1" <<'EOF'
import sys
sys.path.insert(0, sys.argv[1])
import gltfcheck
_, doc, _ = gltfcheck.load(sys.argv[2])
p = doc["meshes"][0]["primitives"][0]["attributes"]
a = doc["accessors"]
print(" ".join(f"{k}:{a[v]['componentType']}:{a[v]['type']}:{int(a[v].get('normalized', False))}" for k, v in sorted(p.items())))
EOF
}
run "$VNC" "$DD/cube-parts.drc" "$T/cube-parts.glb" -q
check "cube-parts -> glb: every attribute" [ "$(glb_attributes "$T/cube-parts.glb")" = \
  "NORMAL:5126:VEC3:0 POSITION:5126:VEC3:0 TEXCOORD_0:5126:VEC2:0 _ADDED_EDGES:5121:SCALAR:0 _SUB_OBJ:5121:SCALAR:0" ]
run "$VNC" "$DD/tetra-rgba.drc" "$T/tetra.glb" -q
check "tetra-rgba -> glb: COLOR_0" [ "$(glb_attributes "$T/tetra.glb")" = \
  "COLOR_0:5121:VEC4:1 NORMAL:5126:VEC3:0 POSITION:5126:VEC3:0" ]
run "$VNC" "$DATA/car.drc" "$T/car.glb" -q
check "car -> glb: TEXCOORD_0" [ "$(glb_attributes "$T/car.glb")" = \
  "NORMAL:5126:VEC3:0 POSITION:5126:VEC3:0 TEXCOORD_0:5126:VEC2:0" ]
run "$VNC" "$T/cube-parts.glb" "$T/cube-parts-back.drc" -q
check "cube-parts glb -> drc exits 0" [ $rc -eq 0 ]
$ATTRS "$T/cube-parts-back.drc" >"$T/cube-parts-back.json"
check "cube-parts glb -> drc: TEX_COORD and named GENERICs" python3 -c "import json, sys
d = json.load(open(sys.argv[1]))
sys.exit(sorted((a['type'], a['metadata'].get('name', '')) for a in d['attributes']) !=
         [(0, ''), (1, ''), (3, ''), (4, 'ADDED_EDGES'), (4, 'SUB_OBJ')])" "$T/cube-parts-back.json"

# glTF with KHR_draco_mesh_compression, every method (default --draco keep):
# the output's Draco data decode, with both decoders, to the input's points
# and triangles exactly (same bits, positions unchanged), with unit normals.
for f in "$GLTF/Box_Draco.glb" "$GLTF/BoxMetaDraco/BoxMetaDraco.gltf"; do
  name=$(basename "${f%.*}")
  check "$name: has Draco data" $GLTFCHECK drc "$f" "$T/g-$name"
  check "$name: decodes" decode "$T/g-${name}_0.drc" "$T/g-$name"
  outs=()
  pairs=()
  for m in $("$VNC" --list-methods | cut -d' ' -f1); do
    for ext in glb gltf; do
      dst=$T/g-$name-$m-out.$ext
      run "$VNC" "$f" "$dst" -m "$m" -q
      check "$name -> $ext ($m) exits 0" [ $rc -eq 0 ]
      check "$name -> $ext ($m): Draco data" $GLTFCHECK drc "$dst" "$T/g-$name-$m-$ext"
      outs+=("$T/g-$name-$m-$ext")
      pairs+=("$T/g-$name-$m-${ext}_0.drc" "$T/g-$name-$m-$ext")
    done
  done
  check "$name -> glb, gltf (every method): decoders read it" decode_each "${pairs[@]}"
  for x in obj json; do
    check "$name -> glb, gltf (every method): same points and triangles, unit normals ($x)" \
      $COMPARE --each "$T/g-$name.$x" 30 "${outs[@]/%/.$x}"
  done
  run "$VNC" "$f" "$T/g-$name-off.glb" -q --draco off
  check "$name --draco off exits 0" [ $rc -eq 0 ]
  check "$name --draco off: no Draco left" $GLTFCHECK nodraco "$T/g-$name-off.glb"
  check "$name --draco off: flat box faces" $GLTFCHECK flat "$T/g-$name-off.glb"
done
# The re-encoded Draco data replace the old (removed), also in a document
# using EXT_mesh_features.
run "$VNC" "$GLTF/Box_Draco.glb" "$T/g-box-stats.glb" --stats
check "Box_Draco: the old Draco bufferView removed" grep -q "^removed unused: *0 accessors, 1 bufferView$" "$T/stdout"
run "$VNC" "$GLTF/BoxMetaDraco/BoxMetaDraco.gltf" "$T/g-meta.gltf" --stats
check "BoxMetaDraco: the old Draco bufferView removed" grep -q "^removed unused: *0 accessors, 1 bufferView$" "$T/stdout"
# Converting the output again finds the Box's hard edges again.
run "$VNC" "$GLTF/Box_Draco.glb" "$T/g-box.glb" -q && run "$VNC" "$T/g-box.glb" "$T/g-box-off.glb" -q --draco off
check "Box_Draco keeps its hard edges" $GLTFCHECK flat "$T/g-box-off.glb"

# --draco on, --stats (the normal quantization error of the new normals),
# --draco-qn overriding an input's normal bits, --draco off after on.
run "$VNC" "$GLTF/Duck.glb" "$T/duck-on.glb" --draco on --stats
check "--draco on exits 0" [ $rc -eq 0 ]
check "--draco on: counted" grep -q "^draco primitives: *1 (0 left uncompressed)$" "$T/stdout"
check "--draco on: the old accessors and bufferViews removed" \
  grep -q "^removed unused: *4 accessors, 3 bufferViews$" "$T/stdout"
check "--draco on: the file shrinks (120484 bytes in)" [ "$(stat -c %s "$T/duck-on.glb")" -lt 40000 ]
check "--draco on: qn=10 stats line" \
  grep -q "^draco normal quantization error: median 0\.[0-9]* deg, max 0\.[0-9]* deg (qn=10, 2399 normals)$" "$T/stdout"
check "--draco on: Draco data" $GLTFCHECK drc "$T/duck-on.glb" "$T/duck-on"
check "--draco on: decoders read it" decode "$T/duck-on_0.drc" "$T/duck-on"
run "$VNC" "$GLTF/Duck.glb" "$T/duck.off" -q
check "--draco on: the Duck's points and triangles within 14 bits" $COMPARE "$T/duck.off" "$T/duck-on.json" 14
check "--draco on: unit normals" $COMPARE --normals "$T/duck-on.json"
# --draco on from other formats (it applied to glTF to glTF only): the file
# is the one glTF to glTF --draco on makes of vn's plain output, byte for
# byte, with the bits given; an OBJ's primitive per material each
# compressed; a vertex no face uses and a point cloud named.
run "$VNC" "$SAMPLES/torus.off" "$T/torus-plain.glb" -q
run "$VNC" "$T/torus-plain.glb" "$T/torus-via.glb" -q --draco on --draco-qp 12
run "$VNC" "$SAMPLES/torus.off" "$T/torus-on.glb" --draco on --draco-qp 12 --stats
check "OFF --draco on: exits 0, qp=12" [ "$rc $(grep -c '^draco settings: *qp=12 qn=10 ' "$T/stdout")" = "0 1" ]
check "OFF --draco on: as glTF to glTF --draco on makes it" cmp -s "$T/torus-via.glb" "$T/torus-on.glb"
check "OFF --draco on: Draco data" $GLTFCHECK drc "$T/torus-on.glb" "$T/torus-on"
check "OFF --draco on: decoders read it" decode "$T/torus-on_0.drc" "$T/torus-on"
run "$VNC" "$SAMPLES/torus.off" "$T/torus-vn.off" -q
check "OFF --draco on: the torus within 12 bits" $COMPARE "$T/torus-vn.off" "$T/torus-on.json" 12
check "OFF --draco on: unit normals" $COMPARE --normals "$T/torus-on.json"
check "OFF --draco on: the file shrinks" [ "$(stat -c %s "$T/torus-on.glb")" -lt "$(($(stat -c %s "$T/torus-plain.glb") / 5))" ]
run "$VNC" "$SAMPLES/torus.off" "$T/torus-on.gltf" -q --draco on --draco-qp 12
check "OFF --draco on, .gltf: no validator error or warning" \
  node "$HERE/gltf/validate.mjs" --allow UNSUPPORTED_EXTENSION --allow UNUSED_OBJECT "$NODE_MODULES" "$T/torus-plain.glb" "$T/torus-on.gltf"
run "$VNC" "$HERE/data/obj/mat_test.obj" "$T/mat-on.glb" -q --draco on
check "OBJ --draco on: each material's primitive compressed" $GLTFCHECK drc "$T/mat-on.glb" "$T/mat-on"
check "OBJ --draco on: 7 primitives" [ -f "$T/mat-on_6.drc" ]
printf 'OFF\n5 1 0\n0 0 0\n1 0 0\n0 1 0\n5 5 5\n6 6 6\n3 0 1 2\n' >"$T/loose.off"
run "$VNC" "$T/loose.off" "$T/loose-on.glb" --draco on
check "--draco on: vertices no face uses named" \
  grep -qxF "vnconvert: warning: 2 vertices no face uses are not written: a Draco-compressed primitive holds only the vertices its triangles use" "$T/stderr"
printf 'OFF\n2 0 0\n0 0 0\n1 0 0\n' >"$T/cloud.off"
run "$VNC" "$T/cloud.off" "$T/cloud-on.glb" --draco on
check "--draco on: a point cloud stays plain, named" \
  [ "$rc $(grep -c "KHR_draco_mesh_compression compresses triangles, so its points are written uncompressed" "$T/stderr")" = "0 1" ]
check "--draco on: a point cloud stays plain" $GLTFCHECK nodraco "$T/cloud-on.glb"
run "$VNC" "$T/duck-on.glb" "$T/duck-qn.glb" --draco-qn 6 --stats
check "--draco-qn overrides the input's normal bits" grep -q "^draco normal quantization error: .*(qn=6, 2399 normals)$" "$T/stdout"
run "$VNC" "$T/duck-on.glb" "$T/duck-off.glb" -q --draco off
check "--draco off after on: no Draco left" $GLTFCHECK nodraco "$T/duck-off.glb"
run "$VNC" "$T/duck-off.glb" "$T/duck-back.off" -q
check "--draco off: the decoded points and triangles" $COMPARE "$T/duck-on.json" "$T/duck-back.off" 24

# --draco-qp re-quantizes an already compressed primitive (keep): the Duck
# at 10 bits is within a 10-bit step of the input but not a 14-bit one, and
# POSITION's min/max are the decoded positions' bounds.
run "$VNC" "$T/duck-on.glb" "$T/duck-qp.glb" -q --draco-qp 10
check "--draco-qp 10 (keep) exits 0" [ $rc -eq 0 ]
check "--draco-qp 10: Draco data" $GLTFCHECK drc "$T/duck-qp.glb" "$T/duck-qp"
check "--draco-qp 10: decoders read it" decode "$T/duck-qp_0.drc" "$T/duck-qp"
check "--draco-qp 10: within 10 bits" $COMPARE "$T/duck.off" "$T/duck-qp.json" 10
check "--draco-qp 10: re-quantized (not within 14 bits)" not $COMPARE "$T/duck.off" "$T/duck-qp.json" 14
bounds() {
  python3 - "$HERE/gltf" "$@" <<'EOF'
import json, struct, sys
sys.path.insert(0, sys.argv[1])
import gltfcheck
_, doc, _ = gltfcheck.load(sys.argv[2])
p = json.load(open(sys.argv[3]))["positions"]
a = doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]
f32 = lambda v: struct.unpack("<f", struct.pack("<f", v))[0]
want = [[f32(min(p[k::3])) for k in range(3)], [f32(max(p[k::3])) for k in range(3)]]
sys.exit(0 if [a["min"], a["max"]] == want else "%s != %s" % ([a["min"], a["max"]], want))
EOF
}
check "--draco-qp 10: POSITION min/max are the decoded bounds" bounds "$T/duck-qp.glb" "$T/duck-qp.json"

# --draco on with a primitive drawing part of a shared accessor (the shapes
# strip uses 26 of the sphere's 117 vertices): Draco 1.5.5's decoder refuses more
# points than 3 per triangle, so the unused vertices are left out.
$GLTFCHECK shapes "$T/shapes.gltf"
run "$VNC" "$T/shapes.gltf" "$T/shapes-on.glb" -q --draco on
check "shapes --draco on exits 0" [ $rc -eq 0 ]
check "shapes --draco on: Draco data" $GLTFCHECK drc "$T/shapes-on.glb" "$T/shapes-on"
for k in 0 1 2 3; do
  check "shapes --draco on: primitive $k decodes" decode "$T/shapes-on_$k.drc" "$T/shapes-on-$k"
done
check "shapes --draco on: the strip keeps its 26 vertices, 24 triangles" \
  python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); sys.exit(d["points"] != 26 or d["triangles"] != 24)' \
  "$T/shapes-on-3.json"

# Morph targets: --draco on compresses AnimatedMorphCube with its points in
# order (the targets' accessors follow it); read back (keep, then off), the
# morphed normals are still the scheme's normals of the morphed positions.
AMC=$GLTF/AnimatedMorphCube/AnimatedMorphCube.gltf
run "$VNC" "$AMC" "$T/amc-on.glb" -m mwa --draco on --stats
check "AnimatedMorphCube --draco on: compressed" grep -q "^draco primitives: *1 (0 left uncompressed)$" "$T/stdout"
check "AnimatedMorphCube --draco on: Draco data" $GLTFCHECK drc "$T/amc-on.glb" "$T/amc-on"
check "AnimatedMorphCube --draco on: decoders read it" decode "$T/amc-on_0.drc" "$T/amc-on"
run "$VNC" "$AMC" "$T/amc.glb" -q -m mwa
in_order() {
  python3 - "$HERE/gltf" "$@" <<'EOF'
import json, sys
sys.path.insert(0, sys.argv[1])
import gltfcheck
p = json.load(open(sys.argv[2]))["positions"]
_, doc, buf = gltfcheck.load(sys.argv[3])
index = doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
a = doc["accessors"][index]
q = [c for v in gltfcheck.accessor_values(doc, buf, index) for c in v]
step = max(a["max"][k] - a["min"][k] for k in range(3)) / (2 ** 14 - 1)
sys.exit(len(p) != len(q) or max(abs(x - y) for x, y in zip(p, q)) > step)
EOF
}
check "AnimatedMorphCube --draco on: points in order" in_order "$T/amc-on.json" "$T/amc.glb"
run "$VNC" "$T/amc-on.glb" "$T/amc-keep.glb" -q -m mwa
check "Draco with morph targets read and kept" [ $rc -eq 0 ]
run "$VNC" "$T/amc-keep.glb" "$T/amc-off.glb" -q -m mwa --draco off
check "Draco with morph targets: --draco off" $GLTFCHECK nodraco "$T/amc-off.glb"
check "Draco with morph targets: morphed normals" $GLTFCHECK morph "$T/amc-off.glb" "$VNC" mwa split

# A Draco primitive without NORMAL gets one: a new unique id and a
# bufferView-less accessor; both decoders read unit normals.
grep -E '^(v|f) ' "$T/in-cube_att.obj" | sed 's#/[0-9/]*##g' >"$T/cube-plain.obj"
draco_encoder -i "$T/cube-plain.obj" -o "$T/cube-plain.drc" >/dev/null
node "$HERE/draco/decode.mjs" "$NODE_MODULES" "$T/cube-plain.drc" >"$T/cube-plain.json"
python3 - "$T/cube-plain.drc" "$T/cube-plain.json" "$T/cube-plain.glb" <<'EOF'
import json, struct, sys
drc, decoded, out = sys.argv[1:]
data = open(drc, "rb").read()
d = json.load(open(decoded))
doc = {"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_draco_mesh_compression"],
       "extensionsRequired": ["KHR_draco_mesh_compression"], "scene": 0, "scenes": [{"nodes": [0]}],
       "nodes": [{"mesh": 0}],
       "meshes": [{"primitives": [{"attributes": {"POSITION": 1}, "indices": 0, "extensions": {
           "KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": 0}}}}]}],
       "accessors": [{"componentType": 5123, "count": 3 * d["triangles"], "type": "SCALAR"},
                     {"componentType": 5126, "count": d["points"], "type": "VEC3",
                      "min": [min(d["positions"][k::3]) for k in range(3)],
                      "max": [max(d["positions"][k::3]) for k in range(3)]}],
       "bufferViews": [{"buffer": 0, "byteLength": len(data)}], "buffers": [{"byteLength": len(data)}]}
text = json.dumps(doc).encode()
text += b" " * (-len(text) % 4)
binary = data + b"\0" * (-len(data) % 4)
open(out, "wb").write(struct.pack("<III", 0x46546C67, 2, 28 + len(text) + len(binary)) +
                      struct.pack("<II", len(text), 0x4E4F534A) + text +
                      struct.pack("<II", len(binary), 0x004E4942) + binary)
EOF
run "$VNC" "$T/cube-plain.glb" "$T/cube-normal.glb" --stats
check "no NORMAL: exits 0" [ $rc -eq 0 ]
check "no NORMAL: an accessor added" grep -q "^appended accessors: *1$" "$T/stdout"
check "no NORMAL: default qn=10" grep -q "^draco normal quantization error: .*(qn=10, " "$T/stdout"
check "no NORMAL: structure" $GLTFCHECK diff "$T/cube-plain.glb" "$T/cube-normal.glb"
check "no NORMAL: Draco data" $GLTFCHECK drc "$T/cube-normal.glb" "$T/cube-normal"
check "no NORMAL: decoders read it" decode "$T/cube-normal_0.drc" "$T/cube-normal"
for x in obj json; do
  check "no NORMAL: unit normals ($x)" $COMPARE --normals "$T/cube-normal.$x"
done
check "no NORMAL: same points and triangles" $COMPARE "$T/cube-plain.json" "$T/cube-normal.json" 30

# --crease-angle splits the vertices of a Draco primitive too: it is
# encoded again with more points, which both decoders read.
run "$VNC" "$T/duck-on.glb" "$T/duck-crease.glb" --crease-angle 30 --stats
check "--crease-angle on a Draco primitive exits 0" [ $rc -eq 0 ]
check "--crease-angle on Draco: vertices split" grep -q "^split vertices: *[1-9][0-9]*$" "$T/stdout"
check "--crease-angle on Draco: Draco data" $GLTFCHECK drc "$T/duck-crease.glb" "$T/duck-crease"
check "--crease-angle on Draco: decoders read it" decode "$T/duck-crease_0.drc" "$T/duck-crease"
run "$VNC" "$T/duck-on.glb" "$T/duck-crease-off.glb" -q --crease-angle 30 --draco off
check "--crease-angle with --draco off exits 0" [ $rc -eq 0 ]
run "$VNC" "$GLTF/Box.glb" "$T/x.off" --draco off
check "--draco with OFF output exits 2" [ $rc -eq 2 ]
run "$VNC" "$GLTF/Box.glb" "$T/x.glb" --draco maybe
check "--draco maybe exits 2" [ $rc -eq 2 ]

# A corrupt Draco stream inside a GLB (and a .gltf), a missing Draco
# attribute: exit 1, one line naming the file, no output.
python3 - "$GLTF/Box_Draco.glb" "$T/cube-plain.glb" "$T" <<'EOF'
import json, struct, sys
box, plain, t = sys.argv[1:]
d = bytearray(open(box, "rb").read())
length = struct.unpack_from("<I", d, 12)[0]
start = 20 + length + 8  # the BIN chunk's data: the Draco bufferView at offset 0
for k in range(start + 20, start + 60):
    d[k] ^= 0x5A
open(t + "/draco-flipped.glb", "wb").write(d)
d = bytearray(open(box, "rb").read())
open(t + "/draco-truncated.glb", "wb").write(d[:start + 60])
d = bytearray(open(plain, "rb").read())
text = d[20:20 + struct.unpack_from("<I", d, 12)[0]].replace(b'"POSITION": 0}', b'"POSITION": 7}')
open(t + "/draco-missing.glb", "wb").write(bytes(d[:20]) + text + bytes(d[20 + len(text):]))
EOF
mkdir -p "$T/gerrors"
for bad in draco-flipped.glb draco-truncated.glb draco-missing.glb; do
  check_rejected "$VNC" "$T/$bad" "$T/gerrors/none.glb" "$T/gerrors/keep.glb"
done
check "no temporary files left (glTF)" [ "$(ls -A "$T/gerrors")" = keep.glb ]

# Draco data as public files have it (tests/data/draco/gltf; the README
# beside the .drc files says how each was made). Every mode, with and without
# --crease-angle, gives a file in which the validator finds nothing new.
# Correctness is checked without welding, so that each primitive's normals
# are vnconvert's on an OFF of its own positions and triangles.
DG=$HERE/data/draco/gltf
VALIDATE="node $HERE/gltf/validate.mjs $NODE_MODULES"
# converts IN NAME MODE [OPTIONS...]: IN to $T/NAME-MODE.glb with --draco
# MODE exits 0, and the validator finds nothing IN does not have.
converts() {
  local in=$1 name=$2 mode=$3
  shift 3
  run "$VNC" "$in" "$T/$name-$mode.glb" --draco "$mode" -q "$@"
  [ $rc -eq 0 ] && $VALIDATE "$in" "$T/$name-$mode.glb" >/dev/null
}
# streams FILE STEM: Debian's decoder reads each of FILE's Draco streams,
# which draco3d decodes into STEM_k.json (decode.mjs) and STEM_k.attr.json
# (attributes.mjs).
streams() {
  local k=0
  $GLTFCHECK drc "$1" "$2" >/dev/null || return 1
  while [ -f "$2_$k.drc" ]; do
    draco_decoder -i "$2_$k.drc" -o "$2_$k.obj" >/dev/null &&
      node "$HERE/draco/decode.mjs" "$NODE_MODULES" "$2_$k.drc" >"$2_$k.json" &&
      $ATTRS "$2_$k.drc" >"$2_$k.attr.json" || return 1
    k=$((k + 1))
  done
}

# Accessors shared by Draco primitives (valid: with Draco an accessor only
# carries count and type): three primitives over one POSITION, NORMAL and
# indices accessor; two of them over one stream (a sphere), the third over
# another (an ellipsoid). Before, --draco off refused it and --draco-qp gave
# the shared POSITION the bounds of the last primitive written.
SA=$DG/shared-accessors.gltf
check "shared accessors: input streams" streams "$SA" "$T/sa-in"
for mode in keep off on; do
  for opts in "" "--crease-angle 30" "--weld-scope mesh" "--draco-qp 10"; do
    check "shared accessors --draco $mode $opts: valid" converts "$SA" "sa${opts//[ -]/}" "$mode" $opts
  done
  check "shared accessors --draco $mode --no-weld: valid" converts "$SA" sa-exact "$mode" --no-weld -m mwa
  if [ $mode = off ]; then
    check "shared accessors --draco off: no Draco left" $GLTFCHECK nodraco "$T/sa-exact-off.glb"
    check "shared accessors --draco off: each primitive's own normals" \
      $GLTFCHECK ownnormals "$T/sa-exact-off.glb" "$VNC" mwa 0.001
    $GLTFCHECK prims "$T/sa-exact-off.glb" "$T/sa-off"
    for k in 0 1 2; do
      check "shared accessors --draco off: primitive $k, its stream's points and triangles" \
        $COMPARE "$T/sa-in_$k.json" "$T/sa-off_$k.off" 30
    done
  else
    check "shared accessors --draco $mode: streams" streams "$T/sa-exact-$mode.glb" "$T/sa-$mode"
    for k in 0 1 2; do
      check "shared accessors --draco $mode: stream $k, its input's points and triangles" \
        $COMPARE "$T/sa-in_$k.json" "$T/sa-${mode}_$k.json" 30
      check "shared accessors --draco $mode: stream $k, its own normals" \
        $GLTFCHECK drcnormals "$T/sa-${mode}_$k.json" "$VNC" mwa 1
    done
  fi
done
check "shared accessors --draco off: the ellipsoid's data under accessors of its own" \
  python3 - "$HERE/gltf" "$T/sa-exact-off.glb" <<'EOF'
import sys
sys.path.insert(0, sys.argv[1])
import gltfcheck
_, doc, _ = gltfcheck.load(sys.argv[2])
p = [q["attributes"] for q in doc["meshes"][0]["primitives"]]
sys.exit(not (p[0] == p[2] and p[1]["POSITION"] != p[0]["POSITION"] and p[1]["NORMAL"] != p[0]["NORMAL"]))
EOF
check "shared accessors --draco-qp 10: streams" streams "$T/sadracoqp10-keep.glb" "$T/sa-qp"
check "shared accessors --draco-qp 10: the shared POSITION bounds every stream's positions" \
  python3 - "$HERE/gltf" "$T/sadracoqp10-keep.glb" "$T"/sa-qp_[0-9].json <<'EOF'
import json, struct, sys
sys.path.insert(0, sys.argv[1])
import gltfcheck
_, doc, _ = gltfcheck.load(sys.argv[2])
a = doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]
p = [v for f in sys.argv[3:] for v in json.load(open(f))["positions"]]
f32 = lambda v: struct.unpack("<f", struct.pack("<f", v))[0]
want = [[f32(min(p[k::3])) for k in range(3)], [f32(max(p[k::3])) for k in range(3)]]
sys.exit(0 if [a["min"], a["max"]] == want else "%s != %s" % ([a["min"], a["max"]], want))
EOF

# KHR_mesh_quantization inside Draco data (glTF-Transform's quantize, then
# draco): int16 or int8 POSITION (normalized, or not with a node scale),
# int16 or int8 NORMAL, uint16 or uint8 TEXCOORD_0. Before, every mode
# refused it ("the Draco POSITION is not 3 floats"). Kept compressed, every
# attribute but NORMAL decodes to the input's values exactly at every
# triangle corner and NORMAL keeps its type; --draco off writes the values in
# their accessors' types. Normals within int8 (1 degree) or int16 steps.
for q in 16:0.1 8:1 raw:1; do
  name=${q%:*}
  tolerance=${q#*:}
  in=$DG/quantized-$name.glb
  check "quantized-$name: input stream" streams "$in" "$T/q$name-in"
  for mode in keep off on; do
    for opts in "" "--crease-angle 30"; do
      check "quantized-$name --draco $mode $opts: valid" converts "$in" "q$name${opts//[ -]/}" "$mode" $opts
    done
    check "quantized-$name --draco $mode --no-weld: valid" converts "$in" "q$name-exact" "$mode" --no-weld -m mwa
  done
  for mode in keep on; do
    check "quantized-$name --draco $mode: stream" streams "$T/q$name-exact-$mode.glb" "$T/q$name-$mode"
    check "quantized-$name --draco $mode: every value but NORMAL as the input's" \
      $SAME "$T/q$name-in_0.attr.json" "$T/q$name-${mode}_0.attr.json"
    check "quantized-$name --draco $mode: NORMAL keeps its integer type" python3 -c "import json, sys
t = [[a['data_type'] for a in json.load(open(f))['attributes'] if a['type'] == 1] for f in sys.argv[1:]]
sys.exit(t[0] != t[1] or t[0][0] == 9)" "$T/q$name-in_0.attr.json" "$T/q$name-${mode}_0.attr.json"
    check "quantized-$name --draco $mode: the normals of its points" \
      $GLTFCHECK drcnormals "$T/q$name-${mode}_0.json" "$VNC" mwa "$tolerance"
  done
  check "quantized-$name --draco off: accessor types kept" \
    python3 - "$HERE/gltf" "$in" "$T/q$name-exact-off.glb" <<'EOF'
import sys
sys.path.insert(0, sys.argv[1])
import gltfcheck
def types(path):
    _, doc, _ = gltfcheck.load(path)
    a = doc["meshes"][0]["primitives"][0]["attributes"]
    return {k: (doc["accessors"][v]["componentType"], doc["accessors"][v].get("normalized", False)) for k, v in a.items()}
sys.exit(types(sys.argv[2]) != types(sys.argv[3]))
EOF
  $GLTFCHECK prims "$T/q$name-exact-off.glb" "$T/q$name-off"
  check "quantized-$name --draco off: the stored positions and triangles" \
    $COMPARE "$T/q$name-in_0.json" "$T/q$name-off_0.off" 30
  check "quantized-$name --draco off: the normals" \
    $GLTFCHECK ownnormals "$T/q$name-exact-off.glb" "$VNC" mwa "$tolerance"
done
# --draco on over KHR_mesh_quantization's int8 normals: Draco 1.5.5 predicted
# them from the positions at levels 7 to 9, and (0, 0, 127) came back as (4, 4, 5).
run "$VNC" "$HERE/data/gltf/quantized.glb" "$T/quantized-on.glb" --draco on --no-weld -m mwa -q
check "quantized.glb --draco on: stream" streams "$T/quantized-on.glb" "$T/quantized-on"
check "quantized.glb --draco on: its normals" $GLTFCHECK drcnormals "$T/quantized-on_0.json" "$VNC" mwa 1

# Accessor counts that are not the decoded ones (valid: loaders use the
# decoded data; Cesium's DracoCompressed/CesiumMilkTruck.gltf says 1856
# points, its stream has 1886): decoded-count.gltf's accessors say 80, its
# sphere stream has 86 points. Before, every mode refused it. The output's
# accessors say what the output holds (with --draco off, the validator
# checks them against their bufferViews).
DC=$DG/decoded-count.gltf
check "decoded count: input stream" streams "$DC" "$T/dc-in"
for mode in keep off on; do
  for opts in "" "--crease-angle 30"; do
    check "decoded count --draco $mode $opts: valid" converts "$DC" "dc${opts//[ -]/}" "$mode" $opts
  done
  check "decoded count --draco $mode --no-weld: valid" converts "$DC" dc-exact "$mode" --no-weld -m mwa
done
$GLTFCHECK prims "$T/dc-exact-off.glb" "$T/dc-off"
check "decoded count --draco off: the stream's points and triangles" $COMPARE "$T/dc-in_0.json" "$T/dc-off_0.off" 30
check "decoded count --draco off: the normals" $GLTFCHECK ownnormals "$T/dc-exact-off.glb" "$VNC" mwa 0.001
# counts FILE STREAM_JSON: FILE's first primitive's accessors count the
# points and corners STREAM_JSON (decode.mjs) has.
counts() {
  python3 - "$HERE/gltf" "$@" <<'PY'
import json, sys
sys.path.insert(0, sys.argv[1])
import gltfcheck
_, doc, _ = gltfcheck.load(sys.argv[2])
stream = json.load(open(sys.argv[3]))
prim = doc["meshes"][0]["primitives"][0]
got = sorted({doc["accessors"][v]["count"] for v in prim["attributes"].values()}), doc["accessors"][prim["indices"]]["count"]
want = [stream["points"]], 3 * stream["triangles"]
sys.exit(0 if got == want else "%s != %s" % (got, want))
PY
}
for mode in keep on; do
  check "decoded count --draco $mode: stream" streams "$T/dc-exact-$mode.glb" "$T/dc-$mode"
  check "decoded count --draco $mode: the input's points and triangles" $COMPARE "$T/dc-in_0.json" "$T/dc-${mode}_0.json" 30
  check "decoded count --draco $mode: the normals of its points" $GLTFCHECK drcnormals "$T/dc-${mode}_0.json" "$VNC" mwa 1
  check "decoded count --draco $mode: accessor counts are the stream's" counts "$T/dc-exact-$mode.glb" "$T/dc-${mode}_0.json"
  check "decoded count --draco $mode --crease-angle 30: stream" streams "$T/dccreaseangle30-$mode.glb" "$T/dcc-$mode"
  check "decoded count --draco $mode --crease-angle 30: accessor counts are the stream's" \
    counts "$T/dccreaseangle30-$mode.glb" "$T/dcc-${mode}_0.json"
done
check "decoded count --draco off: accessor counts are the stream's" counts "$T/dc-exact-off.glb" "$T/dc-in_0.json"

# A mesh whose every triangle is degenerate (the Draco repository's
# degenerate_mesh.obj: three equal corners): edgebreaker refuses it ("All
# triangles are degenerate", which refused the file), so the sequential
# method encodes it, and both decoders read its triangle. The same in a
# glTF primitive with --draco on (which refused the whole file).
printf 'OFF\n3 1 0\n0 0 0\n0 0 0\n0 0 0\n3 2 1 0\n' >"$T/degenerate.off"
run "$VNC" "$T/degenerate.off" "$T/degenerate.drc" -q
check "all degenerate -> drc: exits 0" [ $rc -eq 0 ]
check "all degenerate: both decoders read it" decode "$T/degenerate.drc" "$T/degenerate-out"
check "all degenerate: its triangle (draco_decoder)" [ "$(grep -c '^f ' "$T/degenerate-out.obj")" = 1 ]
run "$VNC" "$T/degenerate.off" "$T/degenerate.glb" -q && run "$VNC" "$T/degenerate.glb" "$T/degenerate-d.glb" --draco on --stats
check "all degenerate -> glb --draco on: compressed" [ "$rc|$(stat_of 'draco primitives:')" = "0|1 (0 left uncompressed)" ]
finish
