"""Compares two .drc files as attributes.mjs dumps them (JSON), for the
Draco tests.

  same.py A.json B.json [BITS]

Exit 0 when B is A with only NORMAL changed: the same geometry metadata; the
same attributes other than NORMAL (unique id, type, data type, components,
normalized flag, metadata); B has a NORMAL; and the same triangles with the
same values at their corners: every triangle as the values of every
attribute but NORMAL at its three corners, oriented, any rotation, compared
as multisets with exact float equality (Draco's edgebreaker renumbers points
and triangles). With BITS, also prints "max position step S": how far B's
positions are from the nearest of A's, in steps of BITS-bit quantization
(A's largest extent / (2^BITS - 1)).
"""
import json
import math
import sys
from collections import Counter

NORMAL, POSITION = 1, 0


def kept(d):
    return sorted((a for a in d["attributes"] if a["type"] != NORMAL), key=lambda a: a["unique_id"])


def describe(a):
    return {k: a[k] for k in ("unique_id", "type", "data_type", "components", "normalized", "metadata")}


def corners(d):
    atts = kept(d)

    def corner(p):
        return tuple(tuple(a["values"][p * a["components"]:(p + 1) * a["components"]]) for a in atts)

    t = d["indices"]
    out = Counter()
    for i in range(0, len(t), 3):
        c = [corner(p) for p in t[i:i + 3]]
        k = c.index(min(c))
        out[tuple(c[k:] + c[:k])] += 1
    return out


def position_steps(a, b, bits):
    pa = next(x for x in a["attributes"] if x["type"] == POSITION)["values"]
    pb = next(x for x in b["attributes"] if x["type"] == POSITION)["values"]
    va = [tuple(pa[i:i + 3]) for i in range(0, len(pa), 3)]
    vb = [tuple(pb[i:i + 3]) for i in range(0, len(pb), 3)]
    step = max(max(p[k] for p in va) - min(p[k] for p in va) for k in range(3)) / (2 ** bits - 1)
    grid = {}
    for p in set(va):
        grid.setdefault(tuple(math.floor(x / step) for x in p), []).append(p)
    worst = 0.0
    for q in vb:
        k = [math.floor(x / step) for x in q]
        near = [p for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)
                for p in grid.get((k[0] + dx, k[1] + dy, k[2] + dz), ())]
        d = min((max(abs(x - y) for x, y in zip(p, q)) for p in near), default=math.inf)
        worst = max(worst, d / step)
    return worst


def same(a, b):
    ok = True
    if a["metadata"] != b["metadata"]:
        print(f"geometry metadata differ: {a['metadata']} vs {b['metadata']}")
        ok = False
    da, db = [describe(x) for x in kept(a)], [describe(x) for x in kept(b)]
    if da != db:
        print(f"attributes differ:\n  {da}\n  {db}")
        ok = False
    if not any(x["type"] == NORMAL for x in b["attributes"]):
        print("B has no NORMAL")
        ok = False
    if ok and corners(a) != corners(b):
        print("the triangles' corner values differ")
        ok = False
    return ok


if __name__ == "__main__":
    a, b = (json.load(open(f)) for f in sys.argv[1:3])
    if len(sys.argv) > 3:
        print(f"max position step {position_steps(a, b, int(sys.argv[3])):.6g}")
    sys.exit(not same(a, b))
