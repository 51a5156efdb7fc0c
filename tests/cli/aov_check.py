#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Check the path layers of `ggrt render --aov` against an independent matcher.

    aov_check.py GGRT SCENE SIZE X0,Y0,X1,Y1 NAME=LPE...

For every pixel of the crop, `ggrt render SCENE -s SIZE --aov ... --pixel
X,Y` prints each layer's value there (the float the EXR holds), and `ggrt
trace --format json` the pixel's ledger terms; each layer's value is
recomputed per channel as the sum of the terms whose path lpe_check.py's
translator (no code shared with the library) matches. They must agree
within 2^-22 of the pixel's magnitude (float layers, double sums in another
order). Prints "ok ..." or "FAIL ..." lines.
"""
import json
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import lpe_check  # noqa: E402


def main():
    ggrt, scene, size, crop = sys.argv[1:5]
    layers = [a.split("=", 1) for a in sys.argv[5:]]
    x0, y0, x1, y1 = (int(v) for v in crop.split(","))
    rx = [(n, lpe_check.compile_lpe(e)) for n, e in layers]
    out = os.path.join(tempfile.mkdtemp(), "l.exr")
    args = [a for n, e in layers for a in ("--aov", "%s=%s" % (n, e))]
    fails, pixels, lit = [], 0, 0
    for y in range(y0, y1):
        for x in range(x0, x1):
            r = lpe_check.run([ggrt, "render", scene, "-s", size, "-q", "-o", out, "--pixel",
                               "%d,%d" % (x, y)] + args)
            got = {}
            for line in r.splitlines():
                w = line.split()
                if w[0] == "layer":
                    got[w[1]] = [float(v) for v in w[3:6]]
            d = json.loads(lpe_check.run([ggrt, "trace", scene, "-s", size, "--pixel",
                                          "%d,%d" % (x, y), "-f", "json"]))
            terms = d["ledger"]["terms"]
            mag = sum(abs(v) for v in d["color"]) + sum(abs(v) for t in terms for v in t["value"])
            for name, (rxe, preds) in rx:
                want = [0.0, 0.0, 0.0]
                for term, (evs, _) in zip(terms, lpe_check.paths(d)):
                    if rxe.fullmatch("".join(lpe_check.token(ev, preds) for ev in evs)):
                        want = [a + b for a, b in zip(want, term["value"])]
                lit += any(v != 0 for v in want)
                if name not in got or any(abs(a - b) > 2 ** -22 * mag for a, b in zip(got[name], want)):
                    fails.append("%d,%d %s: layer %s, terms %s" % (x, y, name, got.get(name), want))
            pixels += 1
    what = "%s %s over %s: %d layers in %d pixels (%d non-zero)" % (
        os.path.basename(scene), size, crop, len(layers), pixels, lit)
    if fails or lit == 0:
        print("FAIL %s; %s" % (what, fails[:3]))
        return 1
    print("ok   %s equal the independent matcher's sums of the trace's terms" % what)
    return 0


if __name__ == "__main__":
    sys.exit(main())
