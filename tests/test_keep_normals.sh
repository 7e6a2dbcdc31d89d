#!/usr/bin/env bash
# A vertex no face gives a normal (no face uses it, or only zero-area ones)
# keeps the input's normal in every output format, and gets the format's
# "no normal" (OFF: (0, 0, 0); Draco: the zero vector, which it decodes as
# (1, 0, 0); glTF: (0, 0, 1), as glTF's normals must be unit vectors) only when the input has none (issue 16). Inputs:
# tests/data/keep_normals/ (a NOFF, a glTF, a .drc made by draco_encoder and
# one with int8 normals made by the npm draco3d encoder, each with normals,
# and an OFF without), converted to OFF, glTF, GLB and
# Draco; outputs read by tests/keep_normals.py (OFF, glTF) and the npm
# draco3d decoder (.drc). A point cloud (normals, no faces) keeps its normals
# in OFF, Draco and glTF (a POINTS primitive).
#   test_keep_normals.sh PATH/TO/vnconvert NODE_MODULES
set -u
VNC=$1
NODE_MODULES=$2
HERE=$(cd "$(dirname "$0")" && pwd)
DATA=$HERE/data/keep_normals
. "$(dirname "$0")/lib.sh"
KN="python3 $HERE/keep_normals.py"
check "draco3d is installed" [ -f "$NODE_MODULES/draco3d/package.json" ]

# dump FILE: "x y z nx ny nz" per vertex (a .drc through draco3d).
dump() {
  case $1 in
  *.drc) node "$HERE/draco/decode.mjs" "$NODE_MODULES" "$1" >"$T/decoded.json" && $KN --dump "$T/decoded.json" ;;
  *) $KN --dump "$1" ;;
  esac
}
# readable OUT: OUT as keep_normals.py compares it (a .drc decoded to JSON).
readable() {
  case $1 in
  *.drc) node "$HERE/draco/decode.mjs" "$NODE_MODULES" "$1" >"$1.json" && echo "$1.json" ;;
  *) echo "$1" ;;
  esac
}
# expect MODE FILE: the loose vertices of FILE (every one at x > 1.5) with
# their normals, under a first line MODE, into $T/expected.
expect() { { echo "$1"; dump "$2" | awk '$1 > 1.5'; } >"$T/expected"; }
# zeros NORMAL INPUT: the loose vertices of INPUT with normal NORMAL.
zeros() { { echo exact; $KN --dump "$2" | awk -v n="$1" '$1 > 1.5 { print $1, $2, $3, n }'; } >"$T/expected"; }

for in in loose.off loose.gltf loose.drc loose_int8.drc loose_plain.off; do
  for ext in off gltf glb drc; do
    dst=$T/${in%.*}-${in##*.}.$ext
    run "$VNC" "$DATA/$in" "$dst"
    check "$in -> $ext exits 0" [ $rc -eq 0 ]
    check "$in -> $ext: warns of the vertices without a normal" grep -q "have no normal" "$T/stderr"
    if [ "$in" = loose_plain.off ]; then
      # Draco's octahedral coding has no zero vector: it decodes as (1, 0, 0).
      case $ext in gltf | glb) z="0 0 1" ;; drc) z="1 0 0" ;; *) z="0 0 0" ;; esac
      zeros "$z" "$DATA/loose.off"
      check "$in -> $ext: says what they got" grep -q "written as" "$T/stderr"
    else
      check "$in -> $ext: says they keep the input's normal" grep -q "the input's normal kept" "$T/stderr"
      case $in.$ext in
      loose_int8.drc.drc) expect "angle 0.2" "$DATA/$in" ;;
      # int8 normals: the unit vector they stand for (draco3d decodes v / 127)
      loose_int8.drc.*) expect "angle 0.001" "$DATA/$in" ;;
      *.off) expect exact "$DATA/$in" ;;        # float precision, OFF's for every normal
      *.gltf | *.glb) expect unit "$DATA/$in" ;;  # the same floats (one of length 2 normalized)
      *.drc) expect "angle 0.2" "$DATA/$in" ;;  # 10 bits (draco_encoder's and vn's default)
      esac
    fi
    if [ "$ext" = drc ]; then
      # Draco keeps no vertex without a face: only those of the zero-area one.
      awk 'NR == 1 || $1 < 4.5' "$T/expected" >"$T/e" && mv "$T/e" "$T/expected"
    fi
    check "$in -> $ext: the loose vertices are there" [ "$(wc -l <"$T/expected")" -ge 4 ]
    check "$in -> $ext: their normals" $KN "$(readable "$dst")" "$T/expected"
  done
done

# loose_lines OFF [X]: the vertex lines of OFF at x > X (1.5), spaces as one.
loose_lines() { awk -v x="${2:-1.5}" '!/^#/ && NF == 6 && $1 > x { print $1, $2, $3, $4, $5, $6 }' "$1"; }
# OFF to OFF keeps them as written, digit for digit (a length 2 one too).
run "$VNC" "$DATA/loose.off" "$T/text.off"
check "loose.off -> off: the loose lines as in the input" \
  diff <(loose_lines "$DATA/loose.off") <(loose_lines "$T/text.off")

# A point cloud: the normals kept in OFF, in Draco (a point cloud stream,
# to its quantization) and in glTF (a POINTS primitive, as float32).
run "$VNC" "$DATA/points.off" "$T/points.off"
check "points.off -> off exits 0" [ $rc -eq 0 ]
check "points.off -> off: every normal kept" \
  diff <(loose_lines "$DATA/points.off" -1) <(loose_lines "$T/points.off" -1)
run "$VNC" "$DATA/points.off" "$T/points.drc" --draco-cl 10 --stats
check "points.off -> drc exits 0" [ $rc -eq 0 ]
# --stats measures the quantization on the decoded point cloud (it failed:
# "a Draco point cloud, not a mesh").
check "points.off -> drc --stats: the 3 normals' quantization error" grep -q "^draco normal quantization error: median [0-9.]* deg, max [0-9.]* deg (qn=10, 3 normals)$" "$T/stdout"
draco_decoder -i "$T/points.drc" -o "$T/points-drc.ply" >/dev/null
check "points.off -> drc: every normal kept, within 1 degree" python3 - "$HERE" "$T/points-drc.ply" <<'EOF'
import sys
import numpy as np
sys.path.insert(0, sys.argv[1])
import plytool
v = plytool.read(sys.argv[2])[2]["vertex"][1]
n = np.array([v["nx"], v["ny"], v["nz"]], float).T
want = np.array([[0.6, 0, 0.8], [0, -0.6, 0.8], [0, 0, -1]])
cos = (n * want).sum(1) / np.linalg.norm(n, axis=1)
sys.exit(not (n.shape == (3, 3) and np.degrees(np.arccos(np.clip(cos, -1, 1))).max() < 1))
EOF
{ echo exact; dump "$DATA/points.off"; } >"$T/expected"
for ext in gltf glb; do
  run "$VNC" "$DATA/points.off" "$T/points.$ext"
  check "points.off -> $ext exits 0" [ $rc -eq 0 ]
  check "points.off -> $ext: every normal kept" $KN "$T/points.$ext" "$T/expected"
done
finish
