#!/usr/bin/env bash
# vnbench beside the peer libraries, in one run, on the same meshes.
#
#   tests/bench/compare_peers.sh [BUILD_DIR] [NTRI ...]     (default: build 1e6 4e6)
#
# For each size: generates the jittered torus with ../shared/bench/peers/genmesh.py,
# runs vnbench (1 and 2 threads, CSV; per-frame plans with float32 positions,
# --plan --float32, for the schemes of issue 20), then ../shared/bench/peers/run.sh (vcglib,
# OpenMesh, CGAL, Assimp, three.js, Blender, plain C loop, bandwidth bound; it
# installs its own Debian packages). Everything single-threaded is pinned to core 0.
# Compare ratios within one run: absolute times move +-20% between runs.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
B=${1:-$ROOT/build}
shift || true
SIZES=("$@")
[ ${#SIZES[@]} -gt 0 ] || SIZES=(1e6 4e6)
PEERS=${PEERS_DIR:-$ROOT/../shared/bench/peers}
OUT=${BENCH_OUT:-/tmp/vn-bench}
mkdir -p "$OUT"
[ -x "$B/vnbench" ] || { echo "no $B/vnbench: build first (cmake -S . -B build && cmake --build build)" >&2; exit 1; }
[ -d "$PEERS" ] || { echo "peer benchmark not found at $PEERS (set PEERS_DIR)" >&2; exit 1; }

for n in "${SIZES[@]}"; do
  mesh="$OUT/torus$n.off"
  [ -f "$mesh" ] || python3 "$PEERS/genmesh.py" "$n" "$mesh" >&2
  echo "## mesh $mesh"
  echo "### vnbench, 1 thread (taskset -c 0)"
  taskset -c 0 "$B/vnbench" "$mesh" --method all --threads 1 --repeat 9 --csv | tee "$OUT/vn-$n-t1.csv"
  echo "### vnbench, 2 threads"
  "$B/vnbench" "$mesh" --method all --threads 2 --repeat 9 --csv | tee "$OUT/vn-$n-t2.csv"
  echo "### vnbench, 1 thread, allocating per call (--alloc)"
  taskset -c 0 "$B/vnbench" "$mesh" --method all --threads 1 --repeat 9 --csv --alloc | tee "$OUT/vn-$n-t1-alloc.csv"
  for t in 1 2; do
    echo "### vnbench --plan --float32, $t thread(s)"
    pin=(); [ "$t" = 1 ] && pin=(taskset -c 0)
    for m in mwe mwaat mwselr mwa; do
      "${pin[@]}" "$B/vnbench" "$mesh" --plan --float32 --method "$m" --threads "$t" --repeat 11 --csv | tail -n 1
    done | tee "$OUT/vn-$n-plan-t$t.csv"
  done
  echo "### speed-up with 2 threads"
  join -t, <(tail -n +2 "$OUT/vn-$n-t1.csv" | cut -d, -f1,4 | sort) <(tail -n +2 "$OUT/vn-$n-t2.csv" | cut -d, -f1,4 | sort) |
    awk -F, '{ printf "%-7s %.2fx\n", $1, $2 / $3 }'
  echo "### peers"
  bash "$PEERS/run.sh" "$mesh"
done
