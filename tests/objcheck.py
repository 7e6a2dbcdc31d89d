"""OBJ facts for tests/test_obj.sh, read independently of Draco and vn.

    objcheck.py faces FILE [D]  one line per face: "object|group|smoothing group|material|corners: ..."
                                ("-" where none is set yet; a group's names joined by one blank) with the corners'
                                positions and texture coordinates as float32 (printed with D
                                decimals, as MeshLab's "%f" prints them, when D is given)
    objcheck.py close A B TOL   exit status 1 unless A's and B's faces, in order, have as many
                                corners, each with its position and texture coordinate within TOL
    objcheck.py triangles FILE  the number of triangles the faces fan into
    objcheck.py lines FILE      one line per `l` line: its points' positions as float32
    objcheck.py vertices FILE   the number of distinct v/vt/vn references of the faces, plus the v lines no
                                face refers to (loose vertices)
    objcheck.py unit FILE       exit status 1 unless every vn is a unit vector (1e-6)
"""
import math
import struct
import sys


def f32(text):
    return struct.unpack("<f", struct.pack("<f", float(text)))[0]


def read(path):
    v, vt, vn, faces, lines = [], [], [], [], []
    material = obj = group = smoothing = "-"
    for line in open(path, encoding="utf-8"):
        words = line.split("#")[0].split()
        if not words:
            continue
        key, rest = words[0], words[1:]
        if key in ("v", "vt", "vn"):
            {"v": v, "vt": vt, "vn": vn}[key].append([f32(x) for x in rest[: 2 if key == "vt" else 3]])
        elif key == "usemtl":
            material = line.split(None, 1)[1].strip()
        elif key == "o":
            obj = rest[0]
        elif key == "g":
            group = " ".join(rest)
        elif key == "s":
            smoothing = " ".join(rest)
        elif key == "f":
            corners = []
            for word in rest:
                refs = (word.split("/") + ["", ""])[:3]
                corners.append(tuple(int(r) + (len(a) + 1 if int(r) < 0 else 0) if r else 0
                                     for r, a in zip(refs, (v, vt, vn))))
            faces.append((f"{obj}|{group}|{smoothing}", material, corners))
        elif key == "l":
            lines.append([int(r) + (len(v) + 1 if int(r) < 0 else 0) for r in (w.split("/")[0] for w in rest)])
    return v, vt, vn, faces, lines


def main():
    what, path = sys.argv[1], sys.argv[2]
    v, vt, vn, faces, lines = read(path)
    if what == "faces":
        number = repr if len(sys.argv) < 4 else lambda x: f"{x:.{int(sys.argv[3])}f}"
        for names, material, corners in faces:
            text = " ".join(",".join(number(x) for x in v[p - 1] + (vt[t - 1] if t else []))
                            for p, t, _ in corners)
            print(f"{names}|{material}|{len(corners)}: {text}")
    elif what == "close":
        w, wt, _, other, _ = read(sys.argv[3])
        def values(p, t, pos, tex):
            return pos[p - 1] + (tex[t - 1] if t else [])
        tol = float(sys.argv[4])
        same = len(faces) == len(other) and all(
            len(a[2]) == len(b[2]) and all(
                len(x) == len(y) and all(abs(i - j) <= tol for i, j in zip(x, y))
                for x, y in ((values(p, t, v, vt), values(q, u, w, wt)) for (p, t, _), (q, u, _) in zip(a[2], b[2])))
            for a, b in zip(faces, other))
        sys.exit(0 if same else 1)
    elif what == "lines":
        for points in lines:
            print(" ".join(",".join(repr(x) for x in v[p - 1]) for p in points))
    elif what == "triangles":
        print(sum(len(c) - 2 for _, _, c in faces))
    elif what == "vertices":
        refs = {c for _, _, cs in faces for c in cs}
        print(len(refs) + len(v) - len({p for p, _, _ in refs}))
    elif what == "unit":
        sys.exit(0 if vn and all(abs(math.hypot(*n) - 1) < 1e-6 for n in vn) else 1)


main()
