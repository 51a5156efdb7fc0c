#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Check `ggrt diff --path` against an independent matcher.

    lpe_diff_check.py GGRT SCENE B_OPTIONS LPE...

Over a crop of SCENE at 64x48, every pixel is traced on both sides with
`ggrt trace --format json` (side a: the defaults; side b: --accuracy
B_OPTIONS). Each side's paths are the ledger's terms as tokens, and each
LPE a regular expression over them, by lpe_check.py's translator (no code
shared with the library). A pixel's light moved between path classes when
the multisets of its matching paths' tokens (event types, scatters and
labels) differ between a and b. Those pixels must be exactly the ones
`ggrt diff --path LPE --format json` lists, and their count its "moved".
Prints "ok ..." or "FAIL ..." lines (tests/cli/t_lpe.sh turns them into TAP).
With GG_TEST_SAMPLE=N in the environment only one pixel in N is traced and
compared (lpe_check.sampled).
"""
import collections
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import lpe_check  # noqa: E402

SIZE = "64x48"
CROP = (16, 8, 48, 24)


def classes(doc, rx, preds):
    got = collections.Counter()
    for evs, _ in lpe_check.paths(doc):
        s = "".join(lpe_check.token(ev, preds) for ev in evs)
        if rx.fullmatch(s):
            got[s] += 1
    return got


def main():
    ggrt, scene, bopt, exprs = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
    x0, y0, x1, y1 = CROP
    crop = "%d,%d,%d,%d" % CROP
    docs = {}
    pixels = lpe_check.sampled(x0, y0, x1, y1, 0)
    for x, y in sorted(pixels):
        args = [ggrt, "trace", scene, "-s", SIZE, "--pixel", "%d,%d" % (x, y), "-f", "json"]
        docs[(x, y)] = (json.loads(lpe_check.run(args)),
                        json.loads(lpe_check.run(args + ["--accuracy", bopt])))
    fails = 0
    for e in exprs:
        rx, preds = lpe_check.compile_lpe(e)
        want = {p for p, (a, b) in docs.items() if classes(a, rx, preds) != classes(b, rx, preds)}
        d = json.loads(lpe_check.run([ggrt, "diff", scene, "-s", SIZE, "--crop", crop, "--b", bopt,
                                      "--path", e, "--worst", "0", "-f", "json", "-q"]))
        every = {tuple(m["pixel"]) for m in d["moves"]}
        got = every & pixels
        what = "diff --path %s on %s, b %s, over %s: %d pixels moved" % (e, scene.split("/")[-1],
                                                                         bopt, crop, len(want))
        if len(pixels) < (x1 - x0) * (y1 - y0):
            what += " of %d traced" % len(pixels)
        if got != want or d["moved"] != len(every):
            fails += 1
            print("FAIL %s; diff says %d; only in diff %s, only in the traces %s"
                  % (what, d["moved"], sorted(got - want)[:3], sorted(want - got)[:3]))
        elif not want:
            fails += 1
            print("FAIL %s: the crop shows no move, so it tests nothing" % what)
        else:
            print("ok   %s, diff agrees" % what)
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
