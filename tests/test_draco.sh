#!/usr/bin/env bash
# Draco (.drc) in vnconvert: every sample and method decodes with Debian's
# draco_decoder and with the npm draco3d decoder to the input's points and
# triangles within a quantization step; OFF round trips; quantization flags;
# the normal quantization statistics; corrupt streams.
#   test_draco.sh PATH/TO/vnconvert NODE_MODULES DRACO_SAMPLE_DIR
# NODE_MODULES holds draco3d (build-node/node_modules, from .ci/setup);
# DRACO_SAMPLE_DIR the .drc files (../shared/data/draco from the repository).
set -u
VNC=$1
NODE_MODULES=$2
DATA=$3
HERE=$(cd "$(dirname "$0")" && pwd)
SAMPLES=$HERE/../samples
. "$(dirname "$0")/lib.sh"
COMPARE="python3 $HERE/draco/compare.py"
# decode IN.drc OUT_STEM: OUT_STEM.obj (draco_decoder) and OUT_STEM.json (draco3d).
decode() {
  draco_decoder -i "$1" -o "$2.obj" >/dev/null &&
    node "$HERE/draco/decode.mjs" "$NODE_MODULES" "$1" >"$2.json"
}
stat_of() { sed -n "s/^$1 *//p" "$T/stdout"; }

check "draco_decoder is installed" command -v draco_decoder
check "draco3d is installed" [ -f "$NODE_MODULES/draco3d/package.json" ]
inputs=("$DATA"/*.drc)
check "found the .drc samples" [ ${#inputs[@]} -ge 3 ]

# Every sample, every method: both decoders get the input's points and
# triangles back (through the same decoder), and unit normals.
for f in "${inputs[@]}"; do
  name=$(basename "$f" .drc)
  check "$name: decodes" decode "$f" "$T/in-$name"
  for m in $("$VNC" --list-methods | cut -d' ' -f1); do
    run "$VNC" "$f" "$T/$name-$m.drc" -m "$m" --stats
    check "$name -> drc ($m) exits 0" [ $rc -eq 0 ]
    qp=$(stat_of "draco settings:" | sed 's/.*qp=\([0-9]*\).*/\1/')
    check "$name ($m): decoders read it" decode "$T/$name-$m.drc" "$T/out-$name-$m"
    for ext in obj json; do
      check "$name ($m): same points and triangles ($ext)" \
        $COMPARE "$T/in-$name.$ext" "$T/out-$name-$m.$ext" "$qp"
      check "$name ($m): unit normals ($ext)" $COMPARE --normals "$T/out-$name-$m.$ext"
    done
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
for bad in truncated header text flipped12 flipped100 flipped1000 points; do
  check_rejected "$VNC" "$T/$bad.drc" "$T/errors/none.drc" "$T/errors/keep.off"
done
check "a point cloud is unsupported" grep -q "point cloud" "$T/stderr"
check "no temporary files left" [ "$(ls -A "$T/errors")" = keep.off ]

finish
