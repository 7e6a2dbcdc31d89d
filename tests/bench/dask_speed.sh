#!/usr/bin/env bash
# Files per second of a batch on a Dask cluster (vn.dask, issue 18) against a
# shell loop over vnconvert and vnconvert's own batch, on this machine.
#
#   tests/bench/dask_speed.sh [BUILD_DIR] [FORMAT] [RUNS]   (default: build glb 3)
#
# Makes the 200 mixed models of batch_inputs.sh, then starts a real cluster
# as on many machines: `dask scheduler` on the loopback address and `dask
# worker` processes (one thread each), 1 worker and then 2. Each row is
# the median of RUNS runs into an emptied folder:
#   loop      for f in IN/*; do vnconvert "$f" OUT/...; done   (one thread each)
#   vnconvert vnconvert --out-dir OUT -j N -r IN
#   vn.convert vn.convert(IN, out_dir=OUT, recursive=True, threads=N)  (one process)
#   vn.dask   python3 -m vn.dask --scheduler ADDRESS --out-dir OUT -r IN --overwrite
# vn.dask's time includes planning and connecting, not starting the cluster.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
B=${1:-$ROOT/build}
FORMAT=${2:-glb}
RUNS=${3:-3}
VNC=$B/vnconvert
PY=/usr/bin/python3
PEERS=${PEERS_DIR:-$ROOT/../shared/bench/peers}
OUT=${BENCH_OUT:-/tmp/vn-bench}/dask
[ -x "$VNC" ] || { echo "no $VNC: build first" >&2; exit 1; }
command -v dask >/dev/null || { echo "no dask command: bash .ci/setup installs python3-distributed" >&2; exit 1; }
export PYTHONPATH=$ROOT/python VN_LIBRARY=$B/libvn.so
rm -rf "$OUT"
mkdir -p "$OUT"
. "$HERE/batch_inputs.sh"
batch_inputs "$OUT/base" "$OUT/in"
IN=$OUT/in
files=$(find "$IN" -name '*.off' -o -name '*.obj' -o -name '*.ply' -o -name '*.stl' -o -name '*.glb' -o -name '*.drc' -o -name '*.gltf' | wc -l)
triangles=$("$VNC" --out-dir "$OUT/warm" --format "$FORMAT" -r "$IN" 2>&1 | tail -1)
echo "inputs: $files files ($triangles)"

pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; wait 2>/dev/null || true; }
trap cleanup EXIT

# Median seconds of RUNS runs of "$@", each into an emptied $OUT/out.
median() {
  local times=() t0 t1
  for _ in $(seq "$RUNS"); do
    rm -rf "$OUT/out"
    t0=$(date +%s.%N)
    "$@" >/dev/null 2>"$OUT/err" || { tail -3 "$OUT/err" >&2; }
    t1=$(date +%s.%N)
    times+=("$(echo "$t1 - $t0" | bc -l)")
  done
  printf '%s\n' "${times[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR + 1) / 2)]}'
}
row() { # NAME SECONDS
  printf '| %-34s | %8.2f | %8.1f |\n' "$1" "$2" "$(echo "$files / $2" | bc -l)"
}

loop() {
  mkdir -p "$OUT/out"
  for f in "$IN"/* "$IN"/Duck/*.gltf; do
    case "$f" in *.off|*.obj|*.ply|*.stl|*.glb|*.drc|*.gltf) ;; *) continue ;; esac
    b=${f##*/}
    "$VNC" "$f" "$OUT/out/${b%.*}.$FORMAT" -q -j 1 || true
  done
}

echo
echo "| run | seconds | files/s |"
echo "|---|---:|---:|"
row "shell loop over vnconvert" "$(median loop)"
for n in 1 2; do
  row "vnconvert --out-dir -j $n" "$(median "$VNC" --out-dir "$OUT/out" --format "$FORMAT" -q -r -j "$n" "$IN")"
done
for n in 1 2; do
  row "vn.convert(out_dir=...), threads=$n" "$(median $PY -c 'import sys, vn
vn.convert(sys.argv[1], out_dir=sys.argv[2], format=sys.argv[3], recursive=True, threads=int(sys.argv[4]))' \
    "$IN" "$OUT/out" "$FORMAT" "$n")"
done

dask scheduler --host 127.0.0.1 --port 0 --dashboard-address :0 --scheduler-file "$OUT/scheduler.json" \
  >"$OUT/scheduler.log" 2>&1 &
pids+=($!)
for _ in $(seq 100); do [ -s "$OUT/scheduler.json" ] && break; sleep 0.1; done
address=$($PY -c 'import json, sys; print(json.load(open(sys.argv[1]))["address"])' "$OUT/scheduler.json")
for n in 1 2; do
  dask worker "$address" --nthreads 1 --nworkers 1 --no-dashboard >"$OUT/worker$n.log" 2>&1 &
  pids+=($!)
  $PY - "$address" "$n" <<'EOF'
import sys
from distributed import Client
with Client(sys.argv[1]) as c:
    c.wait_for_workers(int(sys.argv[2]), timeout=60)
EOF
  row "vn.dask, $n worker$([ "$n" = 1 ] || echo s) (1 thread each)" \
    "$(median $PY -m vn.dask --scheduler "$address" --out-dir "$OUT/out" --format "$FORMAT" -q -r --overwrite "$IN")"
done
