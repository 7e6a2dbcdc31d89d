#!/usr/bin/env python3
"""Speed of the Python package on numpy arrays (issue 18, "Performance").

    PYTHONPATH=python /usr/bin/python3 tests/bench/python_speed.py [--triangles 1e6] [--repeat 5]
        [--build build] [--csv FILE] [--work DIR]

A benchmark, not a test: one run prints Markdown tables (and with --csv one
row per measurement). The mesh is a closed jittered torus made here with
numpy (the scheme of shared/bench/peers/genmesh.py: parameter-space and
normal jitter, a random diagonal per quad, valences 4 to 8; seed fixed, so
every run times the same mesh). Every time is in milliseconds, from numpy
arrays to a numpy result, the median of 3 x --repeat calls: the cases
compared in one table row take turns, --repeat calls each after a warm-up
call, three times over (vnbench: 3 x --repeat calls after one warm-up):

  vn.vertex_normals(positions, faces, method, threads=T): positions (n, 3)
      C-contiguous float64 (read in place); faces (m, 3) in three dtypes:
      uint32 (passed in place), int32 (Open3D's triangles) and int64
      (numpy's default), the last two converted by the binding, in every
      call, after a range check. Returns a new (n, 3) float64 array (or, in
      one column, writes into a float32 array allocated once: out=). The
      binding passes each Python thread's workspace, kept from call to
      call, and no vn_stats (vn.vertex_normals has no use for them).
  vnbench MESH.ply -m METHOD -j T -r K --float64: the same mesh
      (binary PLY with double positions, written here), timed in C around
      vn_triangle_normals: float64 positions, one workspace reused by every
      call, as the binding does; no vn_stats; float32
      normals written into one buffer reused by all calls. "overhead" is
      vn.vertex_normals's time over vnbench's, less 1.
  The C call from ctypes: vn_triangle_normals called through ctypes with
      arguments built once (the binding's structs), exactly as vnbench calls
      it (float32 output reused), without and with vn_stats: it separates
      the cost of the ctypes call and of the statistics pass from the rest.
      Page faults per call show the binding's temporary arrays being mapped
      afresh; a last table repeats the binding's calls with glibc told to
      keep freed memory (mallopt), which removes them.
  Open3D: TriangleMesh.compute_vertex_normals() (area-weighted: vn's MWAAT)
      plus np.asarray(mesh.vertex_normals) (a view, no copy), on a
      TriangleMesh built once outside the timing; its vertex normals are
      cleared (outside the timing) before every call, so that every call
      allocates its result as vn.vertex_normals does (ComputeVertexNormals
      otherwise adds onto the normals already there). Also timed with
      the construction inside: Vector3dVector(positions),
      Vector3iVector(faces), TriangleMesh(...).
  numpy: face normals (cross products, area-weighted like MWAAT) summed onto
      their vertices with np.add.at, then normalized; the same with
      np.bincount instead of np.add.at.

"CPU/wall" is the process's CPU time over wall time across the timed calls:
about 1 for code running on one core, about 2 on both. The angles are the
largest at any vertex between a result and vn's MWAAT, in degrees, from
atan2(|a x b|, a . b) (exact down to rounding, where acos stops near 1e-6).
"""
import argparse
import csv
import ctypes
import os
import platform
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
METHODS = ["mwe", "mwaat", "mwa"]
ROUNDS = 3


def torus(triangles, seed=12345):
    """(positions float64 (V, 3), faces int64 (F, 3)): the jittered torus of
    genmesh.py (R = 1, r = 0.4, nu x nv cells, V = F / 2), in numpy."""
    big, small = 1.0, 0.4
    quads = max(triangles // 2, 12)
    nv = max(3, int(round(np.sqrt(quads * small / big))))
    nu = max(3, int(round(quads / nv)))
    rng = np.random.default_rng(seed)
    du, dv = 2 * np.pi / nu, 2 * np.pi / nv
    i, j = np.arange(nu)[:, None], np.arange(nv)[None, :]
    u = (i + 0.6 * (rng.random((nu, nv)) - 0.5)) * du
    v = (j + 0.6 * (rng.random((nu, nv)) - 0.5)) * dv
    rr = small + 0.05 * small * dv * (2 * rng.random((nu, nv)) - 1)
    ring = big + rr * np.cos(v)
    positions = np.stack([ring * np.cos(u), ring * np.sin(u), rr * np.sin(v)], axis=-1).reshape(-1, 3)
    i1, j1 = (i + 1) % nu, (j + 1) % nv
    a, b, c, d = (np.broadcast_to(x, (nu, nv)).ravel() for x in (i * nv + j, i1 * nv + j, i1 * nv + j1, i * nv + j1))
    ac = (rng.random(a.size) < 0.5)[:, None]  # diagonal a-c, else b-d
    first = np.where(ac, np.stack([a, b, c], 1), np.stack([a, b, d], 1))
    second = np.where(ac, np.stack([a, c, d], 1), np.stack([b, c, d], 1))
    return positions, np.stack([first, second], 1).reshape(-1, 3).astype(np.int64)


def write_ply(path, positions, faces):
    """Binary little-endian PLY: double x y z, uint32 corner lists."""
    header = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty double x\nproperty double y\n"
              "property double z\nelement face %d\nproperty list uchar uint vertex_indices\nend_header\n"
              % (len(positions), len(faces)))
    rows = np.empty(len(faces), dtype=[("n", "u1"), ("i", "<u4", 3)])
    rows["n"], rows["i"] = 3, faces
    with open(path, "wb") as f:
        f.write(header.encode())
        f.write(np.ascontiguousarray(positions, dtype="<f8").tobytes())
        f.write(rows.tobytes())


def timed(cases, repeat, rounds=ROUNDS):
    """{name: (median seconds, CPU/wall, page faults per call)} of cases
    [(name, call, before)]: in each of `rounds` rounds, every case in turn
    makes one warm-up call and `repeat` timed calls (a load on the machine
    then hits every case alike, while each case's calls follow each other,
    as in a loop over one function); before (or None) runs ahead of each
    call, outside the timing."""
    times = {name: [] for name, _, _ in cases}
    cpu = dict.fromkeys(times, 0.0)
    faults = dict.fromkeys(times, 0)
    for _ in range(rounds):
        for name, call, before in cases:
            for k in range(repeat + 1):
                if before:
                    before()
                f0 = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
                c0, t0 = time.process_time(), time.perf_counter()
                call()
                t = time.perf_counter() - t0
                c = time.process_time() - c0
                if k:  # k == 0 warms up
                    times[name].append(t)
                    cpu[name] += c
                    faults[name] += resource.getrusage(resource.RUSAGE_SELF).ru_minflt - f0
    return {name: (statistics.median(t), cpu[name] / sum(t), faults[name] / len(t)) for name, t in times.items()}


def vnbench(build, mesh, method, threads, repeat, triangles):
    """vnbench's median in seconds (float64 positions, one workspace)."""
    cmd = [os.path.join(build, "vnbench"), mesh, "-m", method, "-j", str(threads), "-r", str(ROUNDS * repeat),
           "--float64", "--csv"]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.splitlines()
    row = dict(zip(out[0].split(","), out[1].split(",")))
    if int(row["triangles"]) != triangles:
        sys.exit("vnbench read %s triangles from %s, not %d" % (row["triangles"], mesh, triangles))
    return float(row["median_ns_per_tri"]) * 1e-9 * triangles


def c_call(vn, p, faces, out):
    """A function of (method, threads, stats) giving a call of
    vn_triangle_normals straight through ctypes, as vnbench makes it: the
    structs of vn's binding, built once; no Python work per call but the
    ctypes call; one workspace; vn_stats passed or not."""
    from vn import _binding
    lib = vn.library()
    pos = _binding._Positions(p.ctypes.data, len(p), 0, 1)  # float64, packed
    vec = _binding._Vectors(out.ctypes.data, 0, 0)  # float32, packed
    stats = _binding._Stats()

    def make(method, threads, with_stats):
        opt = _binding._Options()
        opt.threads = threads
        lib._workspace(len(p), opt)
        args = (ctypes.byref(vec), ctypes.byref(pos), faces.ctypes.data, faces.size, lib.method_index(method),
                ctypes.byref(opt), ctypes.byref(stats) if with_stats else None)

        def call():
            if lib._lib.vn_triangle_normals(*args):
                sys.exit("vn_triangle_normals failed")
        return call
    return make


def max_angle(a, b):
    """Largest angle between the rows of a and b, in degrees."""
    return float(np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.einsum("ij,ij->i", a, b))).max())


def numpy_add_at(p, f):
    fn = np.cross(p[f[:, 1]] - p[f[:, 0]], p[f[:, 2]] - p[f[:, 0]])
    n = np.zeros_like(p)
    for k in range(3):
        np.add.at(n, f[:, k], fn)
    length = np.linalg.norm(n, axis=1, keepdims=True)
    return np.divide(n, length, out=np.zeros_like(n), where=length > 0)


def numpy_bincount(p, f):
    fn = np.cross(p[f[:, 1]] - p[f[:, 0]], p[f[:, 2]] - p[f[:, 0]])
    idx, w = f.ravel(), np.repeat(fn, 3, axis=0)
    n = np.stack([np.bincount(idx, w[:, c], minlength=len(p)) for c in range(3)], axis=1)
    length = np.linalg.norm(n, axis=1, keepdims=True)
    return np.divide(n, length, out=np.zeros_like(n), where=length > 0)


def machine(vn, o3d):
    cpu = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    try:
        commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True).stdout.strip()
    except OSError:
        commit = ""
    return ("%s, %d cores, %s %s, Python %s, numpy %s, Open3D %s, vn %s (%s, commit %s), load average %.2f, %s"
            % (cpu, os.cpu_count(), platform.system(), platform.release(), platform.python_version(), np.__version__,
               o3d.__version__, vn.__version__, vn.library().path, commit or "?", os.getloadavg()[0],
               time.strftime("%Y-%m-%d %H:%M")))


def raise_malloc_thresholds():
    """Keeps freed memory in glibc's heap (mallopt M_TRIM_THRESHOLD and
    M_MMAP_THRESHOLD at 32 MB), so that a call's temporary arrays reuse the
    pages of the previous call's instead of faulting in fresh ones."""
    libc = ctypes.CDLL(None)
    if libc.mallopt(-1, 1 << 25) != 1 or libc.mallopt(-3, 1 << 25) != 1:
        sys.exit("mallopt failed")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--triangles", type=float, default=1e6)
    ap.add_argument("--repeat", type=int, default=5, help="timed calls after one warm-up, per round (3 rounds)")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"), help="folder with libvn.so and vnbench")
    ap.add_argument("--csv", help="also write the measurements as CSV to this file")
    ap.add_argument("--work", help="folder for the PLY vnbench reads (default: a temporary one)")
    args = ap.parse_args()
    build = os.path.abspath(args.build)
    os.environ["VN_LIBRARY"] = os.path.join(build, "libvn.so")
    sys.path.insert(0, os.path.join(ROOT, "python"))
    import vn
    import open3d as o3d

    p, f64 = torus(int(args.triangles))
    faces = {"uint32": f64.astype(np.uint32), "int32": f64.astype(np.int32), "int64": f64}
    nt, K, cores = len(f64), args.repeat, os.cpu_count() or 1
    configs = [(m, t) for m in METHODS for t in sorted({1, cores})]
    rows = []  # CSV: what, method, threads, seconds, CPU/wall, page faults per call

    def measure(method, threads, cases):
        """timed(cases), each also a CSV row."""
        res = timed(cases, K)
        rows.extend((name, method, threads) + res[name] for name, _, _ in cases)
        return res

    print("machine: " + machine(vn, o3d))
    print("mesh: jittered torus, %d vertices, %d triangles; ms, median of %d calls: the cases of a table row "
          "take turns, %d calls each after 1 warm-up, %d times (vnbench: %d calls after 1 warm-up)"
          % (len(p), nt, ROUNDS * K, K, ROUNDS, ROUNDS * K))
    work = args.work or tempfile.mkdtemp(prefix="vn-pyspeed-")
    os.makedirs(work, exist_ok=True)
    ply = os.path.join(work, "torus_%d.ply" % nt)
    write_ply(ply, p, faces["uint32"])

    # The binding against vnbench and the bare C call, per face dtype.
    out32, base, reference = np.empty(p.shape, np.float32), {}, {}
    direct = c_call(vn, p, faces["uint32"], out32)
    dtypes = ("uint32", "int32", "int64")

    def binding(method, threads):
        return [("vn.vertex_normals, %s faces" % d,
                 lambda d=d: vn.vertex_normals(p, faces[d], method, threads=threads), None) for d in dtypes]

    def overheads(res, names, over):
        return " / ".join("%+.0f%%" % (100 * (res[n][0] / over - 1)) for n in names)

    print("\nOverhead: vn.vertex_normals's time over the other's, less 1, for uint32 / int32 / int64 faces.\n")
    print("| method | threads | vnbench --float64 | C call from ctypes | C call, vn_stats "
          "| vn, uint32 faces, float32 out= | vn, uint32 faces | vn, int32 faces | vn, int64 faces "
          "| overhead over vnbench | overhead over the C call | page faults per call |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    try:
        for method, threads in configs:
            t = base[method, threads] = vnbench(build, ply, method, threads, K, nt)
            rows.append(("vnbench --float64", method, threads, t, float("nan"), float("nan")))
            cases = [("C call from ctypes", direct(method, threads, False), None),
                     ("C call from ctypes, vn_stats", direct(method, threads, True), None),
                     ("vn.vertex_normals, uint32 faces, float32 out=",
                      lambda: vn.vertex_normals(p, faces["uint32"], method, threads=threads, out=out32), None)]
            cases += binding(method, threads)
            res = measure(method, threads, cases)
            names = [c[0] for c in cases]
            print("| %s | %d | %.2f | %s | %s | %s | %s |" % (
                method.upper(), threads, 1e3 * t, " | ".join("%.2f" % (1e3 * res[n][0]) for n in names),
                overheads(res, names[3:], t), overheads(res, names[3:], res[names[0]][0]),
                " / ".join("%.0f" % res[n][2] for n in names[3:])))
            result = vn.vertex_normals(p, f64, method, threads=threads)
            if not np.array_equal(reference.setdefault(method, result), result):
                sys.exit("%s: vn's results differ between thread counts" % method)
    finally:  # the PLY is needed no more
        if not args.work:
            shutil.rmtree(work)

    # MWAAT against Open3D and numpy.
    mwaat = reference["mwaat"]
    mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(p), o3d.utility.Vector3iVector(faces["int32"]))

    def clear():
        mesh.vertex_normals = o3d.utility.Vector3dVector()

    def open3d_normals():
        mesh.compute_vertex_normals()
        return np.asarray(mesh.vertex_normals)

    def open3d_built(f):
        m = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(p), o3d.utility.Vector3iVector(f))
        m.compute_vertex_normals()
        return np.asarray(m.vertex_normals)

    plan = vn.Plan(faces["uint32"], len(p), threads=1)  # issue 20: a per-frame plan, made once
    p32 = p.astype(np.float32)
    cases = [
        ("vn.vertex_normals(p, faces, 'mwaat', threads=1), uint32 faces", 1,
         lambda: vn.vertex_normals(p, faces["uint32"], "mwaat", threads=1), None),
        ("vn.vertex_normals(p, faces, 'mwaat', threads=1), int32 faces", 1,
         lambda: vn.vertex_normals(p, faces["int32"], "mwaat", threads=1), None),
        ("vn.vertex_normals(p, faces, 'mwaat', threads=1), int64 faces", 1,
         lambda: vn.vertex_normals(p, f64, "mwaat", threads=1), None),
        ("vn.vertex_normals(p, faces, 'mwaat'), %d threads, uint32 faces" % cores, cores,
         lambda: vn.vertex_normals(p, faces["uint32"], "mwaat"), None),
        ("vn.Plan(faces, threads=1).normals(p32, 'mwaat'), float32 positions", 1,
         lambda: plan.normals(p32, "mwaat"), None),
        ("vn.Plan(faces, threads=1).normals(p, 'mwaat'), float64 positions", 1, lambda: plan.normals(p, "mwaat"), None),
        ("Open3D compute_vertex_normals() + np.asarray, mesh built outside the timing", 1, open3d_normals, clear),
        ("Open3D, mesh built inside the timing from float64 + int32 arrays", 1,
         lambda: open3d_built(faces["int32"]), None),
        ("Open3D, mesh built inside the timing from float64 + int64 arrays", 1, lambda: open3d_built(f64), None),
        ("numpy, np.add.at", 1, lambda: numpy_add_at(p, f64), None),
        ("numpy, np.bincount", 1, lambda: numpy_bincount(p, f64), None),
    ]
    res = measure("mwaat", 1, [(what, call, before) for what, _, call, before in cases])
    first = res[cases[0][0]][0]
    print("\n| MWAAT (area-weighted), numpy arrays to a numpy result | threads | ms | CPU/wall | time / vn 1 thread "
          "(uint32 faces) | max angle to vn MWAAT (°) |")
    print("|---|---:|---:|---:|---:|---:|")
    for what, threads, call, before in cases:
        if before:
            before()
        angle = max_angle(call(), mwaat)  # a result of its own, outside the timing
        t, ratio, _ = res[what]
        print("| %s | %d | %.2f | %.2f | %.2f | %.1e |" % (what, threads, 1e3 * t, ratio, t / first, angle))

    # The binding again, with freed memory kept in the heap (last: it changes the process's malloc).
    raise_malloc_thresholds()
    print("\nThe same calls with glibc's trim and mmap thresholds raised to 32 MB (mallopt), so that freed "
          "memory stays in the heap:\n")
    print("| method | threads | C call from ctypes | vn, uint32 faces | vn, int32 faces | vn, int64 faces "
          "| overhead over vnbench | overhead over the C call | page faults per call |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for method, threads in configs:
        cases = [("C call from ctypes, mallopt", direct(method, threads, False), None)]
        cases += [(name + ", mallopt", call, None) for name, call, _ in binding(method, threads)]
        res = measure(method, threads, cases)
        names = [c[0] for c in cases]
        print("| %s | %d | %s | %s | %s | %s |" % (
            method.upper(), threads, " | ".join("%.2f" % (1e3 * res[n][0]) for n in names),
            overheads(res, names[1:], base[method, threads]), overheads(res, names[1:], res[names[0]][0]),
            " / ".join("%.0f" % res[n][2] for n in names[1:])))

    if args.csv:
        with open(args.csv, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["what", "method", "threads", "median_ms", "cpu_per_wall", "page_faults_per_call", "triangles",
                        "repeat"])
            for what, method, threads, t, ratio, faults in rows:
                w.writerow([what, method, threads, "%.4f" % (1e3 * t), "%.3f" % ratio, "%.0f" % faults, nt, K])


if __name__ == "__main__":
    main()
