#!/usr/bin/env python3
"""Closed jittered torus of quads (genmesh.py's grid, one quad per cell): usage genquads.py NQUADS OUT.off [SEED]"""
import math, random, sys
nq = int(float(sys.argv[1])); out = sys.argv[2]; seed = int(sys.argv[3]) if len(sys.argv) > 3 else 12345
R, r = 1.0, 0.4
nv = max(3, int(round(math.sqrt(nq * r / R)))); nu = max(3, int(round(nq / nv)))
rng = random.Random(seed); rnd = rng.random
du, dv = 2 * math.pi / nu, 2 * math.pi / nv; hn = 0.05 * r * dv
with open(out, "w") as f:
    f.write("OFF\n%d %d 0\n" % (nu * nv, nu * nv))
    for i in range(nu):
        for j in range(nv):
            u = (i + 0.6 * (rnd() - 0.5)) * du; v = (j + 0.6 * (rnd() - 0.5)) * dv
            rr = r + hn * (2 * rnd() - 1); cv = R + rr * math.cos(v)
            f.write("%.6f %.6f %.6f\n" % (cv * math.cos(u), cv * math.sin(u), rr * math.sin(v)))
    for i in range(nu):
        i1 = (i + 1) % nu
        for j in range(nv):
            j1 = (j + 1) % nv
            f.write("4 %d %d %d %d\n" % (i * nv + j, i1 * nv + j, i1 * nv + j1, i * nv + j1))
print("%s: quad torus %dx%d, V=%d F=%d" % (out, nu, nv, nu * nv, nu * nv))
