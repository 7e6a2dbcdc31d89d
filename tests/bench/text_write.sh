#!/usr/bin/env bash
# Writing text formats (docs/PERFORMANCE.md "Writing text formats"): the
# whole vnconvert run, two builds in turn, the least of ROUNDS wall times a
# conversion, and whether the two outputs are the same bytes.
#   tests/bench/text_write.sh OLD/vnconvert NEW/vnconvert [ROUNDS] [WORKDIR]
# Inputs, made in WORKDIR (default: a temporary folder): the regular torus
# of 200,000 triangles (400 x 250 quads, R = 1, r = 0.4, coordinates with 17
# digits), as GLB too (floats) and as OBJ from the GLB (float text), and
# 2M normal-distributed float points with unit double normals (binary PLY,
# numpy seed 1).
set -eu
OLD=$(realpath "$1") NEW=$(realpath "$2") ROUNDS=${3:-3}
W=${4:-$(mktemp -d)}
mkdir -p "$W" && cd "$W"
[ -f torus200k.off ] || /usr/bin/python3 - <<'EOF'
import math
nu, nv = 400, 250
with open("torus200k.off", "w") as f:
    f.write("OFF\n%d %d 0\n" % (nu * nv, 2 * nu * nv))
    for i in range(nu):
        for j in range(nv):
            u, v = 2 * math.pi * i / nu, 2 * math.pi * j / nv
            f.write("%.17g %.17g %.17g\n" % ((1 + 0.4 * math.cos(v)) * math.cos(u), (1 + 0.4 * math.cos(v)) * math.sin(u), 0.4 * math.sin(v)))
    for i in range(nu):
        for j in range(nv):
            a, b, c, d = i * nv + j, (i + 1) % nu * nv + j, (i + 1) % nu * nv + (j + 1) % nv, i * nv + (j + 1) % nv
            f.write("3 %d %d %d\n3 %d %d %d\n" % (a, b, c, a, c, d))
EOF
[ -f t200.glb ] || "$NEW" torus200k.off t200.glb -q
[ -f t200.obj ] || "$NEW" t200.glb t200.obj -q
[ -f cloud2m.ply ] || /usr/bin/python3 - <<'EOF'
import numpy as np
n = 2000000
rng = np.random.default_rng(1)
p = rng.normal(size=(n, 3)).astype("<f4")
nn = rng.normal(size=(n, 3))
nn /= np.linalg.norm(nn, axis=1)[:, None]
a = np.zeros(n, dtype=[("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("nx", "<f8"), ("ny", "<f8"), ("nz", "<f8")])
a["x"], a["y"], a["z"] = p.T
a["nx"], a["ny"], a["nz"] = nn.T
header = "ply\nformat binary_little_endian 1.0\nelement vertex %d\n" % n
header += "".join("property %s %s\n" % (t, k) for t, k in
                  (("float", "x"), ("float", "y"), ("float", "z"), ("double", "nx"), ("double", "ny"), ("double", "nz")))
open("cloud2m.ply", "wb").write((header + "end_header\n").encode() + a.tobytes())
EOF
for job in "torus200k.off off" "t200.glb obj" "t200.obj obj" "t200.glb off" "cloud2m.ply off"; do
  set -- $job
  for b in OLD NEW; do
    bin=${!b} best=
    for _ in $(seq "$ROUNDS"); do
      s=$(date +%s%N); "$bin" "$1" "out_$b.$2" -q; e=$(date +%s%N)
      t=$(((e - s) / 1000000)); [ -n "$best" ] && [ "$best" -le "$t" ] || best=$t
    done
    echo "$1 -> $2 $b $best ms"
  done
  cmp -s "out_OLD.$2" "out_NEW.$2" && echo "  the same bytes" || echo "  outputs differ"
done
