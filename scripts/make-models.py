#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Write the example meshes of examples/scenes/models (made here, so no
third-party model needs a licence):

  knot.obj  a (2,3) torus knot tube as quads, without normals (ggrt
            computes them), y up
  blob.ply  a bumpy sphere, binary little endian, with vertex normals and
            u v, y up

  python3 scripts/make-models.py [OUTDIR]     (default examples/scenes/models)
"""
import math
import os
import struct
import sys


def knot(path, n=240, m=16, p=2, q=3, tube=0.42):
    def curve(t):
        r = 2 + math.cos(q * t)
        return (r * math.cos(p * t), -math.sin(q * t), r * math.sin(p * t))

    def sub(a, b):
        return (a[0] - b[0], a[1] - b[1], a[2] - b[2])

    def cross(a, b):
        return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])

    def unit(a):
        l = math.sqrt(a[0] ** 2 + a[1] ** 2 + a[2] ** 2)
        return (a[0] / l, a[1] / l, a[2] / l)

    out = ["# a (2,3) torus knot, %d x %d quads, no normals: ggrt computes them" % (n, m),
           "# written by scripts/make-models.py", "o knot"]
    for i in range(n):
        t = 2 * math.pi * i / n
        c = curve(t)
        tan = unit(sub(curve(t + 1e-4), curve(t - 1e-4)))
        # away from the torus's core circle: periodic, so the tube closes
        core = (2 * math.cos(p * t), 0, 2 * math.sin(p * t))
        b = unit(cross(tan, sub(c, core)))
        nrm = cross(b, tan)
        for j in range(m):
            a = 2 * math.pi * j / m
            out.append("v %.6f %.6f %.6f" % tuple(c[k] + tube * (math.cos(a) * nrm[k] + math.sin(a) * b[k])
                                              for k in range(3)))
    for i in range(n):
        for j in range(m):
            a = i * m + j + 1
            b_ = i * m + (j + 1) % m + 1
            c_ = ((i + 1) % n) * m + (j + 1) % m + 1
            d = ((i + 1) % n) * m + j + 1
            out.append("f %d %d %d %d" % (a, b_, c_, d))  # counter-clockwise seen from outside
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def blob(path, nu=96, nv=48):
    def point(u, v):
        th, ph = 2 * math.pi * u, math.pi * v
        r = 1 + 0.12 * math.sin(5 * th) * math.sin(4 * ph) * math.sin(ph)
        return (r * math.sin(ph) * math.cos(th), r * math.cos(ph), -r * math.sin(ph) * math.sin(th))

    verts, faces = [], []
    for j in range(nv + 1):
        for i in range(nu + 1):
            u, v = i / nu, j / nv
            p = point(u, v)
            e = 1e-5
            du = [(a - b) / (2 * e) for a, b in zip(point(u + e, v), point(u - e, v))]
            dv = [(a - b) / (2 * e) for a, b in zip(point(u, min(v + e, 1)), point(u, max(v - e, 0)))]
            n = (du[1] * dv[2] - du[2] * dv[1], du[2] * dv[0] - du[0] * dv[2], du[0] * dv[1] - du[1] * dv[0])
            l = math.sqrt(sum(x * x for x in n))
            n = tuple(x / l for x in n) if l > 1e-9 else (0.0, 1.0 if v < 0.5 else -1.0, 0.0)
            # outward
            if sum(a * b for a, b in zip(n, p)) < 0:
                n = tuple(-x for x in n)
            verts.append(p + n + (u, 1 - v))
    w = nu + 1
    for j in range(nv):
        for i in range(nu):
            a, b, c, d = j * w + i, j * w + i + 1, (j + 1) * w + i + 1, (j + 1) * w + i
            if j == 0:
                faces.append((a, d, c))
            elif j == nv - 1:
                faces.append((a, d, b))
            else:
                faces.append((a, d, c, b))
    head = ("ply\nformat binary_little_endian 1.0\ncomment a bumpy sphere, written by "
            "scripts/make-models.py\nelement vertex %d\nproperty float x\nproperty float y\n"
            "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
            "property float u\nproperty float v\nelement face %d\n"
            "property list uchar int vertex_indices\nend_header\n" % (len(verts), len(faces)))
    with open(path, "wb") as f:
        f.write(head.encode())
        for v in verts:
            f.write(struct.pack("<8f", *v))
        for fc in faces:
            f.write(struct.pack("<B%di" % len(fc), len(fc), *fc))


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "examples/scenes/models"
    os.makedirs(out, exist_ok=True)
    knot(os.path.join(out, "knot.obj"))
    blob(os.path.join(out, "blob.ply"))
