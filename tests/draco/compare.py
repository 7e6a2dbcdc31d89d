"""Compares two decoded meshes for the Draco tests.

  compare.py A B BITS        -> prints "max error E"; exit 0 when B is A within one
                                step of BITS-bit quantization (Draco's step: A's
                                largest extent / (2^BITS - 1))
  compare.py --normals A     -> exit 0 when every normal of A is a unit vector
  compare.py --each A BITS B... -> both checks on every B: prints "B: max error E"
                                (or why not) for each; exit 0 when every B passes.
                                A is read once, and a B whose points and
                                triangles equal an earlier B's is not snapped
                                again (vnconvert's outputs for each method share
                                them), which makes it much faster than one
                                process a file

A and B are draco_decoder's .obj, decode.mjs's .json, or .off. They match
when they have as many points, distinct positions and triangles, and B's triangles (oriented,
any rotation) are A's once each B position is replaced by the nearest A
position within one step per coordinate: vertex and face order may differ,
as Draco's edgebreaker renumbers both.
"""
import json
import math
import sys
from collections import Counter


def load(path):
    """(positions, triangles, normals or None, point count or None): triangles
    index positions; an .obj has no point count (its v lines are the distinct
    position values)."""
    if path.endswith(".json"):
        d = json.load(open(path))
        p, n = d["positions"], d["normals"]
        positions = [tuple(p[i:i + 3]) for i in range(0, len(p), 3)]
        t = d["indices"]
        normals = [n[i:i + 3] for i in range(0, len(n), 3)] if n else None
        return positions, [tuple(t[i:i + 3]) for i in range(0, len(t), 3)], normals, d["points"]
    if path.endswith(".obj"):
        positions, normals, triangles = [], [], []
        for line in open(path):
            w = line.split()
            if w and w[0] == "v":
                positions.append(tuple(map(float, w[1:4])))
            elif w and w[0] == "vn":
                normals.append(list(map(float, w[1:4])))
            elif w and w[0] == "f":
                c = [int(x.split("/")[0]) - 1 for x in w[1:]]
                triangles += [(c[0], c[i - 1], c[i]) for i in range(2, len(c))]
        return positions, triangles, normals or None, None
    rows = [l.split("#")[0].split() for l in open(path)]
    rows = [r for r in rows if r]
    nv, nf = int(rows[1][0]), int(rows[1][1])
    positions = [tuple(map(float, r[:3])) for r in rows[2:2 + nv]]
    triangles = []
    for r in rows[2 + nv:2 + nv + nf]:
        c = list(map(int, r[1:1 + int(r[0])]))
        triangles += [(c[0], c[i - 1], c[i]) for i in range(2, len(c))]
    return positions, triangles, None, nv


def canonical(t):
    i = t.index(min(t))
    return t[i:] + t[:i]


def compare(a_path, b_path, bits):
    return compare_loaded(load(a_path), load(b_path), bits)


def compare_loaded(a, b, bits):
    (pa, ta, _, na), (pb, tb, _, nb) = a, b
    tolerance = max(max(p[k] for p in pa) - min(p[k] for p in pa) for k in range(3)) / (2 ** bits - 1)
    if na != nb or len(set(pa)) != len(set(pb)) or len(ta) != len(tb):
        print(f"counts differ: {na} vs {nb} points, {len(set(pa))} vs {len(set(pb))} positions, "
              f"{len(ta)} vs {len(tb)} triangles")
        return False
    cell = max(tolerance, 1e-30)
    grid = {}
    for p in set(pa):
        grid.setdefault(tuple(math.floor(x / cell) for x in p), []).append(p)
    worst, snapped = 0.0, []
    for q in pb:
        k = [math.floor(x / cell) for x in q]
        near = [p for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)
                for p in grid.get((k[0] + dx, k[1] + dy, k[2] + dz), ())]
        best = min(near, key=lambda p: max(abs(x - y) for x, y in zip(p, q)), default=None)
        if best is None or max(abs(x - y) for x, y in zip(best, q)) > tolerance:
            print(f"vertex {q} is not within {tolerance} of any input vertex")
            return False
        worst = max(worst, max(abs(x - y) for x, y in zip(best, q)))
        snapped.append(best)
    same = Counter(canonical(tuple(pa[i] for i in t)) for t in ta) == \
        Counter(canonical(tuple(snapped[i] for i in t)) for t in tb)
    print(f"max error {worst:.9g}")
    if not same:
        print("the triangles differ")
    return same


def unit_normals(path):
    return are_unit(load(path)[2])


def are_unit(normals):
    return bool(normals) and all(abs(math.sqrt(sum(x * x for x in n)) - 1) < 1e-3 for n in normals)


def each(a_path, bits, b_paths):
    a, passed, ok = load(a_path), {}, True
    for path in b_paths:
        b = load(path)
        key = (tuple(b[0]), tuple(b[1]), b[3])
        print(f"{path}: ", end="")
        if key in passed:
            print(passed[key])
        elif compare_loaded(a, b, bits):
            passed[key] = "the points and triangles of a B above"
        else:
            ok = False
        if not are_unit(b[2]):
            print(f"{path}: normals missing or not unit")
            ok = False
    return ok


if __name__ == "__main__":
    if sys.argv[1] == "--each":
        sys.exit(not each(sys.argv[2], int(sys.argv[3]), sys.argv[4:]))
    if sys.argv[1] == "--normals":
        sys.exit(not unit_normals(sys.argv[2]))
    sys.exit(not compare(sys.argv[1], sys.argv[2], int(sys.argv[3])))
