# SPDX-License-Identifier: MIT
"""Check a `ggrt trace --format json` document against docs/trace-json.md
and against `ggrt render --pixel X,Y --crop ...` output for the same pixel:
the colour must be equal as 32-bit floats and the ray counts per kind equal.
usage: check_trace.py TRACE.json RENDER.txt"""
import json
import re
import struct
import sys

VEC = "vec"
NUM = (int, float)
NONFINITE = {"inf": float("inf"), "-inf": float("-inf"), "nan": float("nan")}


def num(v):
    """A number of the document: JSON numbers, and since version 2 the
    strings "inf", "-inf", "nan" for the values JSON has not."""
    return NONFINITE[v] if isinstance(v, str) and v in NONFINITE else v


def fail(msg):
    print("check_trace:", msg)
    sys.exit(1)


def need(obj, key, kind, where):
    if key not in obj:
        fail("%s: missing '%s'" % (where, key))
    v = obj[key]
    if kind == VEC:
        if not (isinstance(v, list) and len(v) == 3 and all(isinstance(num(c), NUM) for c in v)):
            fail("%s: '%s' is not a 3-vector: %r" % (where, key, v))
        v = [num(c) for c in v]
    elif isinstance(kind, tuple) and all(isinstance(k, str) for k in kind):
        if v not in kind:
            fail("%s: '%s' = %r not one of %s" % (where, key, v, kind))
    elif kind is None:
        pass
    elif kind is NUM and isinstance(num(v), NUM) and not isinstance(v, bool):
        v = num(v)
    elif not isinstance(v, kind) or isinstance(v, bool) and kind is not bool:
        fail("%s: '%s' has type %s" % (where, key, type(v).__name__))
    return v


def close(a, b, tol):
    return a == b or abs(a - b) <= tol


def check_node(n, counts, parent_depth, parent=None, nodes=None):
    """parent: (its weight, its absorption) to check this node's weight
    against: the parent's times its absorption times this factor."""
    w = "node %s" % n.get("id")
    if nodes is not None:
        nodes[n.get("id")] = n
    need(n, "id", int, w)
    kind = need(n, "kind", ("eye", "reflect", "refract", "tir"), w)
    depth = need(n, "depth", int, w)
    if parent_depth is not None and depth != parent_depth + 1:
        fail("%s: depth %d under a parent of depth %d" % (w, depth, parent_depth))
    need(n, "sample", int, w)
    if n.get("channel") not in (None, "r", "g", "b"):
        fail("%s: bad channel" % w)
    for k in ("origin", "direction", "weight", "factor", "contribution", "absorption", "color"):
        need(n, k, VEC, w)
    need(n, "share", NUM, w)
    wt, fac, ab = need(n, "weight", VEC, w), need(n, "factor", VEC, w), need(n, "absorption", VEC, w)
    if parent is not None:
        want = [parent[0][c] * parent[1][c] * fac[c] for c in range(3)]
        if wt != want:
            fail("%s: weight %r is not the parent's %r x its absorption %r x factor %r"
                 % (w, wt, parent[0], parent[1], fac))
    need(n, "medium", int, w)
    need(n, "n_medium", NUM, w)
    need(n, "stop", ("none", "miss", "depth", "matte"), w)
    tv = need(n, "traversal", dict, w)
    if not (isinstance(tv.get("nodes"), int) and isinstance(tv.get("prims"), int)
            and tv["nodes"] >= 0 and tv["prims"] >= 0):
        fail("%s: traversal %r" % (w, tv))
    counts[kind] = counts.get(kind, 0) + 1
    hit = n.get("hit", "absent")
    if hit == "absent":
        fail("%s: missing 'hit'" % w)
    if hit is None:
        if n["stop"] != "miss":
            fail("%s: no hit but stop is %s" % (w, n["stop"]))
    else:
        for k in ("object", "line", "material"):
            need(hit, k, int, w + " hit")
        need(hit, "shape", ("sphere", "triangle", "polygon", "cone", "rect", "implicit", "mesh"), w)
        need(hit, "t", NUM, w)
        for k in ("point", "ng", "ns", "surface", "emission", "ambient", "reflect_factor",
                  "refract_factor"):
            need(hit, k, VEC, w + " hit")
        need(hit, "front", bool, w)
        uv = need(hit, "uv", list, w)
        if len(uv) != 2:
            fail("%s: uv" % w)
        if hit["fresnel"] is not None and not isinstance(hit["fresnel"], NUM):
            fail("%s: fresnel" % w)
        num = need(hit, "numeric", dict, w)
        for k in ("perr", "offset"):
            if not isinstance(num.get(k), NUM) or num[k] < 0:
                fail("%s: numeric %s = %r" % (w, k, num.get(k)))
        for k in ("tir_margin", "edge"):
            if num.get(k, "absent") is not None and not isinstance(num.get(k), NUM):
                fail("%s: numeric %s = %r" % (w, k, num.get(k)))
        if (num["edge"] is None) != (hit["shape"] not in ("triangle", "rect", "mesh")):
            fail("%s: an edge distance belongs to triangles and rectangles" % w)
        for L in need(hit, "lights", list, w):
            need(L, "light", int, w + " light")
            v = need(L, "verdict", ("visible", "blocked", "attenuated", "facing-away"), w)
            for k in ("transmittance", "diffuse", "phong"):
                need(L, k, VEC, w + " light")
            if v != "facing-away":
                counts["shadow"] = counts.get("shadow", 0) + 1
            if v in ("blocked", "attenuated"):
                counts[v] = counts.get(v, 0) + 1
                need(L, "origin", VEC, w), need(L, "direction", VEC, w)
                need(L, "t_block", NUM, w)
            if v == "blocked" and not isinstance(L["occluder"], int):
                fail("%s: blocked light without an occluder" % w)
            # the verdict says how much of the light arrived (trace.h)
            t = L["transmittance"]
            if (v == "visible" and t != [1, 1, 1]) or (v == "attenuated" and t == [1, 1, 1]) or \
               (v == "blocked" and t != [0, 0, 0]):
                fail("%s: %s light with transmittance %r" % (w, v, t))
    for c in need(n, "children", list, w):
        check_node(c, counts, depth, (wt, ab), nodes)


def f32(x):
    return struct.unpack("f", struct.pack("f", x))[0]


def main():
    def refuse(name):
        fail("not JSON: " + name)
    doc = json.load(open(sys.argv[1]), parse_constant=refuse)
    if doc.get("ggrt_trace") != 2 or doc.get("version") != 2:
        fail("not a ggrt trace document of version 2")
    color = need(doc, "color", VEC, "top")
    need(doc, "pixel", list, "top")
    stats = need(doc, "stats", dict, "top")
    counts, nodes = {}, {}
    roots = need(doc, "roots", list, "top")
    for r in roots:
        if r["kind"] != "eye" or r["depth"] != 1:
            fail("a root is not an eye ray of depth 1")
        if [num(c) for c in r["weight"]] != [1.0 / len(roots)] * 3:
            fail("a root's weight is not 1/%d" % len(roots))
        check_node(r, counts, None, None, nodes)
    render = open(sys.argv[2]).read()
    m = re.search(r"^pixel \d+,\d+ (\S+) (\S+) (\S+)$", render, re.M)
    if not m:
        fail("no pixel line in the render output:\n" + render)
    rendered = [float(v) for v in m.groups()]
    if [f32(c) for c in color] != [f32(c) for c in rendered]:
        fail("traced colour %r != rendered %r" % (color, rendered))
    if [f32(c) for c in color] != color:
        fail("traced colour %r is not the float the image stores" % (color,))
    # The ledger (every sample recorded): its terms add up to the colour.
    if doc["sample"] is None:
        led = need(doc, "ledger", dict, "top")
        if led["holds"] is not True:
            fail("the ledger does not hold")
        for c in range(3):
            total = sum(t["value"][c] for t in led["terms"])
            if abs(total - color[c]) > led["bound"][c]:
                fail("ledger terms add up to %r, the colour is %r" % (total, color[c]))
        # Each ray's share is the ledger's shares of the terms it carried
        # (those entering at it or below it), within the ledger's rounding.
        under = {i: [] for i in nodes}
        up = {k["id"]: i for i, nd in nodes.items() for k in nd["children"]}
        for t in led["terms"]:
            i = t["node"]
            while i is not None:
                under[i].append(t)
                i = up.get(i)
        tol = 1e-9 + sum(led["bound"]) / max(1e-300, abs(sum(color)))
        for i, nd in nodes.items():
            s = sum(num(t["share"]) for t in under[i])
            if not close(num(nd["share"]), s, tol * max(1, len(under[i]))):
                fail("node %d: share %r, its ledger terms' %r" % (i, nd["share"], s))
    # The tree's own counts agree with its stats object...
    tree = {"eye": counts.get("eye", 0), "reflect": counts.get("reflect", 0) + counts.get("tir", 0),
            "refract": counts.get("refract", 0), "shadow": counts.get("shadow", 0)}
    tree["shadow_blocked"], tree["shadow_attenuated"] = counts.get("blocked", 0), counts.get("attenuated", 0)
    for k, v in tree.items():
        if stats[k] != v:
            fail("tree has %d %s rays, its stats say %d" % (v, k, stats[k]))
    # ...and, when every sample was recorded, with the renderer's counts.
    if doc["sample"] is None:
        m = re.search(r"rays: eye (\d+) \(hit \d+\), reflect (\d+) \(tir (\d+) of them\), "
                      r"refract (\d+), shadow (\d+) \(blocked (\d+), attenuated (\d+)\)", render)
        if not m:
            fail("no rays line in the render output")
        kinds = ("eye", "reflect", "tir", "refract", "shadow", "blocked", "attenuated")
        got = dict(zip(kinds, map(int, m.groups())))
        for k in ("eye", "reflect", "refract", "shadow", "tir"):
            if got[k] != stats[k]:
                fail("render counted %d %s rays for the pixel, trace %d" % (got[k], k, stats[k]))
        # the renderer's shadow verdicts are the trace's, light by light
        for k in ("blocked", "attenuated"):
            if got[k] != counts.get(k, 0):
                fail("render counted %d %s shadow rays for the pixel, the trace %d"
                     % (got[k], k, counts.get(k, 0)))
    print("ok: colour %r, rays %r" % (color, tree))


main()
