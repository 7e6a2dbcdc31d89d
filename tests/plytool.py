"""A small independent PLY reader for the PLY/STL tests (numpy).

  plytool.py same A B      every vertex property of A but nx ny nz is in B
                           with the same values and type, and so are the
                           faces, every other face property and element of
                           A, and A's comments and obj_info lines, in order
  plytool.py same_normals A B  the same, nx ny nz included
  plytool.py same_vertices A B  as same, but only the vertex properties and
                           faces (B went through a format without the rest)
  plytool.py same_set A B  A and B have the same vertex properties and the
                           same vertices (every property's value), in any order
  plytool.py count A       "VERTICES FACES TRIANGLES" (fan-triangulated)
  plytool.py column A NAME I  vertex I's value of property NAME
  plytool.py big A B       A rewritten as binary_big_endian (same header)
"""
import re
import sys

import numpy as np

TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
         "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
         "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


def read(path):
    raw = open(path, "rb").read()
    end = raw.index(b"end_header") + len(b"end_header")
    end += 2 if raw[end:end + 2] == b"\r\n" else 1
    lines = re.split(r"\r\n|\r|\n", raw[:end].decode("latin-1"))
    fmt, elements = None, []
    for line in lines:
        w = line.split()
        if w and w[0] == "format":
            fmt = w[1]
        elif w and w[0] == "element":
            elements.append((w[1], int(w[2]), []))
        elif w and w[0] == "property":
            elements[-1][2].append((w[-1], w[2:4] if w[1] == "list" else w[1]))
    data, out = raw[end:], {}
    order = "<" if fmt == "binary_little_endian" else ">"
    tokens, pos = (data.split(), 0) if fmt == "ascii" else (None, 0)
    for name, count, props in elements:
        columns = {p: [] for p, _ in props}
        for _ in range(count):
            for p, t in props:
                if fmt == "ascii":
                    if isinstance(t, list):
                        n = int(tokens[pos]); pos += 1
                        columns[p].append(np.array(tokens[pos:pos + n], dtype=TYPES[t[1]])); pos += n
                    else:
                        columns[p].append(np.array(tokens[pos], dtype=TYPES[t])[()]); pos += 1
                elif isinstance(t, list):
                    c = np.dtype(order + TYPES[t[0]]); v = np.dtype(order + TYPES[t[1]])
                    n = int(np.frombuffer(data, c, 1, pos)[0]); pos += c.itemsize
                    columns[p].append(np.frombuffer(data, v, n, pos)); pos += n * v.itemsize
                else:
                    v = np.dtype(order + TYPES[t])
                    columns[p].append(np.frombuffer(data, v, 1, pos)[0]); pos += v.itemsize
        out[name] = ({p: t for p, t in props}, columns)
    return fmt, elements, out, raw[:end], data


def comments(path):
    """The header's comment and obj_info lines but vn's own."""
    _, _, _, header, _ = read(path)
    lines = re.split(r"\r\n|\r|\n", header.decode("latin-1"))
    return [l for l in lines if l.split()[:1] in (["comment"], ["obj_info"]) and l != "comment written by vn"]


def face_lists(e):
    """The faces' index lists; none without a face element (a point cloud)."""
    if "face" not in e:
        return []
    return e["face"][1].get("vertex_indices") or e["face"][1].get("vertex_index") or []


def main():
    cmd = sys.argv[1]
    if cmd == "count":
        _, _, e, _, _ = read(sys.argv[2])
        faces = face_lists(e)
        print(len(e["vertex"][1]["x"]), len(faces), sum(max(len(f) - 2, 0) for f in faces))
    elif cmd == "column":
        _, _, e, _, _ = read(sys.argv[2])
        print(repr(float(e["vertex"][1][sys.argv[3]][int(sys.argv[4])])))
    elif cmd in ("same", "same_normals", "same_vertices"):
        _, _, a, _, _ = read(sys.argv[2])
        _, _, b, _, _ = read(sys.argv[3])
        bad = []
        for p, values in a["vertex"][1].items():
            if (cmd != "same_normals" and p in ("nx", "ny", "nz")) or isinstance(a["vertex"][0][p], list):
                continue
            if p not in b["vertex"][1]:
                bad.append("no property " + p)
            elif not np.array_equal(np.array(values), np.array(b["vertex"][1][p])):
                bad.append("values of " + p + " differ")
            elif TYPES[a["vertex"][0][p]] != TYPES[b["vertex"][0][p]]:
                bad.append(p + " changed type")
        fa, fb = face_lists(a), face_lists(b)
        if len(fa) != len(fb) or any(not np.array_equal(x, y) for x, y in zip(fa, fb)):
            bad.append("faces differ")
        for name, props in ((n, p) for n, (p, _) in a.items() if n != "vertex" and cmd != "same_vertices"):
            if name == "tristrips" and "face" not in a:  # read as faces
                continue
            for p, t in props.items():
                if name == "face" and p in ("vertex_indices", "vertex_index"):
                    continue
                if name not in b or p not in b[name][0]:
                    bad.append("no %s property %s" % (name, p))
                elif b[name][0][p] != t and TYPES[t if isinstance(t, str) else t[1]] != TYPES[
                        b[name][0][p] if isinstance(t, str) else b[name][0][p][1]]:
                    bad.append("%s property %s changed type" % (name, p))
                elif len(a[name][1][p]) != len(b[name][1][p]) or not all(
                        np.array_equal(x, y) for x, y in zip(a[name][1][p], b[name][1][p])):
                    bad.append("values of %s property %s differ" % (name, p))
        if cmd != "same_vertices" and comments(sys.argv[2]) != comments(sys.argv[3]):
            bad.append("comments differ: %r, %r" % (comments(sys.argv[2]), comments(sys.argv[3])))
        print("\n".join(bad))
        sys.exit(1 if bad else 0)
    elif cmd == "same_set":
        _, _, a, _, _ = read(sys.argv[2])
        _, _, b, _, _ = read(sys.argv[3])
        names = sorted(a["vertex"][1])
        if names != sorted(b["vertex"][1]):
            sys.exit("properties differ: %s, %s" % (names, sorted(b["vertex"][1])))
        rows = [sorted(zip(*(np.asarray(e["vertex"][1][p], float).tolist() for p in names))) for e in (a, b)]
        sys.exit(0 if rows[0] == rows[1] else "vertices differ")
    elif cmd == "big":
        fmt, elements, e, header, _ = read(sys.argv[2])
        out = [header.replace(fmt.encode(), b"binary_big_endian", 1)]
        for name, count, props in elements:
            for i in range(count):
                for p, t in props:
                    v = e[name][1][p][i]
                    if isinstance(t, list):
                        out.append(np.array(len(v), ">" + TYPES[t[0]]).tobytes())
                        out.append(np.asarray(v, ">" + TYPES[t[1]]).tobytes())
                    else:
                        out.append(np.array(v, ">" + TYPES[t]).tobytes())
        open(sys.argv[3], "wb").write(b"".join(out))


if __name__ == "__main__":
    main()
