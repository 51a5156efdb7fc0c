#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Write the mesh scenes of issue 35 (meshes at scale) as NFF, triangles
only, so that ggrt and the Embree anchor read the same file:

  torus-1m.nff   make bench-mesh's bumpy torus (bench/bench_mesh.c,
                 make_torus) at 1,000,000 triangles
  knot-512k.nff  the (2,3) torus knot of examples/scenes/models/knot.obj
                 (scripts/make-models.py, knot) at 2000 x 128 quads,
                 512,000 triangles

each with two mirrors (a wall behind, one at the left, two triangles
each) and two lights, 1024x1024, y up; and for ggrt the same scenes with
the model as a mesh (torus-1m-mesh.nff reading torus-1m.obj through
`mesh "..." flat material current`: the same flat triangles, with shared
vertices). Made here, not committed: up to 90 MB of text each.

  python3 scripts/make-mesh-scenes.py [OUTDIR]   (default build/meshes)
"""
import importlib.util
import math
import os
import sys
import tempfile

HEAD = """v
from 0 5 9.5
at 0 0 0
up 0 1 0
angle 45
hither 0.01
resolution 1024 1024
b 0.2 0.3 0.5
l 6 8 6
l -4 6 8
"""
# two mirrors: the wall behind (z = -5) and one at the left (x = -5.5),
# facing the model; then the model's own material
MIRRORS = """f 0.9 0.9 0.9 0.1 0.85 50 0 1
p 3
-7 -3 -5
7 -3 -5
7 6 -5
p 3
-7 -3 -5
7 6 -5
-7 6 -5
p 3
-5.5 -3 7
-5.5 -3 -5
-5.5 6 -5
p 3
-5.5 -3 7
-5.5 6 -5
-5.5 6 7
f 0.9 0.5 0.3 0.9 0 0 0 1
"""


def write(path, verts, tris):
    with open(path, "w") as f:
        f.write(HEAD + MIRRORS)
        for t in tris:
            f.write("p 3\n%.6f %.6f %.6f\n%.6f %.6f %.6f\n%.6f %.6f %.6f\n"
                    % (verts[t[0]] + verts[t[1]] + verts[t[2]]))
    print("%s: %d triangles (+4 of the mirrors)" % (path, len(tris)))
    base = path[:-len(".nff")]
    with open(base + ".obj", "w") as f:
        f.write("# written by scripts/make-mesh-scenes.py\n")
        f.write("".join("v %.6f %.6f %.6f\n" % v for v in verts))
        f.write("".join("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1) for t in tris))
    with open(base + "-mesh.nff", "w") as f:
        f.write(HEAD + MIRRORS + 'mesh "%s" flat material current\n' % os.path.basename(base + ".obj"))
    print("%s-mesh.nff: the same as a mesh (%s.obj)" % (base, os.path.basename(base)))


def torus(ntri):
    """bench_mesh.c's make_torus: nu x nv quads with bumps."""
    nu = int(math.sqrt(ntri))
    nv = ntri // (2 * nu)
    v = []
    for i in range(nu):
        for j in range(nv):
            a, b = 2 * math.pi * i / nu, 2 * math.pi * j / nv
            r = 0.6 + 0.05 * math.sin(7 * a) * math.sin(5 * b)
            R = 2 + 0.1 * math.cos(3 * a)
            v.append(((R + r * math.cos(b)) * math.cos(a), r * math.sin(b),
                      (R + r * math.cos(b)) * math.sin(a)))
    t = []
    for i in range(nu):
        for j in range(nv):
            a, b = i * nv + j, i * nv + (j + 1) % nv
            c, d = ((i + 1) % nu) * nv + (j + 1) % nv, ((i + 1) % nu) * nv + j
            t += [(a, b, c), (a, c, d)]
    return v, t


def knot(n, m):
    """make-models.py's knot at n x m quads, each split in two triangles."""
    here = os.path.dirname(os.path.abspath(__file__))
    spec = importlib.util.spec_from_file_location("make_models", os.path.join(here, "make-models.py"))
    mm = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mm)
    with tempfile.TemporaryDirectory() as d:
        p = os.path.join(d, "knot.obj")
        mm.knot(p, n=n, m=m)
        v, t = [], []
        for line in open(p):
            w = line.split()
            if w and w[0] == "v":
                v.append(tuple(float(x) for x in w[1:4]))
            elif w and w[0] == "f":
                q = [int(x) - 1 for x in w[1:5]]
                t += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
    return v, t


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "build/meshes"
    os.makedirs(out, exist_ok=True)
    write(os.path.join(out, "torus-1m.nff"), *torus(1000000))
    write(os.path.join(out, "knot-512k.nff"), *knot(2000, 128))


if __name__ == "__main__":
    main()
