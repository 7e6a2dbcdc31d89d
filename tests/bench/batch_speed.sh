#!/usr/bin/env bash
# Batch conversion against a shell loop of single conversions (issue 17).
#
#   tests/bench/batch_speed.sh [BUILD_DIR] [FORMAT] [RUNS]   (default: build glb 5)
#
# Makes a folder of 200 mixed models (batch_inputs.sh). Then times, with
# farm-bench (A and B in turn, the ratio taken pair by pair),
#   A  vnconvert --out-dir OUT --format FORMAT -q IN        (-j: every core)
#   B  for f in IN/*; do vnconvert "$f" OUT/...; done       (each with every core)
# and prints the triangles, the files and farm-bench's report.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
B=${1:-$ROOT/build}
FORMAT=${2:-glb}
RUNS=${3:-5}
VNC=$B/vnconvert
PEERS=${PEERS_DIR:-$ROOT/../shared/bench/peers}
OUT=${BENCH_OUT:-/tmp/vn-bench}/batch
[ -x "$VNC" ] || { echo "no $VNC: build first" >&2; exit 1; }
rm -rf "$OUT"
mkdir -p "$OUT/base" "$OUT/in" "$OUT/out" "$OUT/loop"

. "$HERE/batch_inputs.sh"
batch_inputs "$OUT/base" "$OUT/in"
"$VNC" --out-dir "$OUT/out" --format "$FORMAT" -r "$OUT/in" 2>&1 | tail -1

# The loop, as a user would write it: one vnconvert per file.
cat >"$OUT/loop.sh" <<EOF
#!/bin/sh
for f in "$OUT/in"/* "$OUT/in"/Duck/*.gltf; do
  case "\$f" in *.off|*.obj|*.ply|*.stl|*.glb|*.drc|*.gltf) ;; *) continue ;; esac
  b=\${f##*/}
  "$VNC" "\$f" "$OUT/loop/\${b%.*}.$FORMAT" -q
done
EOF
chmod +x "$OUT/loop.sh"
farm-bench -n "$RUNS" --timeout 600 --vs "$OUT/loop.sh" -- "$VNC" --out-dir "$OUT/out" --format "$FORMAT" -q -r "$OUT/in"
