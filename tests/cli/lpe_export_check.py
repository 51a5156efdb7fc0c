#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Check the path export of `ggrt find --path` against an independent matcher.

    lpe_export_check.py GGRT SCENE SIZE LPE JSONL OBJ

JSONL and OBJ are what `ggrt find SCENE -s SIZE --path LPE --paths-jsonl
JSONL --paths-obj OBJ` wrote. Every line of JSONL must parse; the pixels
must be the ones find lists; for each pixel, the paths must be exactly the
ledger terms of `ggrt trace --format json` that lpe_check.py's translator
(no code shared with the library) matches, with the term's value as the
contribution; each path's events, read as an expression, must match that
path's own tokens; its points one per ray hit plus the eye and the light
(or a point on the leaving ray); and OBJ must have one polyline (l) per
path, over that path's points. Prints "ok ..." or "FAIL ..." lines.
"""
import collections
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import lpe_check  # noqa: E402


def expected_points(doc, term):
    nodes, parent = {}, {}

    def walk(n, p):
        nodes[n["id"]], parent[n["id"]] = n, p
        for c in n["children"]:
            walk(c, n["id"])

    for r in doc["roots"]:
        walk(r, None)
    i, hits = term["node"], 0
    while i is not None:
        hits += nodes[i]["hit"] is not None
        i = parent[i]
    return 1 + hits + (term["kind"] in ("background", "diffuse", "phong"))


def main():
    ggrt, scene, size, lpe, jsonl, obj = sys.argv[1:7]
    fails = []
    lines = [json.loads(l) for l in open(jsonl, encoding="utf-8")]
    f = json.loads(lpe_check.run([ggrt, "find", scene, "-s", size, "--path", lpe, "--limit", "0",
                                  "-f", "json", "-q"]))
    pixels = {tuple(m["pixel"]) for m in f["matches"]}
    by_pixel = collections.defaultdict(list)
    for p in lines:
        by_pixel[tuple(p["pixel"])].append(p)
    if set(by_pixel) != pixels:
        fails.append("pixels: %d in the file, find matched %d" % (len(by_pixel), len(pixels)))
    rx, preds = lpe_check.compile_lpe(lpe)
    for (x, y), got in sorted(by_pixel.items()):
        d = json.loads(lpe_check.run([ggrt, "trace", scene, "-s", size, "--pixel", "%d,%d" % (x, y),
                                      "-f", "json"]))
        terms = d["ledger"]["terms"]
        want = {}
        for term, (evs, _) in zip(terms, lpe_check.paths(d)):
            toks = "".join(lpe_check.token(ev, preds) for ev in evs)
            if rx.fullmatch(toks):
                want[(term["node"], term["kind"], term["light"])] = (term, evs)
        have = {(p["node"], p["term"], p["light"]): p for p in got}
        if set(have) != set(want) or len(got) != len(have):
            fails.append("%d,%d: paths %s, the trace's matching terms %s" % (x, y, sorted(have),
                                                                             sorted(want)))
            continue
        for k, p in have.items():
            term, evs = want[k]
            erx, epreds = lpe_check.compile_lpe(p["events"])
            own = "".join(lpe_check.token(ev, epreds) for ev in evs)
            if not erx.fullmatch(own):
                fails.append("%d,%d: events %s do not match the path" % (x, y, p["events"]))
            if any(abs(a - b) > 1e-12 * max(1, abs(b)) for a, b in zip(p["contribution"], term["value"])):
                fails.append("%d,%d: contribution %s, term %s" % (x, y, p["contribution"], term["value"]))
            n = expected_points(d, term)
            if len(p["points"]) != n or len(p["weights"]) != n:
                fails.append("%d,%d %s: %d points, want %d" % (x, y, p["events"], len(p["points"]), n))
    verts, polys = 0, []
    for line in open(obj, encoding="utf-8"):
        w = line.split()
        if w and w[0] == "v":
            verts += 1
        elif w and w[0] == "l":
            polys.append([int(i) for i in w[1:]])
    if len(polys) != len(lines):
        fails.append("OBJ: %d polylines for %d paths" % (len(polys), len(lines)))
    for pl, p in zip(polys, lines):
        if len(pl) != len(p["points"]) or max(pl) > verts:
            fails.append("OBJ: polyline %s for %d points" % (pl, len(p["points"])))
            break
    what = "export of find --path %s on %s: %d paths of %d pixels" % (lpe, scene.split("/")[-1],
                                                                     len(lines), len(pixels))
    if fails or not lines:
        print("FAIL %s: %s" % (what, "; ".join(fails[:3]) or "no paths"))
        return 1
    print("ok   %s, JSONL and OBJ agree with the traces" % what)
    return 0


if __name__ == "__main__":
    sys.exit(main())
