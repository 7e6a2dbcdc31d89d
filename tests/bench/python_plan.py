#!/usr/bin/env python3
"""Per-frame normals from Python: vn.Plan.normals against vn.vertex_normals
(issue 20, "Use it where it counts").

    /usr/bin/python3 /work/shared/bench/peers/genmesh.py 1e6 /tmp/torus1m.off
    PYTHONPATH=python VN_LIBRARY=build/libvn.so /usr/bin/python3 tests/bench/python_plan.py /tmp/torus1m.off \\
        [--repeat 5] [--methods mwe,mwaat,mwselr,mwa] [--threads 1,2] [--csv FILE]

A benchmark, not a test. The mesh is read once (an OFF of triangles); faces
are passed as uint32 (read in place by both). For float32 and float64
positions (C-contiguous, read in place by both) and each thread count and
method, the two calls take turns, --repeat times each after a warm-up, three
times over; each writes into one output array of the positions' dtype
allocated once (out=), so neither allocates its result:
  vn.vertex_normals(p, faces, method, threads=T, out=out)  (vn_triangle_normals)
  plan.normals(p, method, out=out), plan = vn.Plan(faces, threads=T)  (vn_plan_normals)
Times are ns per triangle, the median. "create" is vn.Plan's time (median of
3), "pays off after" the frames whose saving covers it. The last column is
the largest angle between the two results in degrees (0: bit for bit).
"""
import argparse
import csv
import statistics
import sys
import time

import numpy as np

import vn


def read_off(path):
    with open(path, "rb") as f:
        words = f.read().split()
    assert words[0] == b"OFF", "%s: not an OFF file" % path
    n, m = int(words[1]), int(words[2])
    p = np.array(words[4:4 + 3 * n], dtype=np.float64).reshape(n, 3)
    f = np.array(words[4 + 3 * n:4 + 3 * n + 4 * m], dtype=np.uint32).reshape(m, 4)
    assert (f[:, 0] == 3).all(), "%s: triangles only" % path
    return p, np.ascontiguousarray(f[:, 1:])


def angle_deg(a, b):
    a, b = a.astype(np.float64), b.astype(np.float64)
    return float(np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), (a * b).sum(axis=1))).max())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("mesh")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--methods", default="mwe,mwaat,mwselr,mwa")
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--csv")
    args = ap.parse_args()
    p64, faces = read_off(args.mesh)
    tris = len(faces)
    print("%s: %d vertices, %d triangles; vn %s (%s)" % (args.mesh, len(p64), tris, vn.library().version,
                                                         vn.library().path))
    rows = []
    print("\n| positions | threads | method | vn.vertex_normals ns/tri | Plan.normals ns/tri | speed-up "
          "| create ms | pays off after | max angle deg |")
    print("|---|---|---|---|---|---|---|---|---|")
    for dtype in (np.float32, np.float64):
        p = p64.astype(dtype)
        out_a, out_b = np.empty_like(p), np.empty_like(p)
        for threads in [int(t) for t in args.threads.split(",")]:
            creates = []
            for _ in range(3):
                t0 = time.perf_counter()
                plan = vn.Plan(faces, len(p), threads=threads)
                creates.append(time.perf_counter() - t0)
                plan.close()
            create = statistics.median(creates)
            plan = vn.Plan(faces, len(p), threads=threads)
            for method in args.methods.split(","):
                calls = {"vertex_normals": lambda: vn.vertex_normals(p, faces, method, threads=threads, out=out_a),
                         "plan": lambda: plan.normals(p, method, out=out_b)}
                times = {k: [] for k in calls}
                for k, call in calls.items():
                    call()  # warm-up
                for _ in range(3):
                    for k, call in calls.items():
                        for _ in range(args.repeat):
                            t0 = time.perf_counter()
                            call()
                            times[k].append(time.perf_counter() - t0)
                a, b = (statistics.median(times[k]) for k in calls)
                pays = create / (a - b) if a > b else float("inf")
                diff = 0.0 if np.array_equal(out_a, out_b) else angle_deg(out_a, out_b)
                row = dict(positions=np.dtype(dtype).name, threads=threads, method=method,
                           vertex_normals_ns=a / tris * 1e9, plan_ns=b / tris * 1e9, speedup=a / b,
                           create_ms=create * 1e3, pays_off_frames=pays, max_angle_deg=diff)
                rows.append(row)
                print("| %s | %d | %s | %.2f | %.2f | %.2fx | %.1f | %s | %s |" % (
                    row["positions"], threads, method.upper(), row["vertex_normals_ns"], row["plan_ns"],
                    row["speedup"], row["create_ms"], "%.1f frames" % pays if pays != float("inf") else "never",
                    "0 (bit for bit)" if diff == 0 else "%.1e" % diff))
                sys.stdout.flush()
            plan.close()
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    main()
