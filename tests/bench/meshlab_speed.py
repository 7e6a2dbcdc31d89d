#!/usr/bin/env python3
"""Per-call time of the MeshLab filter plugin against MeshLab's own vertex normals (issue 16).
  meshlab_speed.py [LABEL=]PLUGIN ... [--runs 5] [--calls 200] [--big-calls 200] [--mesh PLY ...] [--no-big] [--work DIR]
PLUGIN is a built libfilter_vn.so (build/libfilter_vn.so); with several (e.g.
before=old.so after=build/libfilter_vn.so) each gets its own staged server and
its own rows, and all scripts run round-robin.

Stages a private meshlabserver with every system plugin plus PLUGIN, as
tests/meshlab/test_meshlab.py does, and starts one Xvfb for all runs. For each
mesh it writes .mlx scripts that apply one filter CALLS times, and a script of
zero calls (load + save only); each script runs RUNS times, round-robin, and the
per-call time is (median t_CALLS - median t_0) / CALLS, in ms.

Filters: "Re-Compute Vertex Normals (all published weightings)" with each of vn's seven methods (the
defaults otherwise: no weld, all vertices, face normals recomputed), and
MeshLab 2020.09's "Re-Compute Vertex Normals" (filter_unsharp, param
weightMode) with each of its four modes.

Meshes: the Stanford bunny (../shared/data/ply/bun_zipper.ply, 35,947 vertices,
69,451 triangles), and unless --no-big the bunny subdivided twice 1-to-4 at edge
midpoints (555,684 vertices, 1,111,216 triangles), written as binary PLY into
the work directory. Prints a Markdown table.
"""
import argparse
import shutil
import os
import statistics
import struct
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "meshlab"))
import test_meshlab  # noqa: E402  (stage(), read_ply())

BUNNY = os.path.normpath(os.path.join(HERE, "..", "..", "..", "shared", "data", "ply", "bun_zipper.ply"))
if not os.path.exists(BUNNY):
    BUNNY = "/work/shared/data/ply/bun_zipper.ply"
VN_FILTER = "Re-Compute Vertex Normals (all published weightings)"
VN_METHODS = ["MWE", "MWA", "MWSELR", "MWAAT", "MWELR", "MWRELR", "MEWCSA"]
ML_FILTER = "Re-Compute Vertex Normals"
ML_MODES = ["Simple Average", "By Angle", "By Area", "As defined by N. Max"]


def vn_call(method):
    enum = " ".join('enum_val%d="%s"' % (i, n) for i, n in enumerate(VN_METHODS))
    return (' <filter name="%s">\n'
            '  <Param type="RichEnum" value="%d" name="method" enum_cardinality="7" %s/>\n'
            '  <Param type="RichBool" value="false" name="weldByPosition"/>\n'
            '  <Param type="RichBool" value="false" name="onlySelected"/>\n'
            '  <Param type="RichBool" value="true" name="faceNormals"/>\n'
            ' </filter>\n' % (VN_FILTER, VN_METHODS.index(method), enum))


def ml_call(mode):
    enum = " ".join('enum_val%d="%s"' % (i, n) for i, n in enumerate(ML_MODES))
    return (' <filter name="%s">\n'
            '  <Param type="RichEnum" value="%d" name="weightMode" enum_cardinality="4" %s/>\n'
            ' </filter>\n' % (ML_FILTER, ML_MODES.index(mode), enum))


def write_mlx(path, call, n):
    with open(path, "w") as f:
        f.write("<!DOCTYPE FilterScript>\n<FilterScript>\n" + call * n + "</FilterScript>\n")


def read_mesh(path):
    """(positions, triangles) of a PLY (test_meshlab.read_ply: polygons as fans)."""
    pos, _, tris = test_meshlab.read_ply(path)
    return pos, tris


def subdivide(pos, tris):
    """1-to-4 split at edge midpoints (new vertices shared between the two faces of an edge)."""
    pos = list(pos)
    mid = {}

    def m(a, b):
        key = (a, b) if a < b else (b, a)
        i = mid.get(key)
        if i is None:
            pa, pb = pos[a], pos[b]
            i = mid[key] = len(pos)
            pos.append(((pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2, (pa[2] + pb[2]) / 2))
        return i

    out = []
    for a, b, c in tris:
        ab, bc, ca = m(a, b), m(b, c), m(c, a)
        out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    return pos, out


def write_ply(path, pos, tris):
    with open(path, "wb") as f:
        f.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\n"
                 "property float y\nproperty float z\nelement face %d\n"
                 "property list uchar int vertex_indices\nend_header\n" % (len(pos), len(tris))).encode())
        f.write(b"".join(struct.pack("<3f", *p) for p in pos))
        f.write(b"".join(struct.pack("<B3i", 3, *t) for t in tris))


def start_xvfb(size="640x480x24"):
    """An Xvfb of its own (screen WxHxDEPTH) on the first free display from :150 (away from
    xvfb-run's :99 up and from :0, which other tools on the machine may take and drop)."""
    n = 150
    while os.path.exists("/tmp/.X%d-lock" % n) or os.path.exists("/tmp/.X11-unix/X%d" % n):
        n += 1
    p = subprocess.Popen(["Xvfb", ":%d" % n, "-screen", "0", size, "-nolisten", "tcp"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    for _ in range(100):
        if os.path.exists("/tmp/.X11-unix/X%d" % n):
            break
        time.sleep(0.05)
    return p, ":%d" % n


def timed(server, mesh, script, out, env):
    t = time.perf_counter()
    p = subprocess.run([server, "-i", mesh, "-o", out, "-m", "vn", "-s", script], env=env,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    t = time.perf_counter() - t
    if p.returncode != 0 or not os.path.exists(out):
        sys.exit("meshlabserver failed on %s:\n%s" % (script, p.stdout.decode("utf-8", "replace")[-2000:]))
    os.remove(out)
    return t


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("plugins", nargs="+")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--calls", type=int, default=200)
    ap.add_argument("--big-calls", type=int, default=None, help="calls per script on the 1M mesh (default --calls)")
    ap.add_argument("--mesh", action="append", help="PLY meshes (default: the bunny)")
    ap.add_argument("--no-big", action="store_true")
    ap.add_argument("--only", help="comma-separated subset of column names, e.g. MWE,Simple Average")
    ap.add_argument("--work")
    a = ap.parse_args()
    work = a.work or tempfile.mkdtemp(prefix="vn-meshlab-speed-")
    os.makedirs(work, exist_ok=True)
    servers = []
    for i, arg in enumerate(a.plugins):
        label, path = arg.split("=", 1) if "=" in arg else ("", arg)
        root = os.path.join(work, "server%d" % i)
        if os.path.exists(root):
            shutil.rmtree(root)
        servers.append((label, test_meshlab.stage(root, os.path.abspath(path))))
    server = servers[0][1]

    meshes = [(m, a.calls) for m in (a.mesh or [BUNNY])]
    if not a.no_big:
        big = os.path.join(work, "bunny_sub2.ply")
        if not os.path.exists(big):
            pos, tris = read_mesh(BUNNY)
            for _ in range(2):
                pos, tris = subdivide(pos, tris)
            write_ply(big, pos, tris)
        meshes.append((big, a.big_calls or a.calls))

    keep = a.only.split(",") if a.only else None
    cols = []  # (row label, filter call, server)
    for label, srv in servers:
        cols += [("vn %s%s" % (m, " (%s)" % label if label else ""), vn_call(m), srv)
                 for m in VN_METHODS if not keep or m in keep]
    cols += [("MeshLab " + m, ml_call(m), server) for m in ML_MODES if not keep or m in keep]
    xvfb, display = start_xvfb()
    env = dict(os.environ, DISPLAY=display)
    results = {}
    try:
        for mesh, calls in meshes:
            name = os.path.basename(mesh)
            zero = os.path.join(work, "zero.mlx")
            write_mlx(zero, "", 0)
            scripts = [("load+save", zero, server)]
            for label, call, srv in cols:
                s = os.path.join(work, "%s.mlx" % "".join(c if c.isalnum() else "_" for c in label))
                write_mlx(s, call, calls)
                scripts.append((label, s, srv))
            out = os.path.join(work, "out.ply")
            times = {label: [] for label, _, _ in scripts}
            timed(server, mesh, zero, out, env)  # warm the page cache
            for run in range(a.runs):
                for label, s, srv in scripts:
                    times[label].append(timed(srv, mesh, s, out, env))
                print("# %s: run %d of %d done" % (name, run + 1, a.runs), file=sys.stderr, flush=True)
            t0 = statistics.median(times["load+save"])
            results[name] = (calls, t0, {label: (statistics.median(times[label]) - t0) / calls * 1000
                                         for label, _, _ in scripts[1:]})
            print("# %s: load+save %.0f ms; " % (name, t0 * 1000) +
                  ", ".join("%s %.2f" % (k, v) for k, v in results[name][2].items()), file=sys.stderr, flush=True)
    finally:
        xvfb.terminate()
        xvfb.wait()

    print("| ms per call | " + " | ".join("%s (%d calls; load+save %.0f ms)" % (n, r[0], r[1] * 1000)
                                         for n, r in results.items()) + " |")
    print("|---|" + "---|" * len(results))
    for label, _, _ in cols:
        print("| %s | " % label + " | ".join("%.2f" % r[2][label] for r in results.values()) + " |")


if __name__ == "__main__":
    main()
