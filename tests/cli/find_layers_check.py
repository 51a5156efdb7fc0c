#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""find --path answered by the layer copy against the recorder.

    find_layers_check.py GGRT SCENE...

An expression without predicates at one sample per pixel is answered by a
render whose shading carries the expression's automaton ("traced": false);
the same expression with an always-true predicate on its C event
(C[x >= 0]...) is answered by recording and matching every pixel's trees
("traced": true). For each scene (at 24x18) and each expression below,
`ggrt find --path ... -f json --limit 0` must give the same document but
for "path" and "traced": the same pixels, values, shares (bit for bit, as
printed with 17 digits), counts and ray statistics. Prints "ok ..." or
"FAIL ..." lines. With GG_TEST_SAMPLE=N in the environment (tests/cli/run.sh)
only one scene-expression pair in N is run, rotating: every scene and every
expression still appear.
"""
import json
import os
import subprocess
import sys

EXPRS = ["C<TS>+B", "C<TS>.*<RS'tir'>.*", "C<RD>L", "C<RD'0'>L", "C<RG>L", "C<RS>+<RD>L",
         "C<RD>A", "C.*O", "CB", "C[^<TS>]*B", "C<TS>{4}<RD>[LA]", "C(<TS><TS>){1,2}<RD>L",
         "C<T.'m1'>.*", "C.*<L.'1'>", "C.{5,}", "C<RS>?<RD>L|CO", "C.*<TS>.*<RD>L"]


def find(ggrt, scene, expr):
    out = subprocess.run([ggrt, "find", scene, "-s", "24x18", "--path", expr, "--limit", "0",
                          "-f", "json", "-q"], check=True, stdout=subprocess.PIPE,
                         universal_newlines=True).stdout
    return json.loads(out)


def forced(expr):
    """expr with an always-true predicate on each C that starts a path."""
    return "|".join("C[x >= 0]" + alt[1:] for alt in expr.split("|"))


def main():
    ggrt, scenes = sys.argv[1], sys.argv[2:]
    fails = 0
    sample = max(1, int(os.environ.get("GG_TEST_SAMPLE", "1")))
    for si, scene in enumerate(scenes):
        bad, matched = [], 0
        exprs = [e for ei, e in enumerate(EXPRS) if (si + ei) % sample == 0]
        for e in exprs:
            a, b = find(ggrt, scene, e), find(ggrt, scene, forced(e))
            if a.pop("traced") is not False or b.pop("traced") is not True:
                bad.append("%s: traced not false / true" % e)
            a.pop("path"), b.pop("path")
            if a != b:
                bad.append("%s: %s" % (e, [k for k in a if a[k] != b.get(k)]))
            matched += a["matched"]
        if bad:
            fails += 1
            print("FAIL find --path by layers on %s: %s" % (scene, bad[:3]))
        else:
            print("ok   find --path by layers on %s: %d expressions, %d matched pixels, the "
                  "recorder's answers" % (scene, len(exprs), matched))
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
