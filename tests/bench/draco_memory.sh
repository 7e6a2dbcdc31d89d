#!/usr/bin/env bash
# Peak memory of vnconvert on large Draco glTF files, against their decoded
# size (per Draco primitive: points x every attribute's element size, plus
# the indices, as their accessors type them).
#
#   tests/bench/draco_memory.sh [BUILD_DIR] [NTRI]     (default: build 1e6)
#
# Makes the jittered torus of ../shared/bench/peers/genmesh.py, converts it to
# GLB (POSITION, NORMAL, uint32 indices) and from it, with vnconvert --draco on,
# three Draco GLBs:
#   pn      one primitive, POSITION and NORMAL
#   pnuc    one primitive, also TEXCOORD_0 (float) and COLOR_0 (normalized uint8)
#   pnuc16  pnuc cut into 16 primitives of one mesh (tests/bench/draco_inputs.py)
# Then, for each, the peak resident memory (/usr/bin/time) of
#   floor   libdraco alone decoding every stream, then decoding and encoding
#           each again as vnconvert does by default (tests/bench/draco_floor.cpp)
#   vnconvert with --draco keep, off and on, each without and with --crease-angle 30
# printed as MB and as a multiple of the decoded size, a Markdown table row per file.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
B=${1:-$ROOT/build}
N=${2:-1e6}
PEERS=${PEERS_DIR:-$ROOT/../shared/bench/peers}
OUT=${BENCH_OUT:-/tmp/vn-bench}
mkdir -p "$OUT"
dpkg -s time >/dev/null 2>&1 || { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq time >/dev/null; }
[ -x "$B/vnconvert" ] || { echo "no $B/vnconvert: build first" >&2; exit 1; }
VNC=$B/vnconvert
g++ -O2 -std=c++17 -o "$OUT/draco_floor" "$HERE/draco_floor.cpp" -ldraco
off=$OUT/torus$N.off
glb=$OUT/torus$N.glb
[ -f "$off" ] || python3 "$PEERS/genmesh.py" "$N" "$off" >&2
[ -f "$glb" ] || "$VNC" -q "$off" "$glb"
[ -f "$OUT/pn$N.glb" ] || "$VNC" -q "$glb" "$OUT/pn$N.glb" --draco on
if [ ! -f "$OUT/pnuc16$N.glb" ]; then
  python3 "$HERE/draco_inputs.py" attributes "$glb" "$OUT/uc$N.glb"
  python3 "$HERE/draco_inputs.py" split "$OUT/uc$N.glb" "$OUT/uc16$N.glb" 16
  "$VNC" -q "$OUT/uc$N.glb" "$OUT/pnuc$N.glb" --draco on
  "$VNC" -q "$OUT/uc16$N.glb" "$OUT/pnuc16$N.glb" --draco on
fi

peak() { /usr/bin/time -f %M "$@" 2>&1 >/dev/null | tail -1; } # KiB
cell() { python3 -c "import sys; k, d = int(sys.argv[1]) * 1024, int(sys.argv[2]); print('%.0f MB (%.1f×)' % (k / 1e6, k / d))" "$1" "$2"; }
echo "## $N triangles; $(basename "$B")/vnconvert; peak RSS in MB (× the decoded size)"
echo
echo "| file | decoded | libdraco decode | libdraco decode + encode | keep | keep, crease | off | off, crease | on | on, crease |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for name in pn pnuc pnuc16; do
  in=$OUT/$name$N.glb
  decoded=$(python3 "$HERE/draco_inputs.py" decoded "$in")
  rm -f "$OUT"/stream_*.drc
  python3 "$ROOT/tests/gltf/gltfcheck.py" drc "$in" "$OUT/stream" >/dev/null
  row="| $name | $(python3 -c "print('%.1f MB' % ($decoded / 1e6))")"
  for what in decode encode; do
    row="$row | $(cell "$(peak "$OUT/draco_floor" $what "$OUT"/stream_*.drc)" "$decoded")"
  done
  for mode in keep off on; do
    for crease in "" "--crease-angle 30"; do
      # shellcheck disable=SC2086 # crease is one option and its value, or nothing
      row="$row | $(cell "$(peak "$VNC" -q "$in" "$OUT/out.glb" --draco $mode $crease)" "$decoded")"
    done
  done
  echo "$row |"
done
