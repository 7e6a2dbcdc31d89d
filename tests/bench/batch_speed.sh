#!/usr/bin/env bash
# Batch conversion against a shell loop of single conversions (issue 17).
#
#   tests/bench/batch_speed.sh [BUILD_DIR] [FORMAT] [RUNS]   (default: build glb 5)
#
# Makes a folder of 200 mixed models: the samples and test files of this
# repository (OFF, OBJ, PLY, STL, GLB, .gltf with its buffer and texture, Draco) and jittered
# tori of 1,000 to 200,000 triangles (../shared/bench/peers/genmesh.py, or the
# samples alone when it is missing), each converted with vnconvert itself into
# OFF, OBJ, PLY, STL, GLB and Draco copies, numbered on to 200 files. Then times, with
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

# The base models, each in its own folder (a .gltf keeps its files beside it).
cp "$ROOT/samples/"*.off "$ROOT/tests/data/off/"*.off "$ROOT/tests/data/gltf/"*.glb "$OUT/base/"
cp "$ROOT/tests/data/models/gltf/"*.glb "$ROOT/tests/data/draco/cube.drc" "$ROOT/tests/data/draco/colored.drc" "$OUT/base/"
cp "$ROOT/tests/data/obj/blender_"*.obj "$ROOT/tests/data/obj/mat_test.obj" "$ROOT/tests/data/ply/blender_"*.ply \
  "$ROOT/tests/data/stl/test_sphere"*.stl "$OUT/base/"
if [ -f "$PEERS/genmesh.py" ]; then
  for n in 1000 5000 20000 50000 200000; do python3 "$PEERS/genmesh.py" $n "$OUT/base/torus$n.off"; done
fi
# OFF, OBJ, PLY, STL, GLB and Draco copies of each (those a format cannot hold are left out).
k=0
for f in "$OUT/base/"*; do
  stem=$(basename "${f%.*}")
  for ext in off obj ply stl glb drc; do
    "$VNC" "$f" "$OUT/base/copies_$stem.$ext" -q 2>/dev/null || true
  done
done
mkdir "$OUT/in/Duck"
cp "$ROOT/tests/data/models/gltf/Duck/"* "$OUT/in/Duck/"
files=("$OUT/base/"*)
while [ "$(find "$OUT/in" -name '*.off' -o -name '*.obj' -o -name '*.ply' -o -name '*.stl' -o -name '*.glb' -o -name '*.drc' -o -name '*.gltf' | wc -l)" -lt 200 ]; do
  f=${files[$((k % ${#files[@]}))]}
  cp "$f" "$OUT/in/$(printf %03d $k)_$(basename "$f")"
  k=$((k + 1))
done
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
