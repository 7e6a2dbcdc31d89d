#!/usr/bin/env python3
"""The MeshLab filter plugin against the real MeshLab (Debian's meshlabserver).

    test_meshlab.py PLUGIN VNCONVERT SOURCE_DIR

Stages a private copy of meshlabserver whose ../lib/<arch>/meshlab/ holds
libmeshlab-common.so and every system plugin (plus ours, in the second copy),
runs it under xvfb-run -a, and checks:
  - the count of filtering actions meshlabserver prints grows by exactly one;
  - every method, applied from an .mlx script to OFF and PLY samples and saved
    as PLY with -m vn, agrees with vnconvert's normals of the same mesh (the
    positions and triangles MeshLab holds, read back from that PLY) and, for
    triangle OFF files, with vnconvert on the file itself, within MAX_ANGLE
    degrees, on meshes where the methods differ far more than that;
  - weld by position, only selected vertices, degenerate faces and an isolated
    vertex (zero normal, never NaN);
  - a bad method value: MeshLab's error, a non-zero exit, no crash, no output.
Prints the largest angle per method and mesh. Exit status 0 when all pass.
"""
import gzip
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile

MAX_ANGLE = 0.05  # degrees: MeshLab holds float positions and float normals
# The paper's seven, first in the filter's enum (scripts store the index); the
# schemes beyond the paper follow (METHODS: all, as vnconvert --list-methods
# gives them, set by main).
PAPER = ["mwe", "mwa", "mwselr", "mwaat", "mwelr", "mwrelr", "mewcsa"]
METHODS = list(PAPER)
METHOD_GAP = 0.5  # degrees (10x MAX_ANGLE): on the comparison meshes every two methods differ by more
ARCH_LIB = "lib/x86_64-linux-gnu"
SYSTEM_MESHLAB_LIB = "/usr/" + ARCH_LIB + "/meshlab"
# VN_MESHLAB_FILTER: another name, to run these tests against an older plugin
FILTER = os.environ.get("VN_MESHLAB_FILTER", "Re-Compute Vertex Normals (all published weightings)")

failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)
    return cond


def stage(root, plugin):
    """A private meshlabserver: root/bin/meshlabserver, root/lib/<arch>/meshlab/."""
    lib = os.path.join(root, ARCH_LIB, "meshlab")
    os.makedirs(os.path.join(lib, "plugins"))
    os.makedirs(os.path.join(root, "bin"))
    shutil.copy2(shutil.which("meshlabserver") or "/usr/bin/meshlabserver", os.path.join(root, "bin"))
    shutil.copy2(os.path.join(SYSTEM_MESHLAB_LIB, "libmeshlab-common.so"), lib)
    for f in sorted(os.listdir(os.path.join(SYSTEM_MESHLAB_LIB, "plugins"))):
        if f.endswith(".so") and f != "libfilter_vn.so":  # not one installed earlier
            shutil.copy2(os.path.join(SYSTEM_MESHLAB_LIB, "plugins", f), os.path.join(lib, "plugins"))
    if plugin:
        shutil.copy2(plugin, os.path.join(lib, "plugins"))
    return os.path.join(root, "bin", "meshlabserver")


def run_server(server, args, cwd):
    p = subprocess.run(["xvfb-run", "-a", server] + args, cwd=cwd, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, timeout=600)
    return p.returncode, p.stdout.decode("utf-8", "replace")


def filter_run(server, tmp, src, out, script):
    """meshlabserver applying script to src and writing out with vertex normals:
    (exit status, output)."""
    return run_server(server, ["-i", src, "-o", out, "-m", "vn", "-s", script], tmp)


def filtered(server, tmp, src, name, what, method, **kw):
    """The filter, as mlx(method, **kw) writes its script, on src into tmp/NAME.ply:
    (positions, normals, triangles, log), or None after a failed check "WHAT: exit N"."""
    script, out = os.path.join(tmp, name + ".mlx"), os.path.join(tmp, name + ".ply")
    mlx(script, method, **kw)
    if os.path.exists(out):
        os.remove(out)
    rc, log = filter_run(server, tmp, src, out, script)
    if not check(rc == 0 and os.path.exists(out), "%s: exit %d" % (what, rc)):
        print(log[-2000:])
        return None
    return read_ply(out) + (log,)


def filtering_actions(out):
    for line in out.splitlines():
        if line.startswith("Total ") and line.endswith(" filtering actions"):
            return int(line.split()[1])
    return None


def mlx(path, method, weld=False, selected=False, face_normals=True, select_condition=None, raw_method=None,
        face_condition=None, delete_selected=False, omit=None):
    """An .mlx script as MeshLab saves one (enum_cardinality and enum_val* included:
    MeshLab 2020.09 silently drops a RichEnum without them). delete_selected: MeshLab's
    Delete Selected Vertices after the selection (it marks vertices and faces deleted
    and leaves them in the mesh's arrays). omit: a parameter name left out of the
    script (as a script written by hand may)."""
    names = [m.upper() for m in METHODS]
    enum = " ".join('enum_val%d="%s"' % (i, n) for i, n in enumerate(names))
    value = raw_method if raw_method is not None else str(method)
    b = lambda x: "true" if x else "false"
    pre = ""
    if select_condition:
        pre = (' <filter name="Conditional Vertex Selection">\n'
               '  <Param type="RichString" value="%s" name="condSelect"/>\n'
               ' </filter>\n' % select_condition)
    if face_condition:
        pre += (' <filter name="Conditional Face Selection">\n'
                '  <Param type="RichString" value="%s" name="condSelect"/>\n'
                ' </filter>\n' % face_condition)
    if delete_selected:
        pre += ' <filter name="Delete Selected Vertices"/>\n'
    text = ('<!DOCTYPE FilterScript>\n<FilterScript>\n%s'
            ' <filter name="%s">\n'
            '  <Param type="RichEnum" value="%s" name="method" enum_cardinality="%d" %s/>\n'
            '  <Param type="RichBool" value="%s" name="weldByPosition"/>\n'
            '  <Param type="RichBool" value="%s" name="onlySelected"/>\n'
            '  <Param type="RichBool" value="%s" name="faceNormals"/>\n'
            ' </filter>\n</FilterScript>\n'
            % (pre, FILTER, value, len(names), enum, b(weld), b(selected), b(face_normals)))
    if omit:
        text = "".join(l for l in text.splitlines(True) if 'name="%s"' % omit not in l)
    with open(path, "w") as f:
        f.write(text)


PLY_TYPES = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h",
             "ushort": "H", "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I",
             "float": "f", "float32": "f", "double": "d", "float64": "d"}


def read_ply(path):
    """Binary little-endian or ASCII PLY: (positions, normals or None, triangles)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header") + len(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode("ascii").splitlines()
    fmt = None
    elements = []
    for line in header:
        w = line.split()
        if not w:
            continue
        if w[0] == "format":
            fmt = w[1]
        elif w[0] == "element":
            elements.append((w[1], int(w[2]), []))
        elif w[0] == "property":
            if w[1] == "list":
                elements[-1][2].append((w[4], "list", PLY_TYPES[w[2]], PLY_TYPES[w[3]]))
            else:
                elements[-1][2].append((w[2], PLY_TYPES[w[1]]))
    verts, faces = [], []
    if fmt == "ascii":
        tokens = data[end:].split()
        pos = 0
        for name, count, props in elements:
            for _ in range(count):
                rec = {}
                for p in props:
                    if p[1] == "list":
                        n = int(tokens[pos]); pos += 1
                        rec[p[0]] = [int(t) for t in tokens[pos:pos + n]]; pos += n
                    else:
                        rec[p[0]] = float(tokens[pos]); pos += 1
                (verts if name == "vertex" else faces if name == "face" else []).append(rec)
    else:
        assert fmt == "binary_little_endian", fmt
        off = end
        for name, count, props in elements:
            simple = all(p[1] != "list" for p in props)
            if simple:
                st = struct.Struct("<" + "".join(p[1] for p in props))
                names = [p[0] for p in props]
                for i in range(count):
                    rec = dict(zip(names, st.unpack_from(data, off)))
                    off += st.size
                    (verts if name == "vertex" else []).append(rec)
            else:
                for i in range(count):
                    rec = {}
                    for p in props:
                        if p[1] == "list":
                            (n,) = struct.unpack_from("<" + p[2], data, off)
                            off += struct.calcsize(p[2])
                            rec[p[0]] = list(struct.unpack_from("<%d%s" % (n, p[3]), data, off))
                            off += n * struct.calcsize(p[3])
                        else:
                            (rec[p[0]],) = struct.unpack_from("<" + p[1], data, off)
                            off += struct.calcsize(p[1])
                    (faces if name == "face" else []).append(rec)
    positions = [(v["x"], v["y"], v["z"]) for v in verts]
    normals = [(v["nx"], v["ny"], v["nz"]) for v in verts] if verts and "nx" in verts[0] else None
    key = "vertex_indices" if faces and "vertex_indices" in faces[0] else "vertex_index"
    tris = []
    for fc in faces:
        idx = fc[key]
        for k in range(1, len(idx) - 1):
            tris.append((idx[0], idx[k], idx[k + 1]))
    return positions, normals, tris


def write_off(path, positions, tris, normals=None):
    with open(path, "w") as f:
        f.write("NOFF\n" if normals else "OFF\n")
        f.write("%d %d 0\n" % (len(positions), len(tris)))
        for i, p in enumerate(positions):
            # repr: the shortest text that reads back as the same double
            f.write("%r %r %r" % tuple(float(c) for c in p))
            if normals:
                f.write(" %r %r %r" % tuple(float(c) for c in normals[i]))
            f.write("\n")
        for t in tris:
            f.write("3 %d %d %d\n" % t)


def read_off_normals(path):
    with open(path) as f:
        lines = [l for l in f if l.strip() and not l.startswith("#")]
    assert lines[0].strip() == "NOFF", lines[0]
    nv = int(lines[1].split()[0])
    return [tuple(float(x) for x in lines[2 + i].split()[3:6]) for i in range(nv)]


def angle(a, b):
    """Degrees between a and b; 0 when both are zero, 180 when only one is."""
    na = math.sqrt(sum(x * x for x in a))
    nb = math.sqrt(sum(x * x for x in b))
    if na == 0 or nb == 0:
        return 0.0 if na == nb else 180.0
    c = sum(x * y for x, y in zip(a, b)) / (na * nb)
    s = math.sqrt(sum(x * x for x in (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                       a[0] * b[1] - a[1] * b[0]))) / (na * nb)
    return math.degrees(math.atan2(s, c))


def max_angle(ns, ms, only=None):
    idx = range(len(ns)) if only is None else only
    return max((angle(ns[i], ms[i]) for i in idx), default=0.0)


def vn_reference(vnconvert, tmp, name, positions, tris, method):
    src = os.path.join(tmp, name + ".ref-in.off")
    if not os.path.exists(src):
        write_off(src, positions, tris)
    dst = os.path.join(tmp, "%s.ref-%s.off" % (name, method))
    subprocess.run([vnconvert, src, dst, "--method", method, "-q", "--no-weld"], check=True)
    return read_off_normals(dst)


def main():
    plugin, vnconvert, source = (os.path.abspath(a) for a in sys.argv[1:4])
    methods = subprocess.run([vnconvert, "--list-methods"], check=True, stdout=subprocess.PIPE,
                             universal_newlines=True).stdout.split("\n")
    methods = [l.split()[0] for l in methods if l.strip()]
    check(methods[:7] == PAPER, "vnconvert --list-methods lists the paper's seven first: %s" % " ".join(methods))
    METHODS[:] = methods
    tmp = tempfile.mkdtemp(prefix="vn-meshlab-")
    try:
        plain = stage(os.path.join(tmp, "plain"), None)
        ours = stage(os.path.join(tmp, "ours"), plugin)

        # -- the filter is registered: exactly one more filtering action
        dump = os.path.join(tmp, "filters.txt")
        rc0, out0 = run_server(plain, ["-d", dump + ".plain"], tmp)
        rc1, out1 = run_server(ours, ["-d", dump], tmp)
        n0, n1 = filtering_actions(out0), filtering_actions(out1)
        check(n0 is not None and n1 == n0 + 1,
              "filtering actions: %s without the plugin, %s with it (one more)" % (n0, n1))
        dumped = open(dump, encoding="utf-8", errors="replace").read() if os.path.exists(dump) else ""
        check(FILTER in dumped and "MWSELR" in dumped, "meshlabserver -d lists '%s' with its methods" % FILTER)

        # -- samples: OFF (triangles; quads, which MeshLab triangulates), PLY, and an
        #    irregular OFF made here (a jittered, unevenly subdivided sphere)
        samples = {}
        samples["torus.off"] = os.path.join(source, "samples", "torus.off")
        samples["sphere-quads.off"] = os.path.join(source, "samples", "sphere-quads.off")
        bunny = os.path.join(tmp, "bun_zipper.ply")
        with gzip.open(os.path.join(source, "tests", "meshlab", "data", "bun_zipper.ply.gz")) as g, \
                open(bunny, "wb") as f:
            shutil.copyfileobj(g, f)
        samples["bun_zipper.ply"] = bunny
        samples["lumpy.off"] = os.path.join(tmp, "lumpy.off")
        make_lumpy(samples["lumpy.off"])

        worst = {}
        refs = {}
        for name, path in samples.items():
            per = []
            for i, m in enumerate(methods):
                r = filtered(ours, tmp, path, "%s.%s" % (name, m), "%s %s: meshlabserver" % (name, m), i)
                if not r:
                    continue
                positions, normals, tris, _ = r
                ref = vn_reference(vnconvert, tmp, name, positions, tris, m)
                refs[(name, m)] = ref
                nan = any(not math.isfinite(c) for n in normals for c in n)
                a = max_angle(normals, ref)
                worst[(name, m)] = a
                per.append("%s %.2e" % (m, a))
                check(not nan and a <= MAX_ANGLE,
                      "%s %s: max angle to vnconvert %.2e deg (<= %g), NaN: %s" % (name, m, a, MAX_ANGLE, nan))
                if name in ("torus.off", "lumpy.off"):
                    # triangle OFF files: vnconvert on the file itself (double positions)
                    direct = os.path.join(tmp, "%s.direct-%s.off" % (name, m))
                    subprocess.run([vnconvert, path, direct, "--method", m, "-q", "--no-weld"], check=True)
                    d = max_angle(normals, read_off_normals(direct))
                    check(d <= MAX_ANGLE, "%s %s: max angle to vnconvert on the file itself %.2e deg" % (name, m, d))
            # the paper's methods differ far more than the tolerance on this mesh
            # (those beyond it may equal one another: adaptive is the jet where it fits)
            gaps = [max_angle(refs[(name, a)], refs[(name, b)])
                    for ia, a in enumerate(PAPER) for b in PAPER[ia + 1:]
                    if (name, a) in refs and (name, b) in refs]
            if name != "torus.off":  # a torus of revolution: several methods coincide there
                check(gaps and min(gaps) > METHOD_GAP,
                      "%s: every two methods differ by > %g deg (smallest max angle %.3f)"
                      % (name, METHOD_GAP, min(gaps) if gaps else -1))

        # -- the default method is MWA (a script that omits it)
        # (MeshLab 2020.09 aborts when any other parameter is missing: test_missing_parameter)
        r = filtered(ours, tmp, samples["lumpy.off"], "default", "method omitted", 0, omit="method")
        if r:
            normals = r[1]
            a = max_angle(normals, refs[("lumpy.off", "mwa")])
            check(a <= MAX_ANGLE, "method omitted: MWA (max angle %.5f deg)" % a)

        test_help(dumped)
        test_point_cloud(ours, tmp)
        test_loose_points(ours, vnconvert, tmp, samples["lumpy.off"])
        test_face_selection(ours, vnconvert, tmp, samples["lumpy.off"])
        test_degenerate(ours, vnconvert, tmp, methods)
        test_weld(ours, vnconvert, tmp, methods)
        test_selected(ours, vnconvert, tmp, samples["lumpy.off"])
        test_deleted(ours, vnconvert, tmp, samples["lumpy.off"])
        test_bad_method(ours, tmp, samples["torus.off"])
        test_missing_parameter(ours, tmp, samples["torus.off"])

        print("max angle to vnconvert (deg), per method:")
        for m in methods:
            print("  %-7s %s" % (m, "  ".join("%s %.2e" % (n, worst.get((n, m), float("nan"))) for n in samples)))
    finally:
        if os.environ.get("VN_KEEP_TMP"):
            print("kept", tmp)
        else:
            shutil.rmtree(tmp, ignore_errors=True)
    print("meshlab: %d failed" % len(failures))
    return 1 if failures else 0


def make_lumpy(path):
    """A sphere with lumps, uneven latitude spacing and alternating diagonals:
    triangles of many shapes and sizes, so that the methods disagree."""
    positions, tris = [], []
    rings, seg = 14, 23
    positions.append((0.0, 0.0, 1.0))
    for r in range(1, rings):
        t = math.pi * (r / rings) ** 1.3
        for s in range(seg):
            p = 2 * math.pi * (s + 0.37 * (r % 3)) / seg
            rad = 1 + 0.25 * math.sin(3 * p + 2 * t) * math.sin(2 * t) + 0.1 * math.cos(5 * p)
            positions.append((rad * math.sin(t) * math.cos(p), 1.3 * rad * math.sin(t) * math.sin(p), rad * math.cos(t)))
    positions.append((0.0, 0.0, -1.0))
    last = len(positions) - 1
    ring = lambda r, s: 1 + (r - 1) * seg + s % seg
    for s in range(seg):
        tris.append((0, ring(1, s), ring(1, s + 1)))
        tris.append((last, ring(rings - 1, s + 1), ring(rings - 1, s)))
    for r in range(1, rings - 1):
        for s in range(seg):
            a, b, c, d = ring(r, s), ring(r + 1, s), ring(r + 1, s + 1), ring(r, s + 1)
            if (r + s) % 2:
                tris += [(a, b, c), (a, c, d)]
            else:
                tris += [(a, b, d), (b, c, d)]
    write_off(path, positions, tris)


def read_off_mesh(path):
    with open(path) as f:
        lines = [l.split() for l in f if l.strip()]
    nv, nf = int(lines[1][0]), int(lines[1][1])
    positions = [tuple(float(x) for x in l[:3]) for l in lines[2:2 + nv]]
    tris = [tuple(int(x) for x in l[1:4]) for l in lines[2 + nv:2 + nv + nf]]
    return positions, tris


def near(a, b, tol=1e-6):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return tuple(x / n for x in v)


def test_help(dump):
    """The filter's name sorts next to MeshLab's own; the help (meshlabserver -d
    prints the description and each parameter's help as the dialog shows them):
    no paper notation, MEWCSA not for shading, the parameter help in short
    <br>-separated lines (the dialog's Help mode clips long wrapped help) and
    complete."""
    names = sorted(l[len("\\section "):].split(" ", 1)[1].strip() for l in dump.splitlines()
                   if l.startswith("\\section "))
    if not check(FILTER in names, "meshlabserver -d lists '%s'" % FILTER):
        return
    i = names.index(FILTER)
    check(i > 0 and names[i - 1] == "Re-Compute Vertex Normals",
          "the name sorts (as MeshLab's menus do) right after MeshLab's 'Re-Compute Vertex Normals' (after '%s')"
          % (names[i - 1] if i else None))
    sec = dump[dump.rindex("\\section", 0, dump.index(" " + FILTER + " \n")):]
    sec = sec[:sec.index("</TABLE>")]
    rows = [r for r in sec.split("<TR>")[1:]]
    info = sec.split("<H2>")[0]
    check("|E" not in sec and "sin(" not in sec and "sqrt(" not in sec,
          "help without the paper's notation (|E||E'|, sin(a))")
    check("<b>MEWCSA</b> is <b>not for shading</b>" in info and "<b>MWA</b> (the default) is the one for shading" in info,
          "description: MWA recommended for shading, MEWCSA not for shading")
    check("four schemes beyond the paper" in info
          and all(m in info for m in ("SMEWCSA", "QUADRIC", "JET", "<b>ADAPTIVE</b> is the most accurate")),
          "description: the four schemes beyond the paper, ADAPTIVE the most accurate")
    check("keeps the normal it has" in info and "without faces is refused" in info,
          "description: loose vertices keep their normals, no faces is refused")
    helps = {}
    for r in rows:
        cells = r.split("<TD>")
        helps[cells[2].split("</TD>")[0].strip()] = cells[3].split("<i>")[1].split(" -- </i>")[0]
    method = next((h for k, h in helps.items() if k.startswith("Weighting")), "")
    check(all("<b>%s</b>:" % a in method for a in ("MWE", "MWA", "MWSELR", "MWAAT", "MWELR", "MWRELR", "MEWCSA",
                                                     "SMEWCSA", "QUADRIC", "JET", "ADAPTIVE"))
          and "MEWCSA</b>: cotangent weights, not for shading" in method,
          "method help names all eleven (MEWCSA: not for shading)")
    weld = helps.get("Weld by position", "")
    sel = helps.get("Affect only selected vertices", "")
    check("not changed" in weld and "selected faces" in sel and "keep theirs" in sel,
          "weld and selection help complete")
    longest = max((len(re.sub("<[^>]*>", "", line)) for h in helps.values() for line in h.split("<br>")),
                  default=999)
    # MeshLab 2020.09's Help mode sizes each help label by its <br> lines: a line
    # that wraps (over about 44 characters at the dialog's width) pushes the last
    # lines out of sight (docs/meshlab-dialog-help.png shows the dialog).
    check(all("\n" not in h for h in helps.values()) and longest <= 44,
          "parameter help: lines broken with <br>, none longer than 44 characters (longest %d)" % longest)


def test_point_cloud(server, tmp):
    """960 points with normals and no faces (PLY and OFF): refused in the
    filter's words, a non-zero exit, nothing written."""
    pts, nrm = [], []
    for i in range(960):
        t, p = math.acos(1 - 2 * (i + 0.5) / 960), math.pi * (1 + 5 ** 0.5) * i
        n = (math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t))
        pts.append(tuple(2 * c for c in n))
        nrm.append(n)
    ply = os.path.join(tmp, "cloud.ply")
    with open(ply, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex 960\nproperty float x\nproperty float y\n"
                "property float z\nproperty float nx\nproperty float ny\nproperty float nz\nend_header\n")
        for p, n in zip(pts, nrm):
            f.write("%r %r %r %r %r %r\n" % (p + n))
    off = os.path.join(tmp, "cloud.off")
    write_off(off, pts, [], normals=nrm)
    script = os.path.join(tmp, "cloud.mlx")
    mlx(script, 1)
    for src in (ply, off):
        out = os.path.join(tmp, "cloud-out.ply")
        if os.path.exists(out):
            os.remove(out)
        rc, log = filter_run(server, tmp, src, out, script)
        check((0 < rc < 128 or rc == 255) and not os.path.exists(out)
              and "needs faces: this layer has 960 vertices and no faces; its normals are left as they are" in log,
              "point cloud (%s, 960 points with normals): refused in the filter's words, exit %d, nothing written"
              % (os.path.basename(src), rc))


def test_loose_points(server, vnconvert, tmp, lumpy):
    """A mesh with 10 loose points (no face): they keep the file's normals; the
    mesh's vertices get vnconvert's."""
    positions, tris = read_off_mesh(lumpy)
    nv = len(positions)
    loose = [(3.0 + i, 0.5 * i, -1.0) for i in range(10)]
    loose_n = [unit((1.0, 0.1 * i, -0.5)) for i in range(10)]
    src = os.path.join(tmp, "loose.off")
    write_off(src, positions + loose, tris, normals=[(0.0, 0.0, 1.0)] * nv + loose_n)
    r = filtered(server, tmp, src, "loose", "10 loose points", 1)
    if not r:
        return
    p, normals, t, log = r
    ref = vn_reference(vnconvert, tmp, "loose", p, t, "mwa")
    idx = [p.index(q) if q in p else None for q in loose]
    ok = None not in idx and len(p) == nv + 10
    kept = ok and all(near(normals[k], n) for k, n in zip(idx, loose_n))
    rest = [k for k in range(len(p)) if k not in idx]
    a = max_angle(normals, ref, rest) if ok else 180
    check(kept and a <= MAX_ANGLE and "%d of %d vertex normals changed" % (nv, nv + 10) in log
          and "10 kept (no face contributes)" in log and "Re-Compute Vertex Normals" in log and ", MWA:" in log,
          "10 loose points keep the file's normals, the rest as vnconvert (%.5f deg), the log counts them "
          "and names MWA" % a)


def test_face_selection(server, vnconvert, tmp, lumpy):
    """Faces selected (as MeshLab's rectangle select does; here Conditional Face
    Selection), "only selected": the vertices of those faces get the normal of a
    whole-mesh run, the others keep the file's; the log counts them."""
    positions, tris = read_off_mesh(lumpy)
    nv = len(positions)
    src = os.path.join(tmp, "lumpy-fsel.off")
    write_off(src, positions, tris, normals=[(0.0, 0.0, 1.0)] * nv)
    r = filtered(server, tmp, src, "fsel", "selected faces", 3, selected=True,
                 face_condition="(x0 &gt; 0.2) &amp;&amp; (x1 &gt; 0.2) &amp;&amp; (x2 &gt; 0.2)")
    if not r:
        return
    p, normals, t, log = r
    ref = vn_reference(vnconvert, tmp, "lumpy-fsel", p, t, "mwaat")
    chosen = sorted({v for tri in t if all(p[v][0] > 0.2 for v in tri) for v in tri})
    rest = [i for i in range(len(p)) if i not in set(chosen)]
    a = max_angle(normals, ref, chosen)
    kept = all(normals[i] == (0.0, 0.0, 1.0) for i in rest)
    check(chosen and rest and a <= MAX_ANGLE and kept
          and "%d of %d vertex normals changed (only selected: %d vertices)" % (len(chosen), nv, len(chosen)) in log,
          "selected faces: their %d vertices as a whole-mesh run (%.5f deg), %d others keep the file's normal: %s; "
          "the log counts them" % (len(chosen), a, len(rest), kept))


def test_degenerate(server, vnconvert, tmp, methods):
    """Zero-area faces (collinear corners) and an isolated vertex: they contribute
    nothing, and a vertex no face contributes to keeps the file's normal; never a NaN."""
    positions = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0.5), (2, 0, 0), (3, 0, 0), (5, 5, 5),
                 (0.5, 0, 0), (0, 0, 1)]
    tris = [(0, 1, 2), (1, 3, 2), (1, 4, 5), (0, 7, 1), (0, 2, 8), (0, 8, 1)]
    given = (0.6, 0.0, 0.8)
    src = os.path.join(tmp, "degenerate.off")
    write_off(src, positions, tris, normals=[given] * len(positions))
    for i, m in enumerate(methods):
        r = filtered(server, tmp, src, "degenerate.%s" % m, "degenerate %s" % m, i)
        if not r:
            continue
        p, normals, t, log = r
        ref = vn_reference(vnconvert, tmp, "degenerate", p, t, m)
        nan = any(not math.isfinite(c) for n in normals for c in n)
        none = [k for k in range(len(p)) if ref[k] == (0.0, 0.0, 0.0)]
        some = [k for k in range(len(p)) if k not in none]
        iso = p.index((5.0, 5.0, 5.0)) if (5.0, 5.0, 5.0) in p else None
        check(not nan and max_angle(normals, ref, some) <= MAX_ANGLE and len(p) == len(positions)
              and iso in none and len(none) == 4 and all(near(normals[k], given) for k in none)
              and ("4 kept (no face contributes)" in log),
              "degenerate %s: no NaN, the isolated vertex and the 3 in zero-area faces only keep the file's "
              "normal, others as vnconvert (%.5f deg)" % (m, max_angle(normals, ref, some)))


def test_weld(server, vnconvert, tmp, methods):
    """A triangle soup (every face its own three vertices): weld on gives every copy
    the normal vnconvert computes on the shared-vertex mesh; off, each copy its face's."""
    src_shared = os.path.join(tmp, "lumpy.off")
    with open(src_shared) as f:
        lines = [l.split() for l in f if l.strip()]
    nv, nf = int(lines[1][0]), int(lines[1][1])
    positions = [tuple(float(x) for x in l) for l in lines[2:2 + nv]]
    tris = [tuple(int(x) for x in l[1:4]) for l in lines[2 + nv:2 + nv + nf]]
    soup_pos, soup_tris, origin = [], [], []
    for t in tris:
        soup_tris.append(tuple(range(len(soup_pos), len(soup_pos) + 3)))
        for v in t:
            soup_pos.append(positions[v])
            origin.append(v)
    soup = os.path.join(tmp, "soup.off")
    write_off(soup, soup_pos, soup_tris)
    for m in ("mwa", "mwselr"):
        i = methods.index(m)
        for weld in (True, False):
            r = filtered(server, tmp, soup, "soup.%s.%d" % (m, weld), "weld=%s %s" % (weld, m), i, weld=weld)
            if not r:
                continue
            p, normals, t, _ = r
            ok = len(p) == len(soup_pos)
            if weld:
                # vnconvert on the shared-vertex mesh as MeshLab holds it (float positions)
                shared_f = [None] * nv
                for k, v in enumerate(origin):
                    shared_f[v] = p[k]
                ref = vn_reference(vnconvert, tmp, "soup-welded", shared_f, tris, m)
                a = max((angle(normals[k], ref[origin[k]]) for k in range(len(p))), default=0) if ok else 180
                check(ok and a <= MAX_ANGLE, "weld on, %s: every copy as the welded mesh (%.5f deg)" % (m, a))
            else:
                ref = vn_reference(vnconvert, tmp, "soup", p, t, m)
                a = max_angle(normals, ref) if ok else 180
                check(ok and a <= MAX_ANGLE, "weld off, %s: each copy its face's normal (%.5f deg)" % (m, a))


def test_selected(server, vnconvert, tmp, lumpy):
    """Only selected vertices (MeshLab's Conditional Vertex Selection x > 0) change;
    the others keep the file's normals."""
    positions, tris = read_off_mesh(lumpy)
    nv = len(positions)
    src = os.path.join(tmp, "lumpy-n.off")
    write_off(src, positions, tris, normals=[(0.0, 0.0, 1.0)] * nv)
    r = filtered(server, tmp, src, "selected", "only selected", 2, selected=True, select_condition="x &gt; 0")
    if not r:
        return
    p, normals, t, _ = r
    ref = vn_reference(vnconvert, tmp, "lumpy-sel", p, t, "mwselr")
    sel = [i for i in range(len(p)) if p[i][0] > 0]
    rest = [i for i in range(len(p)) if p[i][0] <= 0]
    a = max_angle(normals, ref, sel)
    kept = all(normals[i] == (0.0, 0.0, 1.0) for i in rest)
    check(sel and rest and a <= MAX_ANGLE and kept,
          "only selected: %d selected as vnconvert (%.5f deg), %d others keep the file's normal: %s"
          % (len(sel), a, len(rest), kept))


def test_deleted(server, vnconvert, tmp, lumpy):
    """Vertices deleted just before the filter (Conditional Vertex Selection x > 0.3,
    Delete Selected Vertices: MeshLab keeps them in its arrays, marked deleted, with
    their faces): the live mesh gets vnconvert's normals of the mesh that is left,
    vertices left without a face and loose points keep the file's normals, the log
    counts live vertices only."""
    positions, tris = read_off_mesh(lumpy)
    nv = len(positions)
    loose = [(-3.0 - i, 0.5 * i, -1.0) for i in range(4)]
    loose_n = [unit((1.0, 0.1 * i, -0.5)) for i in range(4)]
    src = os.path.join(tmp, "lumpy-del.off")
    write_off(src, positions + loose, tris, normals=[(0.0, 0.0, 1.0)] * nv + loose_n)
    r = filtered(server, tmp, src, "deleted", "deleted vertices", 1, select_condition="x &gt; 0.3",
                 delete_selected=True)
    if not r:
        return
    p, normals, t, log = r
    gone = sum(1 for q in positions if q[0] > 0.3)
    ref = vn_reference(vnconvert, tmp, "lumpy-del", p, t, "mwa")
    none = [k for k in range(len(p)) if ref[k] == (0.0, 0.0, 0.0)]
    some = [k for k in range(len(p)) if k not in none]
    given = dict(zip(positions + loose, [(0.0, 0.0, 1.0)] * nv + loose_n))
    kept = all(near(normals[k], given[p[k]]) for k in none)
    a = max_angle(normals, ref, some)
    check(gone > 0 and len(p) == nv + 4 - gone and len(none) >= 4 and kept and a <= MAX_ANGLE
          and "%d of %d vertex normals changed, %d kept (no face contributes)" % (len(some), len(p), len(none)) in log,
          "%d vertices deleted before the filter: the %d left as vnconvert (%.5f deg), %d without a face keep "
          "the file's normals: %s; the log counts live vertices" % (gone, len(some), a, len(none), kept))


def test_missing_parameter(server, tmp, src):
    """What the README says meshlabserver 2020.09 does with a script that lacks a
    parameter other than method (the missing method is tested above: MWA): it
    aborts on an assertion in mainserver.cpp (exit 134) and writes nothing."""
    for name in ("weldByPosition", "onlySelected", "faceNormals"):
        script = os.path.join(tmp, "missing.mlx")
        mlx(script, 0, omit=name)
        out = os.path.join(tmp, "missing.ply")
        if os.path.exists(out):
            os.remove(out)
        rc, log = filter_run(server, tmp, src, out, script)
        check(rc == 134 and not os.path.exists(out) and "mainserver.cpp" in log and "Assertion" in log,
              "script without %s: meshlabserver's assertion in mainserver.cpp, exit %d (134), nothing written"
              % (name, rc))


def test_bad_method(server, tmp, src):
    for raw in (str(len(METHODS)), "-1", "99"):
        script = os.path.join(tmp, "bad.mlx")
        mlx(script, 0, raw_method=raw)
        out = os.path.join(tmp, "bad.ply")
        rc, log = filter_run(server, tmp, src, out, script)
        # exit(-1) is 255; a crash would be 128 + the signal (134 abort, 139 segfault)
        check((0 < rc < 128 or rc == 255) and not os.path.exists(out) and ("is not one of 0..%d" % (len(METHODS) - 1)) in log
              and "Problem with filter" in log,
              "method=%s: MeshLab's error, exit %d (non-zero, not a signal), no output" % (raw, rc))
        if raw == "99":
            print("     " + "\n     ".join(l for l in log.splitlines() if "vn" in l or "filter" in l.lower()))


if __name__ == "__main__":
    sys.exit(main())
