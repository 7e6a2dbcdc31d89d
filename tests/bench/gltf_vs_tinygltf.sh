#!/usr/bin/env bash
# vnconvert on a large GLB against tinygltf alone loading and saving it.
#
#   tests/bench/gltf_vs_tinygltf.sh [BUILD_DIR] [NTRI]     (default: build 1e6)
#
# Makes the jittered torus of ../shared/bench/peers/genmesh.py, converts it to
# GLB once (with normals), then times with hyperfine (pinned to core 0):
#   tinygltf   load + save (the baseline; tests/bench/tinygltf_roundtrip.cpp)
#   vnconvert  load + recompute (mwselr, 1 thread) + save
# and measures each one's peak resident memory with /usr/bin/time.
# Targets (issue 4): vnconvert <= 1.5x tinygltf's time; peak memory <= 3x the file.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
B=${1:-$ROOT/build}
N=${2:-1e6}
PEERS=${PEERS_DIR:-$ROOT/../shared/bench/peers}
OUT=${BENCH_OUT:-/tmp/vn-bench}
mkdir -p "$OUT"
for p in hyperfine time; do
  dpkg -s "$p" >/dev/null 2>&1 || { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$p" >/dev/null; }
done
[ -x "$B/vnconvert" ] || { echo "no $B/vnconvert: build first" >&2; exit 1; }
g++ -O2 -std=c++17 -o "$OUT/tinygltf_roundtrip" "$HERE/tinygltf_roundtrip.cpp" -ltinygltf
off="$OUT/torus$N.off"
glb="$OUT/torus$N.glb"
[ -f "$off" ] || python3 "$PEERS/genmesh.py" "$N" "$off" >&2
[ -f "$glb" ] || "$B/vnconvert" -q "$off" "$glb"
size=$(stat -c %s "$glb")
echo "## $glb: $size bytes"
hyperfine -N --warmup 2 --runs 11 --export-csv "$OUT/gltf-times.csv" \
  -n tinygltf "taskset -c 0 $OUT/tinygltf_roundtrip $glb $OUT/tiny-out.glb" \
  -n vnconvert "taskset -c 0 $B/vnconvert -q -j 1 --method mwselr $glb $OUT/vn-out.glb"
peak() { /usr/bin/time -f %M "$@" 2>&1 >/dev/null | tail -1; }   # KiB
pt=$(peak "$OUT/tinygltf_roundtrip" "$glb" "$OUT/tiny-out.glb")
pv=$(peak "$B/vnconvert" -q -j 1 --method mwselr "$glb" "$OUT/vn-out.glb")
python3 - "$OUT/gltf-times.csv" "$size" "$pt" "$pv" <<'PY'
import csv, sys
rows = {r["command"]: float(r["median"]) for r in csv.DictReader(open(sys.argv[1]))}
size, pt, pv = int(sys.argv[2]), int(sys.argv[3]) * 1024, int(sys.argv[4]) * 1024
t, v = rows["tinygltf"], rows["vnconvert"]
print("median time: tinygltf load+save %.1f ms, vnconvert %.1f ms: ratio %.2f (target <= 1.5)" % (1e3 * t, 1e3 * v, v / t))
print("peak memory: tinygltf %.1f MB (%.2fx file), vnconvert %.1f MB (%.2fx file; target <= 3)"
      % (pt / 1e6, pt / size, pv / 1e6, pv / size))
PY
