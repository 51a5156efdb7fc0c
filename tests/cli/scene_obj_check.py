#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Check `ggrt trace --scene-obj` on every scene file.

    scene_obj_check.py GGRT SCENE...

For each scene: the OBJ must be well formed (every face's indices name
vertices written before it, every vertex finite), hold one OBJ object per
scene object (as many as `ggrt info` counts), named objectI_KIND_lineL, each
with at least one face; and every hit point of the ray trees of a few
pixels (`ggrt trace -f json`) must lie on the faces of the object the ray
hit, named as the tree names it: within the tessellation's sagitta for
spheres and cones (from the header's segment count), within a cell for
implicit surfaces (a quarter of a cell, 64 along the box's longest side
or as many as the object's comment says, for a surface written coarser),
within rounding for
flat faces and meshes. So the file shows each object where the renderer
hits it. A file over 20 MB (balls-s4, rings, tree) is checked for its
header and object count only. Prints "ok ..." or "FAIL ..." lines.
"""
import json
import math
import os
import re
import subprocess
import sys
import tempfile

PIXELS = ((8, 6), (3, 2), (12, 9), (5, 10))
BIG = 20 << 20


def run(args):
    return subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def parse_obj(path):
    """(header, {name: (verts, faces)}, order, problems, {name: cells})"""
    verts, objs, order, bad, header, cur, cells = [], {}, [], [], "", None, {}
    with open(path) as f:
        for ln, line in enumerate(f, 1):
            w = line.split()
            if not w:
                continue
            if w[0] == "#":
                header = header or line
                m = re.match(r"# (\d+) cells along", line)
                if m and cur is not None:
                    cells[cur] = int(m.group(1))
            elif w[0] == "o":
                cur = w[1]
                order.append(cur)
                objs[cur] = ([], [])
            elif w[0] == "v":
                p = tuple(float(x) for x in w[1:4])
                if len(w) != 4 or not all(math.isfinite(x) for x in p):
                    bad.append("line %d: vertex %r" % (ln, line.strip()))
                verts.append(p)
            elif w[0] == "f":
                idx = [int(x) for x in w[1:]]
                if cur is None or len(idx) < 3 or not all(1 <= i <= len(verts) for i in idx):
                    bad.append("line %d: face %r" % (ln, line.strip()))
                    continue
                objs[cur][1].append([verts[i - 1] for i in idx])
            else:
                bad.append("line %d: %r" % (ln, line.strip()))
    return header, objs, order, bad, cells


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def closest_on_triangle(p, a, b, c):
    """Closest point to p on triangle abc (Ericson, Real-Time Collision Detection 5.1.5)."""
    ab, ac, ap = sub(b, a), sub(c, a), sub(p, a)
    d1, d2 = dot(ab, ap), dot(ac, ap)
    if d1 <= 0 and d2 <= 0:
        return a
    bp = sub(p, b)
    d3, d4 = dot(ab, bp), dot(ac, bp)
    if d3 >= 0 and d4 <= d3:
        return b
    vc = d1 * d4 - d3 * d2
    if vc <= 0 and d1 >= 0 and d3 <= 0:
        v = d1 / (d1 - d3)
        return (a[0] + v * ab[0], a[1] + v * ab[1], a[2] + v * ab[2])
    cp = sub(p, c)
    d5, d6 = dot(ab, cp), dot(ac, cp)
    if d6 >= 0 and d5 <= d6:
        return c
    vb = d5 * d2 - d1 * d6
    if vb <= 0 and d2 >= 0 and d6 <= 0:
        w = d2 / (d2 - d6)
        return (a[0] + w * ac[0], a[1] + w * ac[1], a[2] + w * ac[2])
    va = d3 * d6 - d5 * d4
    if va <= 0 and (d4 - d3) >= 0 and (d5 - d6) >= 0:
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return (b[0] + w * (c[0] - b[0]), b[1] + w * (c[1] - b[1]), b[2] + w * (c[2] - b[2]))
    denom = 1.0 / (va + vb + vc)
    v, w = vb * denom, vc * denom
    return (a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w)


def boxed(faces):
    """Each face with its box: (lo, hi, face); the box computed once per
    object, not once per hit point."""
    out = []
    for fc in faces:
        lo = tuple(min(v[k] for v in fc) for k in range(3))
        hi = tuple(max(v[k] for v in fc) for k in range(3))
        out.append((lo, hi, fc))
    return out


def distance(p, boxes, tol):
    """Distance from p to the nearest face (fans of triangles), faces whose
    box is farther than tol skipped."""
    best = math.inf
    px, py, pz = p
    for lo, hi, fc in boxes:
        if (px < lo[0] - tol or px > hi[0] + tol or py < lo[1] - tol or py > hi[1] + tol or
                pz < lo[2] - tol or pz > hi[2] + tol):
            continue
        for i in range(1, len(fc) - 1):
            q = closest_on_triangle(p, fc[0], fc[i], fc[i + 1])
            best = min(best, math.sqrt(dot(sub(p, q), sub(p, q))))
    return best


def extent(boxes):
    """The longest side of the box around every face."""
    return max(max(b[1][k] for b in boxes) - min(b[0][k] for b in boxes) for k in range(3))


def tolerance(kind, ext, seg, scale, cells):
    # radius at most half the extent; a cone's quads (between its circles)
    # are off the surface by a chord's sagitta, a sphere's (between two
    # parallels and two meridians, both pi/seg from their middle) by
    # r (1 - cos^2(pi/seg)) at most
    c = math.cos(math.pi / seg)
    if kind == "sphere":
        return 0.5 * ext * (1 - c * c) * 1.01 + 1e-9 * scale
    if kind == "cone":
        return 0.5 * ext * (1 - c) * 1.01 + 1e-9 * scale
    if kind == "implicit":  # a vertex on each cut edge: the surface within a cell
        return ext / cells * 0.25 + 1e-9 * scale
    return 1e-9 * scale


def hits(doc):
    out = []

    def walk(n):
        if n.get("hit"):
            out.append(n["hit"])
        for c in n["children"]:
            walk(c)
    for r in doc["roots"]:
        walk(r)
    return out


def check(ggrt, scene, tmp):
    obj = os.path.join(tmp, "scene.obj")
    r = run([ggrt, "trace", scene, "-s", "16x12", "--pixel", "8,6", "--scene-obj", obj, "-f", "json"])
    if r.returncode != 0:
        return "exit %d: %s" % (r.returncode, r.stderr[-300:])
    info = run([ggrt, "info", scene])
    m = re.search(r"^objects\s+(\d+)", info.stdout, re.M)
    want = int(m.group(1)) if m else -1
    if os.path.getsize(obj) > BIG:
        with open(obj, "rb") as f:
            data = f.read()
        head = data[:data.find(b"\n") + 1].decode("utf-8", "replace")
        n = data.count(b"\no ") + data.startswith(b"o ")
        if not head.startswith("# ggrt trace --scene-obj: ") or n != want:
            return "header %r, %d objects of %d" % (head, n, want)
        return None
    header, objs, order, bad, cells = parse_obj(obj)
    if bad:
        return "; ".join(bad[:3])
    m = re.search(r"(\d+) segments", header)
    if not m or len(order) != want or len(objs) != want:
        return "header %r, %d objects of %d" % (header, len(order), want)
    seg = int(m.group(1))
    names = {}
    for name in order:
        m = re.match(r"object(\d+)_([a-z]+)_line(\d+)$", name)
        if not m or not objs[name][1]:
            return "object %s: a bad name or no face" % name
        names[int(m.group(1))] = (name, m.group(2), int(m.group(3)))
    checked, prepared = 0, {}
    for i, (x, y) in enumerate(PIXELS):
        doc = json.loads(r.stdout) if i == 0 else \
            json.loads(run([ggrt, "trace", scene, "-s", "16x12", "--pixel", "%d,%d" % (x, y), "-f", "json"]).stdout)
        for h in hits(doc):
            name, kind, line = names.get(h["object"], (None, None, None))
            if name is None or kind != h["shape"] or line != h["line"]:
                return "hit on object %d (%s line %d), the OBJ says %s" % (h["object"], h["shape"], h["line"], name)
            if name not in prepared:
                boxes = boxed(objs[name][1])
                prepared[name] = (boxes, extent(boxes))
            boxes, ext = prepared[name]
            p = tuple(h["point"])
            scale = max(1.0, max(abs(c) for c in p))
            tol = tolerance(kind, ext, seg, scale, cells.get(name, 64))
            d = distance(p, boxes, tol)
            if not d <= tol:
                return "pixel %d,%d: a hit on %s at %r is %g from its faces (at most %g)" % (x, y, name, p, d, tol)
            checked += 1
    return checked


def main():
    ggrt, scenes = sys.argv[1], sys.argv[2:]
    with tempfile.TemporaryDirectory() as tmp:
        total = 0
        for s in scenes:
            res = check(ggrt, s, tmp)
            if isinstance(res, str):
                print("FAIL %s: trace --scene-obj: %s" % (s, res))
            else:
                total += res or 0
                print("ok   %s: trace --scene-obj: one object each, %s" %
                      (s, "%d hit points on their object's faces" % res if res is not None else "header and count (a large file)"))
        print("# scene-obj: %d hit points checked" % total)


if __name__ == "__main__":
    main()
