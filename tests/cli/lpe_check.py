#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Check ggrt's light-path expressions against an independent matcher.

    lpe_check.py GGRT DOC SCENE...

DOC is docs/debugging.md: its table of examples (rows "| `LPE` | N | N | N |",
counts on glass.nff, default.nff and prism.nff at -s 24x18) gives the
expressions. For each scene, over a crop (the whole 24x18 image for
glass.nff), every pixel is traced with `ggrt trace --format json`; each
ledger term becomes a string of event tokens read from the JSON tree, and
each expression a Python regular expression by the small translator below
(no code shared with the library's parser or matcher). The pixels with a
matching path and their shares must equal `ggrt find --path ... --format
json` over the same crop, and `ggrt find --path` over the whole image must
give the documented counts. Prints "ok ..." or "FAIL ..." lines
(tests/cli/t_lpe.sh turns them into TAP). With GG_TEST_SAMPLE=N in the
environment (tests/cli/run.sh) only one pixel of the crop in N is traced
and compared, and one expression in N is compared with find, each
rotating from scene to scene (the documented counts are all checked).
"""
import json
import math
import os
import re
import subprocess
import sys

SIZE = "24x18"
CROP = (8, 6, 16, 12)
DOC_SCENES = ["glass.nff", "default.nff", "prism.nff"]

# ---- LPE -> regular expression over tokens ----
# A token: TYPE SCATTER TIR ':' OBJECT ':' MATERIAL ':' LIGHT ':' PREDBITS ';'
# (SCATTER 'N' for events without one; '-' for fields an event lacks).
TYPES = "CRTLOBA"
ANY = r"[^;]*;"


class Translator:
    def __init__(self, text):
        self.s, self.i, self.preds = text, 0, []

    def peek(self):
        while self.i < len(self.s) and self.s[self.i] in " \t\r\n":
            self.i += 1
        return self.s[self.i] if self.i < len(self.s) else ""

    def take(self, c):
        if self.peek() != c:
            raise ValueError("expected %r at %d in %r" % (c, self.i, self.s))
        self.i += 1

    def translate(self):
        r = self.alt()
        if self.peek():
            raise ValueError("trailing text in %r" % self.s)
        return r

    def alt(self):
        parts = [self.cat()]
        while self.peek() == "|":
            self.i += 1
            parts.append(self.cat())
        return "(?:" + "|".join(parts) + ")"

    def cat(self):
        out = ""
        while self.peek() not in ("", "|", ")"):
            out += self.rep()
        return out

    def rep(self):
        r = self.atom()
        while self.peek() in ("*", "+", "?", "{"):
            c = self.peek()
            if c == "{":
                j = self.s.index("}", self.i)
                r = "(?:%s){%s}" % (r, self.s[self.i + 1:j].replace(" ", ""))
                self.i = j + 1
            else:
                r = "(?:%s)%s" % (r, c)
                self.i += 1
        return r

    def atom(self):
        if self.peek() == "(":
            self.i += 1
            r = self.alt()
            self.take(")")
            return r
        if self.peek() == "[" and not self.is_pred():
            self.i += 1
            neg = self.peek() == "^"
            if neg:
                self.i += 1
            alts = []
            while self.peek() != "]":
                alts.append(self.event())
            self.i += 1
            r = "(?:%s)" % "|".join(alts)
            r = "(?:(?!%s)%s)" % (r, ANY) if neg else r
        else:
            r = self.event()
        if self.peek() == "[" and self.is_pred():
            j = self.s.index("]", self.i)
            self.preds.append(self.s[self.i + 1:j])
            self.i = j + 1
            r = "(?=[^;]*:{K%d};)%s" % (len(self.preds) - 1, r)
        return r

    def is_pred(self):
        j = self.i + 1
        while j < len(self.s) and self.s[j] == " ":
            j += 1
        return j < len(self.s) and (self.s[j].islower() or self.s[j].isdigit() or self.s[j] in "(!")

    def label(self):
        j = self.s.index("'", self.i + 1)
        lab = self.s[self.i + 1:j]
        self.i = j + 1
        return lab

    def event(self):
        c = self.peek()
        types, scat, labels = TYPES, "NDGS", []
        if c == "<":
            self.i += 1
            c = self.peek()
            if c in TYPES or c == ".":
                types = TYPES if c == "." else c
                self.i += 1
                c = self.peek()
                if c in "DGS." and c:
                    scat = "NDGS" if c == "." else c
                    self.i += 1
            while self.peek() == "'":
                labels.append(self.label())
            self.take(">")
        elif c == "'":
            labels.append(self.label())
        elif c == ".":
            self.i += 1
        elif c and c in TYPES:
            types = c
            self.i += 1
        elif c and c in "DGS":
            scat = c
            self.i += 1
        else:
            raise ValueError("unexpected %r at %d in %r" % (c, self.i, self.s))
        return self.pattern(types, scat, labels)

    def pattern(self, types, scat, labels):
        alts = []
        for t in types:
            sc = scat if t in "RT" else ("N" if "N" in scat else "")
            sc = sc.replace("N", "") if t in "RT" else sc
            if not sc:
                continue
            tir, obj, mat, light, ok = "[01]", "[^:]*", "[^:]*", "[^:]*", True
            for lab in labels:
                if lab == "tir":
                    tir = "1"
                elif lab.startswith("m"):
                    ok = ok and t in "RTO" and mat in ("[^:]*", lab[1:])
                    mat = lab[1:]
                elif t == "L":
                    ok = ok and light in ("[^:]*", lab)
                    light = lab
                else:
                    ok = ok and t in "RTO" and obj in ("[^:]*", lab)
                    obj = lab
            if ok:
                alts.append("%s[%s]%s:%s:%s:%s:[01]*;" % (t, sc, tir, obj, mat, light))
        return "(?:%s)" % "|".join(alts) if alts else "(?!)"


def compile_lpe(text):
    t = Translator(text)
    body = t.translate()
    k = len(t.preds)
    for n in range(k):
        body = body.replace("{K%d}" % n, "[01]{%d}1[01]{%d}" % (n, k - n - 1))
    return re.compile(body), t.preds


# ---- predicates: comparisons joined by && and || ----


class Unknown:
    def _no(self, other):
        return False

    __eq__ = __ne__ = __lt__ = __le__ = __gt__ = __ge__ = _no
    __hash__ = object.__hash__


def pred_true(text, ray):
    py = text.replace("&&", " and ").replace("||", " or ")
    names = {"eye": "eye", "reflect": "reflect", "refract": "refract", "tir": "tir",
             "shadow": "shadow"}
    names.update(ray)
    return eval(py, {"__builtins__": {}}, names) is True


# ---- paths from the trace JSON ----


def fields(node, light=None):
    hit = node.get("hit")
    u = Unknown()
    tm = hit["numeric"]["tir_margin"] if hit else None
    return {"kind": "shadow" if light is not None else node["kind"], "depth": node["depth"],
            "object": hit["object"] if hit else u, "material": hit["material"] if hit else u,
            "tir_margin": tm if tm is not None else u,
            "light": light if light is not None else u}


def paths(doc):
    nodes, parent = {}, {}

    def walk(n, p):
        nodes[n["id"]], parent[n["id"]] = n, p
        for c in n["children"]:
            walk(c, n["id"])

    for r in doc["roots"]:
        walk(r, None)
    for term in doc["ledger"]["terms"]:
        i = term["node"]
        chain = [i]
        while parent[chain[-1]] is not None:
            chain.append(parent[chain[-1]])
        chain.reverse()
        evs = [("C", "N", 0, None, None, None, fields(nodes[chain[0]]))]
        for p, c in zip(chain, chain[1:]):
            hp = nodes[p]["hit"]
            evs.append(("T" if nodes[c]["kind"] == "refract" else "R", "S",
                        int(nodes[c]["kind"] == "tir"), hp["object"], hp["material"], None,
                        fields(nodes[p])))
        n, h, k = nodes[i], nodes[i]["hit"], term["kind"]
        if k == "background":
            evs.append(("B", "N", 0, None, None, None, fields(n)))
        elif k == "emission":
            evs.append(("O", "N", 0, h["object"], h["material"], None, fields(n)))
        else:
            evs.append(("R", "G" if k == "phong" else "D", 0, h["object"], h["material"], None,
                        fields(n)))
            if k == "ambient":
                evs.append(("A", "N", 0, None, None, None, fields(n)))
            else:
                evs.append(("L", "N", 0, None, None, term["light"], fields(n, term["light"])))
        yield evs, sum(term["value"])


def token(ev, preds):
    t, sc, tir, obj, mat, light, ray = ev
    bits = "".join("1" if pred_true(p, ray) else "0" for p in preds)
    f = lambda v: "-" if v is None else str(v)
    return "%s%s%d:%s:%s:%s:%s;" % (t, sc, tir, f(obj), f(mat), f(light), bits)


# ---- the checks ----


def sampled(x0, y0, x1, y1, k):
    """The crop's pixels, one in GG_TEST_SAMPLE, from the k-th on."""
    n = max(1, int(os.environ.get("GG_TEST_SAMPLE", "1")))
    every = [(x, y) for y in range(y0, y1) for x in range(x0, x1)]
    return set(p for i, p in enumerate(every) if (i + k) % n == 0)


def run(args):
    return subprocess.run(args, check=True, stdout=subprocess.PIPE, universal_newlines=True).stdout


def doc_examples(path):
    rows = []
    for line in open(path, encoding="utf-8"):
        m = re.match(r"^\| `([^`]+)` \| (\d+) \| (\d+) \| (\d+) \|", line.replace("\\|", "\x00"))
        if m:
            rows.append((m.group(1).replace("\x00", "|"), [int(m.group(k)) for k in (2, 3, 4)]))
    return rows


def main():
    ggrt, doc, scenes = sys.argv[1], sys.argv[2], sys.argv[3:]
    examples = doc_examples(doc)
    fails = 0
    if len(examples) < 10:
        print("FAIL docs: %d examples in the table of %s" % (len(examples), doc))
        return 1
    exprs = [(e, compile_lpe(e)) for e, _ in examples]
    for si, scene in enumerate(scenes):
        name = scene.split("/")[-1]
        x0, y0, x1, y1 = (0, 0, 24, 18) if name == "glass.nff" else CROP
        crop = "%d,%d,%d,%d" % (x0, y0, x1, y1)
        want = {e: {} for e, _ in exprs}
        pixels = sampled(x0, y0, x1, y1, si)
        for x, y in sorted(pixels):
            d = json.loads(run([ggrt, "trace", scene, "-s", SIZE, "--pixel", "%d,%d" % (x, y),
                                "-f", "json"]))
            ps = list(paths(d))
            total = sum(d["color"])
            for e, (rx, preds) in exprs:
                got = [v for evs, v in ps if rx.fullmatch("".join(token(ev, preds) for ev in evs))]
                if got:
                    ok = total != 0 and math.isfinite(total)
                    want[e][(x, y)] = sum(got) / total if ok else 0.0
        n = max(1, int(os.environ.get("GG_TEST_SAMPLE", "1")))
        for ei, (e, _) in enumerate(exprs):
            # one expression in GG_TEST_SAMPLE per scene, rotating: each
            # expression's find still runs on some scenes, each scene's on some
            if (si + ei) % n:
                continue
            f = json.loads(run([ggrt, "find", scene, "-s", SIZE, "--crop", crop, "--path", e,
                                "--limit", "0", "-f", "json", "-q"]))
            every = {tuple(m["pixel"]): m["share"] for m in f["matches"]}
            got = {p: v for p, v in every.items() if p in pixels}
            bad = [p for p in set(got) | set(want[e])
                   if p not in got or p not in want[e] or abs(got[p] - want[e][p]) > 1e-9]
            what = "%s %s over %s: %d pixels" % (name, e, crop, len(want[e]))
            if len(pixels) < (x1 - x0) * (y1 - y0):
                what += " of %d traced" % len(pixels)
            if bad or f["matched"] != len(every) or len(got) != len(want[e]):
                fails += 1
                print("FAIL %s; find says %d; first differences %s" % (what, f["matched"], bad[:3]))
            else:
                print("ok   %s, find agrees (pixels and shares)" % what)
    for k, scene in enumerate(DOC_SCENES):
        path = "examples/scenes/" + scene
        before = fails
        for e, counts in examples:
            f = json.loads(run([ggrt, "find", path, "-s", SIZE, "--path", e, "--limit", "1", "-f",
                                "json", "-q"]))
            if f["matched"] != counts[k]:
                fails += 1
                print("FAIL docs: %s on %s: find says %d, the table %d" % (e, scene, f["matched"],
                                                                          counts[k]))
        if fails == before:
            print("ok   docs: the %d examples' counts on %s" % (len(examples), scene))
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
