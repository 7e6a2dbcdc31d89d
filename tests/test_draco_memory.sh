#!/usr/bin/env bash
# Peak memory of glTF conversions with Draco data: a torus of 320,000
# triangles with POSITION, NORMAL, TEXCOORD_0 and COLOR_0 in 8 Draco
# primitives (about 8 MB decoded), converted with --draco keep, off and on,
# each with and without --crease-angle 30 (2 threads), needs at most 3 times
# its decoded size above what converting one Draco triangle needs (the
# program and its libraries): 1.9 to 2.5 times here, 3.3 to 5.1 on d4658a4.
# With one primitive this large libdraco alone needs more (docs/PERFORMANCE.md,
# "Draco: peak memory"), hence several. Peaks are GNU time's (.ci/setup
# installs it). Not run in sanitizer builds, whose memory is not a release's.
#   test_draco_memory.sh PATH/TO/vnconvert
set -u
VNC=$1
HERE=$(cd "$(dirname "$0")" && pwd)
. "$HERE/lib.sh"
INPUTS="python3 $HERE/bench/draco_inputs.py"
if [ ! -x /usr/bin/time ]; then
  echo "FAIL: /usr/bin/time is missing: run .ci/setup (Debian's time)"
  exit 1
fi
# peak CMD...: CMD's peak resident memory in bytes.
peak() {
  local kib
  kib=$(/usr/bin/time -f %M "$@" 2>&1 >/dev/null | tail -1)
  echo $((kib * 1024))
}

# A torus, 400 x 400 quads cut into triangles, and one triangle.
python3 - "$T/torus.off" <<'PY'
import math, sys
n, m = 400, 400
with open(sys.argv[1], "w") as f:
    f.write("OFF\n%d %d 0\n" % (n * m, 2 * n * m))
    for i in range(n):
        for j in range(m):
            u, v = 2 * math.pi * i / n, 2 * math.pi * j / m
            f.write("%.6f %.6f %.6f\n" % ((2 + math.cos(v)) * math.cos(u), (2 + math.cos(v)) * math.sin(u), math.sin(v)))
    for i in range(n):
        for j in range(m):
            a, b, c, d = i * m + j, i * m + (j + 1) % m, (i + 1) % n * m + j, (i + 1) % n * m + (j + 1) % m
            f.write("3 %d %d %d\n3 %d %d %d\n" % (a, c, b, b, c, d))
PY
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >"$T/one.off"
for f in torus one; do
  "$VNC" -q "$T/$f.off" "$T/$f.glb" && $INPUTS attributes "$T/$f.glb" "$T/$f-uc.glb"
done
$INPUTS split "$T/torus-uc.glb" "$T/torus-8.glb" 8
"$VNC" -q "$T/torus-8.glb" "$T/big.glb" --draco on
"$VNC" -q "$T/one-uc.glb" "$T/small.glb" --draco on
decoded=$($INPUTS decoded "$T/big.glb")
check "the Draco file is made" [ "${decoded:-0}" -gt 7000000 ]

for mode in keep off on; do
  for crease in "" "--crease-angle 30"; do
    # shellcheck disable=SC2086 # crease is one option and its value, or nothing
    base=$(peak "$VNC" -q -j 2 "$T/small.glb" "$T/small-out.glb" --draco $mode $crease)
    # shellcheck disable=SC2086
    big=$(peak "$VNC" -q -j 2 "$T/big.glb" "$T/big-out.glb" --draco $mode $crease)
    ratio=$(python3 -c "import sys; print('%.2f' % ((int(sys.argv[1]) - int(sys.argv[2])) / int(sys.argv[3])))" \
      "$big" "$base" "$decoded")
    echo "--draco $mode $crease: $(((big - base) / 1000000)) MB above the program's own, ${ratio}x the decoded size"
    check "--draco $mode $crease: at most 3x the decoded size" python3 -c "import sys; sys.exit(not 0 < float(sys.argv[1]) <= 3)" "$ratio"
  done
done

finish
