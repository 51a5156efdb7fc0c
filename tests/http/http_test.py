# SPDX-License-Identifier: MIT
"""HTTP test of `ggrt serve` (docs/serve.md): starts the server on a free
port and checks every route, the token and Host checks, the limits, the
errors (always JSON with the HTTP status), /api/trace against
`ggrt trace --format json`, concurrent requests, and that shutdown leaves
nothing behind. Standard library only (http.client).
    python3 tests/http/http_test.py build/ggrt
Prints TAP (tests/http/tap.py)."""
import http.client
import json
import math
import os
import re
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
import urllib.parse
import xml.dom.minidom
import zlib

import tap
# Every scene file the loops serve, and JSON without NaN: the scene suite's.
from http_scenes_test import scene_files, strict  # noqa: E402

GGRT = os.path.abspath(sys.argv[1]) if len(sys.argv) > 1 else "build/ggrt"
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(ROOT, "examples", "scenes", "glass.nff")
SIZE = (160, 120)
ok, bad = tap.ok, tap.bad


def check(cond, name, detail=""):
    (ok if cond else lambda n: bad(n, detail))(name)
    return cond


SERVERS = []  # every server started, stopped at the end whatever happened


class Server:
    def __init__(self, args, cwd, env=None, wrap=()):
        self.proc = subprocess.Popen(list(wrap) + [GGRT, "serve"] + args, cwd=cwd, env=env,
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        SERVERS.append(self.proc)
        self.url = self.proc.stdout.readline().strip()
        m = re.match(r"^http://127\.0\.0\.1:(\d+)/\?token=([0-9a-f]{32})$", self.url)
        if not m:
            err = self.proc.stderr.read() if self.proc.poll() is not None else ""
            raise RuntimeError("no URL printed: %r %s" % (self.url, err))
        self.port, self.token = int(m.group(1)), m.group(2)

    def conn(self):
        return http.client.HTTPConnection("127.0.0.1", self.port, timeout=120)

    def get(self, path, token=True, headers=None, conn=None):
        """GET path (the token as query parameter unless token is False or a
        string to use instead); returns (status, headers, body bytes)."""
        if token is not False:
            path += ("&" if "?" in path else "?") + "token=" + (self.token if token is True else token)
        c = conn or self.conn()
        c.request("GET", path, headers=headers or {})
        r = c.getresponse()
        body = r.read()
        if not conn:
            c.close()
        return r.status, {k.lower(): v for k, v in r.getheaders()}, body

    def json(self, path, **kw):
        st, h, b = self.get(path, **kw)
        return st, json.loads(b.decode())

    def wait(self, path):
        """Poll a render route until it answers 200."""
        for _ in range(6000):
            st, h, b = self.get(path)
            if st != 202:
                return st, h, b
            time.sleep(0.05)
        raise RuntimeError("render never finished: " + path)

    def stop(self, sig=signal.SIGINT, timeout=60):
        self.proc.send_signal(sig)
        try:
            rc = self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            rc = "hung"
        return rc, self.proc.stderr.read()


def json_error(st, h, b, want, name):
    """A refusal: status want, a JSON body {"status": want, "error": text}."""
    try:
        j = json.loads(b.decode())
        good = (st == want and h.get("content-type") == "application/json" and j.get("status") == want
                and isinstance(j.get("error"), str) and j["error"])
    except ValueError:
        good, j = False, b[:200]
    return check(good, name, "got %s %r" % (st, j))


def png_pixels(data):
    """Decode an 8-bit RGB PNG (any filter) to (w, h, bytes)."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    i, idat, w, h = 8, b"", 0, 0
    while i < len(data):
        n, = struct.unpack(">I", data[i:i + 4])
        t, c = data[i + 4:i + 8], data[i + 8:i + 8 + n]
        if zlib.crc32(data[i + 4:i + 8 + n]) != struct.unpack(">I", data[i + 8 + n:i + 12 + n])[0]:
            raise ValueError("bad CRC in " + t.decode())
        if t == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", c[:10])
            assert depth == 8 and ctype == 2, "not 8-bit RGB"
        elif t == b"IDAT":
            idat += c
        i += 12 + n
    raw, stride, out, prev = zlib.decompress(idat), w * 3, bytearray(), bytearray(w * 3)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - 3] if x >= 3 else 0
            b, c = prev[x], (prev[x - 3] if x >= 3 else 0)
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        out += line
        prev = line
    return w, h, bytes(out)


def cli(*args, ok=(0,)):
    """ggrt's standard output; exit codes other than ok raise."""
    r = subprocess.run([GGRT] + list(args), stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    if r.returncode not in ok:
        raise RuntimeError("ggrt %s: %s" % (" ".join(args), r.stderr.decode()))
    return r.stdout


def size_args():
    return ["-s", "%dx%d" % SIZE]


# ---- the checks ----

def check_pages(s):
    st, h, b = s.get("/")
    check(st == 200 and h["content-type"].startswith("text/html") and
          ("app.js?token=" + s.token).encode() in b and b"@TOKEN@" not in b,
          "/ serves the page with the token in its links")
    check("default-src 'none'" in h.get("content-security-policy", "") and
          h.get("x-content-type-options") == "nosniff" and h.get("cache-control") == "no-store" and
          h.get("referrer-policy") == "no-referrer", "security headers (CSP, nosniff, no-store, no-referrer)")
    for path, typ, needle in (("/app.js", "text/javascript", b"'use strict'"),
                              ("/view3d.js", "text/javascript", b"'use strict'"),
                              ("/links.js", "text/javascript", b"'use strict'"),
                              ("/export.js", "text/javascript", b"'use strict'"),
                              ("/app.css", "text/css", b"box-sizing")):
        st, h, b = s.get(path)
        check(st == 200 and h["content-type"].startswith(typ) and needle in b, path)
    st, h, b = s.get("/favicon.ico")
    json_error(st, h, b, 404, "an unknown page is 404 JSON")
    st, h, b = s.get("/", headers={"Authorization": "Bearer " + s.token}, token=False)
    check(st == 200, "Authorization: Bearer works as well as ?token=")
    check_keepalive(s)


def check_keepalive(s):
    """HTTP/1.1 keep-alive: three requests on one socket, each answered
    without Connection: close."""
    sk = socket.create_connection(("127.0.0.1", s.port), timeout=30)
    f = sk.makefile("rb")
    heads = []
    try:
        for path in ("/api/info", "/api/trace?x=44&y=40", "/app.css"):
            sk.sendall(("GET %s%stoken=%s HTTP/1.1\r\nHost: 127.0.0.1:%d\r\n\r\n"
                        % (path, "&" if "?" in path else "?", s.token, s.port)).encode())
            head = b""
            while not head.endswith(b"\r\n\r\n"):
                line = f.readline()
                if not line:
                    raise OSError("closed by the server")
                head += line
            n = int(re.search(rb"(?i)content-length: *(\d+)", head).group(1))
            f.read(n)
            heads.append(head)
        good = all(h.startswith(b"HTTP/1.1 200") and b"connection: close" not in h.lower() for h in heads)
    except OSError as e:
        good, heads = False, heads + [repr(e).encode()]
    finally:
        f.close()
        sk.close()
    check(good, "keep-alive: 3 requests answered on one connection, none says Connection: close",
          b"\n".join(heads).decode(errors="replace")[:1500])


def check_info(s):
    st, j = s.json("/api/info")
    check(st == 200 and j["width"] == SIZE[0] and j["height"] == SIZE[1] and j["scene"] == SCENE and
          any(e["name"] == "refraction" for e in j["effects"]) and j["limits"]["max_depth"] == 16 and
          j["options"] == "size=%dx%d" % SIZE, "/api/info: size, scene, effects, options, limits", j)
    st, j = s.json("/api/scene")
    check(st == 200 and len(j["shapes"]) == 3 and j["shapes"][1]["kind"] == "sphere" and
          len(j["materials"]) == 3, "/api/scene: shapes and materials", j)
    check(st == 200 and [L["position"] for L in j["lights"]] == [[3, -3, 6], [-4, -2, 5]] and
          j["meshes"] == [] and j["triangles"] == 0 and j["simplified"] is False,
          "/api/scene: the lights (glass.nff lines 16, 17), no mesh triangles", j)


def check_render_stats(s):
    """The job's ray counts are ggrt render's, with the shadow verdicts
    (glass.nff's kt 1 spheres block nothing unless shadows are opaque).
    Last: it leaves another render as the server's current one."""
    for q, args in (("?opts=shadows%3Dopaque", ["-a", "shadows=opaque"]), ("?opts=corners", ["--corners"]),
                    ("?opts=spd", ["--spd"]), ("", [])):
        st, h, b = s.wait("/api/render" + q)
        stats = json.loads(b)["job"].get("stats", {})
        with tempfile.TemporaryDirectory() as d:
            out = cli("render", SCENE, *size_args(), *args, "-o", os.path.join(d, "r.exr")).decode()
        m = re.search(r"^rays: eye (\d+) .*, shadow (\d+) \(blocked (\d+), attenuated (\d+)\)",
                      out, re.M)
        keys = ("eye", "shadow", "shadow_blocked", "shadow_attenuated")
        check(st == 200 and m is not None and [stats.get(k) for k in keys] == [int(v) for v in m.groups()],
              "/api/render%s: the stats count the shadow verdicts as ggrt render %s does"
              % (q, " ".join(args)), (out, stats))


def check_render(s):
    st, h, b = s.wait("/api/render")
    j = json.loads(b)
    check(st == 200 and j["job"]["state"] == "done" and j["job"]["total"] == SIZE[0] * SIZE[1],
          "/api/render reaches done", j)
    st, h, png = s.wait("/api/image")
    with tempfile.TemporaryDirectory() as d:
        cli("render", SCENE, *size_args(), "-q", "-o", os.path.join(d, "r.png"))
        with open(os.path.join(d, "r.png"), "rb") as f:
            ref = png_pixels(f.read())
    got = png_pixels(png)
    check(st == 200 and h["content-type"] == "image/png" and got == ref,
          "/api/image PNG has the pixels of ggrt render -o x.png")
    st, h, f32 = s.wait("/api/image?format=f32")
    check(st == 200 and len(f32) == SIZE[0] * SIZE[1] * 12 and h.get("x-ggrt-size") == "%dx%d" % SIZE,
          "/api/image?format=f32: 3 little-endian floats a pixel")
    return struct.unpack("<%df" % (SIZE[0] * SIZE[1] * 3), f32), j["job"]["stats"]


def check_trace(s, rgb):
    pixels = [(44, 40), (0, 0), (80, 60), (159, 119), (70, 20), (100, 90)]
    for x, y in pixels:
        ref = cli("trace", SCENE, "--pixel", "%d,%d" % (x, y), "--format", "json", *size_args())
        st, h, b = s.get("/api/trace?x=%d&y=%d" % (x, y))
        check(st == 200 and b == ref, "/api/trace %d,%d equals ggrt trace --format json" % (x, y),
              "status %d, %d vs %d bytes" % (st, len(b), len(ref)))
        c = json.loads(b)["color"]
        i = 3 * (y * SIZE[0] + x)
        check(tuple(struct.unpack("<3f", struct.pack("<3f", *c))) == rgb[i:i + 3],
              "/api/trace %d,%d colour equals the image's pixel" % (x, y))
    for q, args in (("opts=depth%3D3", ["-d", "3"]), ("opts=samples%3D4&sample=2", ["-n", "4", "--sample", "2"]),
                    ("opts=samples%3D4", ["-n", "4"]), ("opts=spd", ["--spd"]),
                    ("opts=force-effects", ["--force-effects"]),
                    ("opts=refract%3Dtextbook+fresnel%3Dschlick", ["-a", "refract=textbook,fresnel=schlick"]),
                    ("opts=depth%3D2,sphere%3Dtextbook,cutoff%3D0.01", ["-d", "2", "-a", "sphere=textbook,cutoff=0.01"])):
        ref = cli("trace", SCENE, "--pixel", "44,40", "--format", "json", *size_args(), *args)
        st, h, b = s.get("/api/trace?x=44&y=40&" + q)
        check(st == 200 and b == ref, "/api/trace ?%s equals ggrt trace %s" % (q, " ".join(args)))
    ref = cli("trace", SCENE, "--pixel", "44,40", "--ascii", *size_args())
    st, h, b = s.get("/api/trace?x=44&y=40&format=text")
    check(st == 200 and b.replace("\u2502".encode(), b"|") and b"tir #" in b and
          b.decode().split("\n")[:3] == ref.decode().split("\n")[:3],
          "/api/trace?format=text: the text tree")
    st, h, b = s.get("/api/trace?x=44&y=40&format=svg")
    try:
        xml.dom.minidom.parseString(b)
        good = st == 200 and h["content-type"] == "image/svg+xml" and b"top view" in b
    except Exception as e:  # noqa: BLE001 -- any parse failure fails the check
        good = False
    check(good, "/api/trace?format=svg parses as XML with the top view")
    st, j = s.json("/api/trace?x=44&y=40")
    led = j.get("ledger", {})
    check(st == 200 and led.get("holds") is True and led.get("terms"), "/api/trace carries the ledger, which holds")


def check_heatmaps(s, stats):
    st, h, b = s.wait("/api/image?kind=rays&format=f32")
    rays = struct.unpack("<%df" % (SIZE[0] * SIZE[1]), b)
    total = stats["eye"] + stats["reflect"] + stats["refract"] + stats["shadow"]
    check(st == 200 and abs(sum(rays) - total) < 0.5, "rays heatmap sums to the render's rays",
          "%s vs %s" % (sum(rays), total))
    st, j = s.json("/api/trace?x=44&y=40")
    want = sum(j["stats"][k] for k in ("eye", "reflect", "refract", "shadow"))
    check(rays[40 * SIZE[0] + 44] == want, "rays heatmap at 44,40 equals the pixel's traced rays",
          "%s vs %s" % (rays[40 * SIZE[0] + 44], want))
    for kind in ("rays", "depth", "time"):
        st, h, b = s.wait("/api/image?kind=%s" % kind)
        w, hh, px = png_pixels(b)
        check(st == 200 and w == SIZE[0] and hh > SIZE[1] and float(h.get("x-ggrt-max", "-1")) > 0,
              "/api/image?kind=%s: the heatmap with its legend" % kind)
    # The scale's top (cli/common/heatmap.h): the largest value for counts;
    # for times the largest, or the 99.9th percentile of the positive
    # values (rounded up within 1/16) where the largest is over 4 times it.
    for kind in ("rays", "time"):
        st, h, b = s.wait("/api/image?kind=%s&format=f32" % kind)
        v = struct.unpack("<%df" % (SIZE[0] * SIZE[1]), b)
        st2, h2, _ = s.wait("/api/image?kind=%s" % kind)
        top, mx = f32(float(h2.get("x-ggrt-top", "nan"))), f32(float(h2.get("x-ggrt-max", "nan")))
        pos = sorted(x for x in v if x > 0)
        q = pos[len(pos) - len(pos) // 1000 - 1] if pos else 0
        if kind == "rays":
            good = top == mx == max(v)
        elif top < mx:
            good = q <= top <= q * (1 + 1 / 16.0) and mx == max(v) and mx > 4 * q
        else:
            good = top == mx == max(v) and mx <= 4 * q * (1 + 1 / 16.0)
        check(st == st2 == 200 and good, "/api/image?kind=%s: the scale's top %g (largest %g, 99.9th percentile %g)"
              % (kind, top, mx, q))
    st, h, b = s.wait("/api/image?kind=depth&format=f32")
    depth = struct.unpack("<%df" % (SIZE[0] * SIZE[1]), b)
    check(st == 200 and max(depth) == 5 and min(depth) >= 1, "depth heatmap: 1 to the limit 5",
          "%s..%s" % (min(depth), max(depth)))


def check_debug(s):
    """find, check, diff and compare against the command line's JSON."""
    where = "some(kind == tir)"
    q = "where=" + urllib.parse.quote(where)
    st, h, b = s.wait("/api/find?" + q)
    ref = cli("find", SCENE, *size_args(), "--where", where, "--format", "json", "-q")
    check(st == 200 and b == ref, "/api/find equals ggrt find --format json", "%d: %s" % (st, b[:300]))
    j = json.loads(b)
    st, h, mask = s.wait("/api/find?%s&format=mask" % q)
    check(st == 200 and len(mask) == SIZE[0] * SIZE[1] and sum(mask) == j["matched"] > 0,
          "/api/find?format=mask: one byte a pixel, as many set as matched (%d)" % j["matched"])
    st, h, b = s.wait("/api/find?%s&limit=3&opts=depth%%3D2" % q)
    ref = cli("find", SCENE, *size_args(), "--where", where, "--format", "json", "-q", "--limit", "3", "-d", "2")
    check(st == 200 and b == ref, "/api/find with a limit and options equals ggrt find's")
    st, h, b = s.get("/api/find?where=" + urllib.parse.quote("some(kind == tri)"))
    json_error(st, h, b, 400, "a predicate with a syntax error: 400")
    check(b"1:14:" in b, "the predicate's error says where (1:14)", b)
    for bad, name in (("", "an empty predicate"), ("some(", "an unclosed one"), ("x" * 600, "a 600-byte one"),
                      ("some(kind == tir) &&", "a dangling &&")):
        st, h, b = s.get("/api/find?where=" + urllib.parse.quote(bad))
        json_error(st, h, b, 400, "find: %s is 400" % name)
    st, h, b = s.get("/api/find")
    json_error(st, h, b, 400, "find without where: 400")
    st, j = s.json("/api/parse?where=" + urllib.parse.quote("some(kind == tri)") + "&opts=depth%3D99")
    check(st == 200 and j["where"]["valid"] is False and j["where"]["line"] == 1 and j["where"]["column"] == 14
          and j["opts"]["valid"] is False, "/api/parse: 200 with where and why for bad texts", j)
    st, j = s.json("/api/parse?where=" + urllib.parse.quote(where))
    check(st == 200 and j == {"where": {"valid": True}}, "/api/parse of a good predicate", j)
    st, h, b = s.wait("/api/check")
    ref = cli("check", SCENE, *size_args(), "--format", "json", "-q", ok=(0, 4))  # 4: an invariant fails
    check(st in (200,) and b == ref, "/api/check equals ggrt check --format json", b[:200])
    st, h, b = s.get("/api/check?x=44&y=40")
    ref = cli("check", SCENE, *size_args(), "--crop", "44,40,45,41", "--format", "json", "-q", ok=(0, 4))
    check(st == 200 and b == ref, "/api/check?x=44&y=40 equals ggrt check --crop 44,40,45,41")
    st, h, b = s.wait("/api/diff?b=depth%3D2")
    ref = cli("diff", SCENE, *size_args(), "--b", "depth=2", "--format", "json", "-q")
    check(st == 200 and b == ref, "/api/diff?b=depth=2 equals ggrt diff --b depth=2 --format json", b[:300])
    j = json.loads(b)
    check(0 < j["value_differ"] < j["scanned"], "the diff finds pixels that differ (%d)" % j["value_differ"])
    st, h, b = s.wait("/api/diff?b=depth%3D2&format=map")
    check(st == 200 and sum(1 for v in b if v) == max(j["value_differ"], j["tree_differ"]),
          "/api/diff?format=map: as many pixels marked as differ")
    st, h, b = s.wait("/api/diff?b=depth%3D2&format=f32")
    d = struct.unpack("<%df" % (SIZE[0] * SIZE[1]), b)
    check(st == 200 and max(d) == struct.unpack("<f", struct.pack("<f", j["max_delta"]))[0],
          "/api/diff?format=f32: the largest difference is max_delta (as a float)",
          "%s vs %s" % (max(d), j["max_delta"]))
    st, h, b = s.wait("/api/diff?b=depth%3D2&format=png")
    check(st == 200 and png_pixels(b)[0] == SIZE[0], "/api/diff?format=png: the difference as a heatmap")
    st, h, b = s.wait("/api/diff?b=sphere%3Dtextbook&limit=2")
    ref = cli("diff", SCENE, *size_args(), "--b", "sphere=textbook", "--format", "json", "-q", "--worst", "2")
    check(st == 200 and b == ref, "/api/diff of a geometry knob (one scene, both knobs) equals ggrt diff's")
    st, j = s.json("/api/compare?x=44&y=40&b=depth%3D2")
    check(st == 200 and j["differ"] is True and j["first"]["what"] == "stop" and j["text"].startswith("ray #"),
          "/api/compare names the first divergent ray", j)
    st, h, b = s.get("/api/compare?x=44&y=40&b=depth%3D2&format=text")
    ref = cli("trace", SCENE, *size_args(), "--pixel", "44,40", "--diff", "--b", "depth=2")
    check(st == 200 and b == ref, "/api/compare?format=text equals ggrt trace --diff", b[:300])


def f32(v):
    return struct.unpack("<f", struct.pack("<f", v))[0]


def check_paths(s):
    """Light-path expressions: /api/find?path=, its mask and share map,
    /api/trace?path=, /api/parse?path=, against ggrt find and trace --path."""
    n = SIZE[0] * SIZE[1]
    for lpe in ("C<TS>.*", "C.*<RS'tir'>.*", "C<RD>L"):
        q = "path=" + urllib.parse.quote(lpe)
        st, h, b = s.wait("/api/find?" + q)
        ref = cli("find", SCENE, *size_args(), "--path", lpe, "--format", "json", "-q")
        check(st == 200 and b == ref, "/api/find?path=%s equals ggrt find --path --format json" % lpe,
              "%d: %s" % (st, b[:300]))
        full = json.loads(cli("find", SCENE, *size_args(), "--path", lpe, "--format", "json", "-q",
                              "--limit", str(n)))
        st, h, mask = s.wait("/api/find?%s&format=mask" % q)
        st2, h2, b = s.wait("/api/find?%s&format=share" % q)
        share = struct.unpack("<%df" % n, b) if st2 == 200 and len(b) == 4 * n else ()
        want = {(m["pixel"][1] * SIZE[0] + m["pixel"][0]): m["share"] for m in full["matches"]}
        got = {i: v for i, v in enumerate(share) if v != 0}
        same = (len(want) == full["matched"] > 0 and sum(mask) == full["matched"] and
                all(mask[i] == 1 for i in want) and set(got) <= set(want) and
                all(share[i] == struct.unpack("<f", struct.pack("<f", v))[0] for i, v in want.items()))
        check(st == 200 and same, "/api/find?path=%s: mask and share map (float) equal ggrt find --path's "
              "%d matches and shares" % (lpe, full["matched"]), "%d pixels with a share, %d want" % (len(got), len(want)))
        st, h, b = s.wait("/api/find?%s&format=png" % q)
        w, hh, px = png_pixels(b)
        check(st == 200 and w == SIZE[0] and hh > SIZE[1] and
              f32(float(h.get("x-ggrt-max", "-1"))) == max(struct.unpack("<f", struct.pack("<f", v))[0] for v in want.values()),
              "/api/find?path=%s&format=png: the share heatmap with its legend, max %s" % (lpe, h.get("x-ggrt-max")))
        for x, y in ((44, 40), (80, 60), (100, 90)):
            ref = cli("trace", SCENE, *size_args(), "--pixel", "%d,%d" % (x, y), "--path", lpe, "--format", "json")
            st, h, b = s.get("/api/trace?x=%d&y=%d&%s" % (x, y, q))
            check(st == 200 and b == ref, "/api/trace %d,%d path=%s equals ggrt trace --path --format json"
                  % (x, y, lpe), b[:300])
    ref = cli("trace", SCENE, *size_args(), "--pixel", "44,40", "--path", "C<TS>.*")
    st, h, b = s.get("/api/trace?x=44&y=40&format=text&path=" + urllib.parse.quote("C<TS>.*"))
    check(st == 200 and b == ref, "/api/trace?format=text&path= equals ggrt trace --path", b[:300])
    # A find with a path is another job than one with a predicate, and the
    # share of the whole pixel (C.*) is 1 on every pixel with a path.
    st, h, b = s.wait("/api/find?format=share&path=" + urllib.parse.quote("C.*"))
    share = struct.unpack("<%df" % n, b)
    check(st == 200 and all(v == 0 or abs(v - 1) < 1e-6 for v in share) and sum(1 for v in share if v) > n // 2,
          "/api/find?path=C.*: the share is 1 wherever a path is")
    for bad in ("C<X>", "C(", "C<TS>[object ==]", "C{", "C<TS>'"):
        r = subprocess.run([GGRT, "find", SCENE, "--path", bad], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           text=True)
        want = r.stderr.split("\n")[0].replace("ggrt find: --path:", "path:")
        for route in ("/api/find?path=", "/api/trace?x=1&y=1&path="):
            st, h, b = s.get(route + urllib.parse.quote(bad))
            json_error(st, h, b, 400, "%s%s is 400" % (route, bad))
            err = json.loads(b).get("error", "")
            check(r.returncode != 0 and re.match(r"^path:1:\d+: ", err) and err == want,
                  "%s%s: the error names the column, as ggrt find --path's (%s)" % (route, bad, err),
                  "%r vs %r" % (err, want))
        st, j = s.json("/api/parse?path=" + urllib.parse.quote(bad))
        check(st == 200 and j["path"]["valid"] is False and j["path"]["line"] == 1 and j["path"]["column"] >= 1
              and j["path"]["error"].startswith("1:%d:" % j["path"]["column"]),
              "/api/parse?path=%s: invalid at column %d" % (bad, j["path"]["column"]), j)
    st, j = s.json("/api/parse?path=" + urllib.parse.quote("C<TS>.*B"))
    check(st == 200 and j == {"path": {"valid": True}}, "/api/parse of a good path", j)
    for q, name in (("where=x&path=C.*", "both where and path"), ("path=" + "C" * 600, "a 600-byte path"),
                    ("where=" + urllib.parse.quote("some(kind == tir)") + "&format=share", "format=share of a predicate"),
                    ("where=" + urllib.parse.quote("some(kind == tir)") + "&format=png", "format=png of a predicate")):
        st, h, b = s.get("/api/find?" + q)
        json_error(st, h, b, 400, "find with %s: 400" % name)
    for q, name in (("sample=0", "one sample"), ("format=svg", "format=svg")):
        st, h, b = s.get("/api/trace?x=1&y=1&path=C.*&" + q)
        json_error(st, h, b, 400, "trace with a path and %s: 400" % name)


def check_security(s):
    st, h, b = s.get("/api/info", token=False)
    json_error(st, h, b, 401, "no token: 401")
    check("bearer" in h.get("www-authenticate", "").lower(), "401 names the Bearer scheme")
    st, h, b = s.get("/", token=False)
    json_error(st, h, b, 401, "no token for the page: 401")
    st, h, b = s.get("/api/info", token="0" * 32)
    json_error(st, h, b, 403, "wrong token: 403")
    st, h, b = s.get("/api/info", token=s.token[:-1])
    json_error(st, h, b, 403, "a token one digit short: 403")
    st, h, b = s.get("/api/info", token=False, headers={"Authorization": "Bearer " + "f" * 32})
    json_error(st, h, b, 403, "wrong bearer token: 403")
    st, h, b = s.get("/api/info?token=%s%%00junk" % s.token, token=False)
    json_error(st, h, b, 400, "a NUL after the token: 400, not cut to the token")
    for q in ("?token=", "?token"):
        st, h, b = s.get("/api/info" + q, token=False, headers={"Authorization": "Bearer " + s.token})
        check(st == 200, "an empty %s counts as none: the Bearer header is used (200)" % q, (st, b[:200]))
    st, h, b = s.get("/api/info?token=", token=False)
    json_error(st, h, b, 401, "an empty ?token= and no header: 401")
    st, h, b = s.get("/api/info", token=False, headers={"Authorization": "Basic " + s.token})
    json_error(st, h, b, 401, "another auth scheme: 401")
    for host in ("evil.example:%d" % s.port, "127.0.0.1:%d" % (s.port + 1), "127.0.0.1",
                 "localhost.evil.example:%d" % s.port, "127.0.0.2:%d" % s.port, "[::1]:%d" % s.port,
                 "127.0.0.1:%d@evil" % s.port, "", "127.0.0.1:%d" % (s.port + 2 ** 32),
                 "127.0.0.1:%d" % (s.port + 2 ** 16), "[127.0.0.1]:%d" % s.port, "127.0.0.1:-%d" % s.port):
        st, h, b = s.get("/api/info", headers={"Host": host})
        json_error(st, h, b, 403, "foreign Host %r: 403" % host)
    for host in ("127.0.0.1:%d" % s.port, "localhost:%d" % s.port, "LOCALHOST:%d" % s.port):
        st, h, b = s.get("/api/info", headers={"Host": host})
        check(st == 200, "own Host %r accepted" % host)
    # HTTP/1.0 without a Host header.
    sk = socket.create_connection(("127.0.0.1", s.port), timeout=30)
    sk.sendall(("GET /api/info?token=%s HTTP/1.0\r\n\r\n" % s.token).encode())
    raw = b""
    while True:
        chunk = sk.recv(65536)
        if not chunk:
            break
        raw += chunk
    sk.close()
    head, _, body = raw.partition(b"\r\n\r\n")
    st = int(head.split()[1])
    json_error(st, {"content-type": "application/json"}, body, 403, "no Host header (HTTP/1.0): 403")
    c = s.conn()
    c.request("POST", "/api/info?token=" + s.token, body=b"x" * 100)
    r = c.getresponse()
    json_error(r.status, {k.lower(): v for k, v in r.getheaders()}, r.read(), 405, "POST: 405")
    c.close()
    # No request parameter names a file.
    for path, want in (("/api/trace?x=1&y=1&scene=/etc/passwd", 400), ("/api/image?file=/etc/passwd", 400),
                       ("/api/trace?x=1&y=1&opts=texture%3D/etc/passwd", 400),
                       ("/api/trace?x=1&y=1&opts=scene%3D/etc/passwd", 400),
                       ("/api/info?path=/etc/passwd", 400), ("/../../../etc/passwd", 404),
                       ("/%2e%2e/%2e%2e/etc/passwd", 404), ("/app.js/../../etc/passwd", 404),
                       ("//etc/passwd", 404), ("/api/trace?x=1&y=1&texture=/etc/passwd", 400)):
        st, h, b = s.get(path)
        json_error(st, h, b, want, "refused: %s -> %d" % (path, want))
        check(b"root:" not in b, "no file content in the answer to " + path)


def raw_answer(s, data, wait):
    """Send data on a new socket; the answer's status line and whether the
    server closed the connection, within wait seconds (None, False when
    it said nothing)."""
    sk = socket.create_connection(("127.0.0.1", s.port), timeout=wait)
    got, closed = b"", False
    try:
        sk.sendall(data)
        while True:
            chunk = sk.recv(65536)
            if not chunk:
                closed = True
                break
            got += chunk
    except OSError:
        pass
    finally:
        sk.close()
    return (got.split(b"\r\n")[0] if got else None), closed


def check_request_body(s):
    """No route takes a body: a request announcing one is refused at once
    and its connection closed, whether or not it has the Host and the
    token, so nobody holds a connection by dripping a body (before: the
    server read 100 MB of body a byte at a time and never answered)."""
    auth = "Host: 127.0.0.1:%d\r\nAuthorization: Bearer %s\r\n" % (s.port, s.token)
    for name, head in (("a Content-Length, no token", "GET / HTTP/1.1\r\nHost: x\r\n"
                        "Content-Length: 100000000\r\n\r\n"),
                       ("chunked, foreign Host", "GET /api/info HTTP/1.1\r\nHost: evil\r\n"
                        "Transfer-Encoding: chunked\r\n\r\n1\r\na\r\n"),
                       ("a Content-Length, authorised", "GET /api/info HTTP/1.1\r\n" + auth +
                        "Content-Length: 100000000\r\n\r\na")):
        t = time.time()
        line, closed = raw_answer(s, head.encode(), 3)
        dt = time.time() - t
        check(line is not None and line.startswith(b"HTTP/1.1 413") and closed and dt < 2,
              "a GET with a body (%s): 413 and closed at once (%.2f s)" % (name, dt), (line, closed))
    line, closed = raw_answer(s, ("GET /api/info HTTP/1.1\r\n" + auth + "Content-Length: 0\r\n"
                                  "Connection: close\r\n\r\n").encode(), 10)
    check(line is not None and line.startswith(b"HTTP/1.1 200"), "Content-Length: 0 is no body: 200", line)


def check_record_bound(s):
    """A find, check or diff records every pixel's trees with the library's
    allocator: options whose trees could pass the per-pixel bound are 413
    before any work (before: /api/check?x=&y= with depth 16, 64 samples
    and ray budget 2^24 took 536 MB on nested-glass.nff, a find 1 GB)."""
    heavy = urllib.parse.quote("depth=16 samples=64 ray-budget=16777216")
    for path in ("/api/check?x=44&y=40&opts=" + heavy, "/api/check?opts=" + heavy,
                 "/api/find?where=some(kind%3D%3Dtir)&opts=" + heavy, "/api/diff?b=" + heavy,
                 "/api/diff?opts=" + heavy):
        t = time.time()
        st, h, b = s.get(path)
        json_error(st, h, b, 413, "%s: 413 at once (%.2f s)" % (path, time.time() - t))
        check(b"64 MiB" in b and b"ray-budget" in b, "its message names the bound and the way out", b[:300])
    st, j = s.json("/api/check?x=44&y=40&opts=" + urllib.parse.quote("depth=16 samples=64"))
    check(st == 200 and j.get("ggrt_check") == 1, "depth 16, 64 samples, the default budget: still checked",
          (st, str(j)[:200]))
    st, j = s.json("/api/info")
    check(j["limits"].get("record_bytes") == 64 << 20, "/api/info: limits.record_bytes", j["limits"])


def check_find_limit0(s):
    """limit=0 lists every match, as ggrt find --limit 0 does (before: none)."""
    for kind, expr in (("where", "some(kind == tir)"), ("path", "C<TS>.*")):
        st, h, b = s.wait("/api/find?limit=0&%s=%s" % (kind, urllib.parse.quote(expr)))
        ref = cli("find", SCENE, *size_args(), "--" + kind, expr, "--limit", "0", "--format", "json", "-q")
        j = json.loads(b) if st == 200 else {}
        check(st == 200 and b == ref and len(j["matches"]) == j["matched"] > 20,
              "/api/find?limit=0&%s= equals ggrt find --limit 0: all %s matches" % (kind, j.get("matched")),
              (st, len(j.get("matches", [])), b[:200]))


def check_parse_opts(s):
    """/api/parse says an option text is valid exactly when the routes take
    it: the server's limits and its size, threads and crop too (before:
    depth=17 was valid there and 400 everywhere else)."""
    for text in ("depth=17", "samples=65", "size=8x8", "threads=1", "crop=0,0,1,1", "refract=bogus",
                 "depth=16 samples=64", "spd"):
        q = urllib.parse.quote(text)
        st, j = s.json("/api/parse?opts=%s&b=%s" % (q, q))
        st2, h, b = s.get("/api/trace?x=1&y=1&opts=" + q)
        check(st == 200 and j["opts"]["valid"] == j["b"]["valid"] == (st2 == 200),
              "/api/parse?opts=%s: valid %s, as /api/trace answers %d" % (text, j["opts"]["valid"], st2), j)


def check_limit_message(s):
    """A depth or samples over the server's limit is refused naming that
    limit, where the text sets it (before: depth=99 said "from 1 to 64",
    the library's bound, though the server refuses above 16)."""
    for text, want in (("depth=99", "opts:1:7: depth must be a whole number from 1 to 16 here, got '99'"),
                       ("depth=17", "opts:1:7: depth must be a whole number from 1 to 16 here, got '17'"),
                       ("spd samples=5000", "opts:1:13: samples must be a whole number from 1 to 64 here, "
                        "got '5000'"),
                       ("samples=65 depth=17", "opts:1:9: samples must be a whole number from 1 to 64 here, "
                        "got '65'"),
                       ("refract=fast depth=99", "opts:1:9: refract must be accurate, textbook or exact, "
                        "got 'fast'")):
        st, h, b = s.get("/api/trace?x=1&y=1&opts=" + urllib.parse.quote(text))
        try:
            got = json.loads(b)["error"]
        except (ValueError, KeyError):
            got = b[:200]
        check(st == 400 and got == want, "opts=%s: 400 %r" % (text, got), "want %r" % want)


def check_too_large(s):
    """A tree over the recorder's 4 MiB: 413 saying the limit, where it
    stopped and the way out, for /api/trace and /api/compare alike
    (before: trace said "4096 rays recorded" against the docs' 10000, and
    compare "out of memory recording the ray tree")."""
    heavy = urllib.parse.quote("depth=16 samples=64")
    for path in ("/api/trace?x=44&y=40&opts=" + heavy, "/api/compare?x=44&y=40&b=" + heavy,
                 "/api/compare?x=44&y=40&opts=" + heavy):
        st, h, b = s.get(path)
        json_error(st, h, b, 413, "%s: 413" % path)
        check(b"the 4 MiB a trace may record: " in b and b"smaller depth" in b,
              "%s: the limit and the way out" % path, b[:300])


def check_bad_queries(s):
    cases = [
        ("/api/trace?y=1", 400, "missing x"),
        ("/api/trace?x=abc&y=1", 400, "x not a number"),
        ("/api/trace?x=1.5&y=1", 400, "x not whole"),
        ("/api/trace?x=-1&y=1", 400, "pixel left of the image"),
        ("/api/trace?x=%d&y=1" % SIZE[0], 400, "pixel right of the image"),
        ("/api/trace?x=1&y=%d" % SIZE[1], 400, "pixel below the image"),
        ("/api/trace?x=1&y=99999999999999999999", 400, "y overflows"),
        ("/api/trace?x=1&y=1&x=2", 400, "x given twice"),
        ("/api/trace?x=1&y=1&sample=7", 400, "a sample the pixel does not have"),
        ("/api/trace?x=1&y=1&format=xml", 400, "unknown format"),
        ("/api/trace?x=1&y=1&opts=depth%3D17", 400, "depth over the limit"),
        ("/api/trace?x=1&y=1&opts=depth%3D0x3", 400, "depth in hex"),
        ("/api/trace?x=1&y=1&opts=samples%3D65", 400, "samples over the limit"),
        ("/api/trace?x=1&y=1&opts=refract%3Dbogus", 400, "unknown knob value"),
        ("/api/trace?x=1&y=1&opts=cutoff%3Dnan", 400, "NaN knob"),
        ("/api/trace?x=1&y=1&opts=cutoff%3D-1", 400, "negative knob"),
        ("/api/trace?x=1&y=1&opts=spd%3Dmaybe", 400, "a flag with a value"),
        ("/api/trace?x=1&y=1&opts=bogus%3D1", 400, "an unknown setting"),
        ("/api/trace?x=1&y=1&opts=size%3D8x8", 400, "a request may not change the size"),
        ("/api/trace?x=1&y=1&opts=threads%3D1", 400, "nor the threads"),
        ("/api/trace?x=1&y=1&opts=crop%3D0,0,1,1", 400, "nor the crop"),
        ("/api/trace?x=1&y=1&depth=2", 400, "a setting as its own parameter"),
        ("/api/trace?x=1&y=1&b=depth%3D2", 400, "b outside diff and compare"),
        ("/api/diff?b=depth%3D99", 400, "a bad b"),
        ("/api/diff?limit=1001", 400, "diff's limit over 1000"),
        ("/api/find?where=x&limit=-1", 400, "a negative find limit"),
        ("/api/compare?x=1&y=999", 400, "compare outside the image"),
        ("/api/image?kind=heat", 400, "unknown heatmap kind"),
        ("/api/image?format=jpeg", 400, "unknown image format"),
        ("/api/diff?format=gif", 400, "unknown diff format"),
        ("/api/check?x=1", 400, "check with x but no y"),
        ("/api/check?format=text", 400, "check in another format"),
        ("/api/nothing", 404, "unknown route"),
        ("/api/trace?x=1&y=1&" + "&".join("p%d=1" % i for i in range(50)), 400, "too many parameters"),
        ("/api/trace?x=1&y=%s" % ("1" * 1100), 414, "a value over 1024 bytes"),
        ("/api/trace?x=1&y=1&pad=%s" % ("a" * 5000), 414, "a request target over 4096 bytes"),
        ("/api/trace?x=1&y=1&%ff%fe=1", 400, "a strange parameter name"),
        ("/api/trace?x=%00&y=1", 400, "a NUL in a value"),
        ("/api/info%00/../..", 400, "a NUL in the path"),
        ("/api/info?x%00y=1", 400, "a NUL in a parameter name"),
    ]
    st, h, b = s.get("/api/info?%s=1" % ("k" * 65))
    json_error(st, h, b, 414, "a 65-byte parameter name: 414")
    check(b"name" in b and b"longer than 64 bytes" in b, "its message says the name limit, 64", b[:200])
    st, h, b = s.get("/api/info?%s=1" % ("k" * 64))
    json_error(st, h, b, 400, "a 64-byte name is within the limit (unknown: 400)")
    for path, want, name in cases:
        st, h, b = s.get(path)
        json_error(st, h, b, want, "%s: %d" % (name, want))
    # Over the per-connection memory for the request head: libmicrohttpd
    # refuses it itself (not JSON), and the server stays up.
    st, h, b = s.get("/api/info?pad=" + "a" * 70000)
    check(400 <= st < 500, "a 70 kB request target: 4xx", "got %d" % st)
    st, h, b = s.get("/api/info", headers={"X-Big": "b" * 70000})
    check(400 <= st < 500, "a 70 kB header: 4xx", "got %d" % st)
    st, j = s.json("/api/info")
    check(st == 200, "still serving after the oversized requests")


def check_concurrent(s):
    """Traces from 8 threads while a long render runs: all answered, all
    equal to the answers given one at a time."""
    pix = [(x, y) for x in range(30, 130, 20) for y in range(20, 110, 30)]
    want = {p: s.get("/api/trace?x=%d&y=%d" % p)[2] for p in pix}
    s.get("/api/render?opts=samples%3D16")  # a slower render in the background
    errors, done = [], []

    def client(k):
        c = s.conn()
        try:
            for i in range(12):
                p = pix[(k * 7 + i) % len(pix)]
                st, h, b = s.get("/api/trace?x=%d&y=%d" % p, conn=c)
                if st != 200 or b != want[p]:
                    errors.append((p, st))
                done.append(1)
        except Exception as e:  # noqa: BLE001 -- report any failure
            errors.append(str(e))
        finally:
            c.close()

    ts = [threading.Thread(target=client, args=(k,)) for k in range(8)]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    check(not errors and len(done) == 96, "96 traces from 8 threads during a render: equal, no errors",
          errors[:5])


def check_tracing_first(work, env):
    """A click's tree never waits for an image: with depth 16 and 16
    samples on gears.nff (512x512), while that render runs, /api/trace of
    a pixel answers within 1 s. A job past --job-seconds fails, is
    reported once and is not kept as the answer: asking again runs it
    again. With every job slot busy, 503 with Retry-After."""
    gears = os.path.join(ROOT, "examples", "scenes", "spd", "gears.nff")
    try:
        s = Server([gears, "--port", "0", "--job-seconds", "1"], work, env)
    except RuntimeError as e:
        bad("ggrt serve --job-seconds 1 starts", e)
        return
    try:
        heavy = "opts=" + urllib.parse.quote("depth=16 samples=16")
        st, h, b = s.get("/api/render?" + heavy)
        check(st == 202, "a depth-16, 16-sample render of gears starts (202)", (st, b[:200]))
        rnd = __import__("random").Random(31)
        for x, y in [(256, 256), (250, 260), (0, 0)] + [(rnd.randrange(512), rnd.randrange(512)) for _ in range(3)]:
            t = time.time()
            st, h, b = s.get("/api/trace?x=%d&y=%d&%s" % (x, y, heavy))
            dt = time.time() - t
            check(st == 200 and json.loads(b)["pixel"] == [x, y] and dt < 1.0,
                  "/api/trace %d,%d at depth 16, 16 samples during that render: %.3f s (< 1 s)" % (x, y, dt),
                  (st, b[:200]))
        st, j, t = 202, {}, time.time()
        while st == 202 and time.time() - t < 30:
            st, h, b = s.get("/api/render?" + heavy)
            j = json.loads(b)
            time.sleep(0.1)
        check(st == 500 and "after 1 s" in j.get("error", ""), "past --job-seconds 1 the job fails: 500 once", j)
        st, h, b = s.get("/api/render?" + heavy)
        j = json.loads(b)
        check(st == 202 and j["job"]["state"] in ("queued", "running"),
              "asking again runs it again (the failure is not kept as the answer)", (st, j))
        codes = [s.get("/api/render?opts=" + urllib.parse.quote("depth=16 samples=%d" % k))
                 for k in range(1, 10)]
        full = [c for c in codes if c[0] == 503]
        check(full and full[0][1].get("retry-after", "").isdigit() and json.loads(full[0][2])["status"] == 503,
              "every job slot busy: 503 with Retry-After", [(c[0], c[1].get("retry-after")) for c in codes])
    finally:
        s.stop(signal.SIGTERM)


def check_cancel(work, env):
    """/api/cancel: a long render asked to be cancelled stops (and is
    forgotten) unless someone asks for it within the grace second, so a
    job queued behind it runs at once; the queued job says what it waits
    behind."""
    try:
        s = Server([SCENE, "--port", "0", "-s", "400x300"], work, env)
    except RuntimeError as e:
        bad("ggrt serve for /api/cancel starts", e)
        return
    q = urllib.parse.quote
    slow, fast = "/api/render?opts=" + q("depth=16 samples=64"), "/api/render?opts=" + q("depth=3")
    try:
        s.wait("/api/render")  # the server's own first render
        st, j = s.json(slow)
        sid = j["job"]["id"]
        time.sleep(0.3)
        st, j = s.json(fast)
        run = j["job"].get("running", {})
        check(st == 202 and j["job"]["state"] == "queued" and j["job"]["ahead"] >= 1 and
              "depth=16" in run.get("what", "") and run.get("total") == 400 * 300,
              "a job queued behind a render says which (%s)" % run.get("what"), j)
        for bad_id in ("abc", "0", "", "-1", "99999999999999999999"):
            st, h, b = s.get("/api/cancel?id=" + bad_id)
            json_error(st, h, b, 400, "/api/cancel?id=%s: 400" % bad_id)
        st, h, b = s.get("/api/cancel?id=999999")
        json_error(st, h, b, 404, "/api/cancel of no such job: 404")
        t = time.time()
        st, j = s.json("/api/cancel?id=%d" % sid)
        check(st == 200 and j["cancelling"] is True and j["job"]["id"] == sid,
              "/api/cancel of the running render: 200, cancelling", j)
        st = 202
        while st == 202 and time.time() - t < 60:
            st, h, b = s.get(fast)
            time.sleep(0.05)
        dt = time.time() - t
        check(st == 200 and dt < 20, "the render queued behind it is done %.1f s after the cancel (< 20 s)" % dt)
        for _ in range(40):
            st, h, b = s.get("/api/cancel?id=%d" % sid)
            if st == 404:
                break
            time.sleep(0.1)
        check(st == 404, "the cancelled job is forgotten (/api/cancel: 404)", (st, b))
        st, j = s.json("/api/cancel?id=%d" % s.json(fast)[1]["job"]["id"])
        check(st == 200 and j["cancelling"] is False and j["job"]["state"] == "done",
              "cancelling a finished job does nothing", j)
        st, j = s.json(slow)
        check(st == 202 and j["job"]["id"] != sid, "asking for the cancelled render again starts it anew", j)
        # Shared: one client cancels, another still polls: it goes on.
        sid = j["job"]["id"]
        s.get("/api/cancel?id=%d" % sid)
        for _ in range(12):
            st, j = s.json(slow)
            time.sleep(0.2)
        check(st == 202 and j["job"]["id"] == sid and j["job"]["state"] == "running",
              "a cancelled job that is still asked for goes on", j)
        s.get("/api/cancel?id=%d" % sid)
        t = time.time()
        while time.time() - t < 30:  # the band's tile under way ends first
            st, h, b = s.get("/api/cancel?id=%d" % sid)
            if st == 404:
                break
            time.sleep(0.2)
        check(st == 404, "... and stops once nobody asks for it (%.1f s)" % (time.time() - t), (st, b))
    finally:
        rc, err = s.stop()
    check(rc == 0, "the server with cancelled jobs exits 0", err[-1000:])


# ---- textures: what the 3D view needs, over every scene ----

TEX_SIZE = (48, 36)  # each scene's image; every other pixel's eye ray is traced


def srgb_to_linear(b):
    s = b / 255.0
    return s / 12.92 if s <= 0.04045 else ((s + 0.055) / 1.055) ** 2.4


def sub3(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def dot3(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross3(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def bary(p, a, b, c, plane=True):
    """Barycentric weights (of b and c) of p in triangle abc's plane, or
    None for a triangle without area or (plane) a p off that plane."""
    e1, e2 = sub3(b, a), sub3(c, a)
    n = cross3(e1, e2)
    nn = dot3(n, n)
    if nn == 0:
        return None
    q = sub3(p, a)
    if plane and dot3(q, n) ** 2 > 1e-10 * nn * max(dot3(e1, e1), dot3(e2, e2), 1e-300):
        return None
    return dot3(q, cross3(e2, n)) / nn, dot3(q, cross3(n, e1)) / nn


def lerp_uv(w, uv):
    """(u, v) at weights w = (b1, b2) from the corners' [u0, v0, u1, v1, u2, v2]."""
    b0 = 1 - w[0] - w[1]
    return [b0 * uv[0] + w[0] * uv[2] + w[1] * uv[4], b0 * uv[1] + w[0] * uv[3] + w[1] * uv[5]]


def turn(y, x):
    u = math.atan2(y, x) / (2 * math.pi)
    u = u + 1 if u < 0 else u
    return 0.0 if u >= 1 else u


def page_uv(scene, obj, p, mesh_tris):
    """The (u, v) the 3D view gives point p of object obj from what
    /api/scene sends (docs/serve.md), as view3d.js computes it; None when
    the scene sends none for it."""
    sh = scene["shapes"][obj]
    k = sh["kind"]
    if k in ("sphere", "cone"):
        if "e1" not in sh:
            return None
        e3 = cross3(sh["e1"], sh["e2"])
        d = sub3(p, sh["center"] if k == "sphere" else sh["base"])
        u = turn(dot3(d, sh["e2"]), dot3(d, sh["e1"]))
        if k == "sphere":
            return [u, math.acos(max(-1, min(1, dot3(d, e3) / math.sqrt(dot3(d, d))))) / math.pi]
        ax = sub3(sh["apex"], sh["base"])
        h = math.sqrt(dot3(ax, ax))
        return [u, max(0, min(1, dot3(d, ax) / h / h))]
    if k == "implicit":
        return sh.get("uv")
    if k == "mesh":
        for a, b, c, uv in mesh_tris.get(obj, ()):
            w = bary(p, a, b, c)
            if w and min(w[0], w[1], 1 - w[0] - w[1]) > -1e-7:
                return lerp_uv(w, uv)
        return None
    uv = sh.get("uv")
    if uv is None:
        return None
    if k == "rect":
        a = sh["corner"]
        b = [a[i] + sh["e1"][i] for i in range(3)]
        c = [b[i] + sh["e2"][i] for i in range(3)]
        dd = [a[i] + sh["e2"][i] for i in range(3)]
        tris = [(a, b, c, uv[0:6]), (a, c, dd, uv[0:2] + uv[4:8])]
    else:
        v, n = sh["verts"], len(sh["verts"])
        fan = k == "triangle" and n > 3
        tris = [(v[0], v[j], v[j + 1], uv[6 * (j - 1):6 * j] if fan else uv[0:2] + uv[2 * j:2 * j + 4])
                for j in range(1, n - 1)]
    # The first fan triangle with p in it; a polygon's (u, v) is affine
    # over its plane, so any of its triangles gives it (a concave one's
    # fan need not hold p).
    for a, b, c, t in tris:
        w = bary(p, a, b, c)
        if w and min(w[0], w[1], 1 - w[0] - w[1]) > -1e-7:
            return lerp_uv(w, t)
    if k == "polygon":
        for a, b, c, t in tris:
            w = bary(p, a, b, c)
            if w:
                return lerp_uv(w, t)
    return None


def texture_sample(tex, texels, u, v, knob=None):
    """The texture at (u, v) as ggTextureBilinear, ggTextureNearest and
    ggTextureChecker compute it (include/ggrt/image.h), from /api/scene's
    description and /api/texture's texels (linear RGB)."""
    if tex["kind"] == "checker":
        n = tex["n"]
        sq = math.floor((u - math.floor(u)) * n) + math.floor((v - math.floor(v)) * n)
        return tex["a"] if sq % 2 == 0 else tex["b"]
    w, h, px = texels

    def wrap(x):
        if tex["wrap"] == "clamp":
            return min(1.0, max(0.0, x))
        return x - math.floor(x) if x < 0 or x > 1 else x

    def at(i, j):
        return px[3 * (j * w + i):3 * (j * w + i) + 3]
    di, dj = (w - 1) * wrap(u), (h - 1) * wrap(v)
    if (knob or tex["filter"]) == "nearest":
        return [min(1.0, c) for c in at(int(math.floor(di + 0.5)), int(math.floor(dj + 0.5)))]
    i, j = int(di), int(dj)
    a, b = di - i, dj - j
    i1, j1 = min(i + 1, w - 1), min(j + 1, h - 1)
    c00, c01, c10, c11 = at(i, j), at(i, j1), at(i1, j), at(i1, j1)
    return [min(1.0, c00[k] * (1 - a) * (1 - b) + c01[k] * (1 - a) * b + c10[k] * a * (1 - b) + c11[k] * a * b)
            for k in range(3)]


def texture_scene(path, work, env, kinds):
    """One scene's texture fields and route; returns (problems, textures,
    textured hits checked); adds the kinds of shape hit to kinds (a pp
    polygon's fan as "fan")."""
    s = Server([path, "--port", "0", "-s", "%dx%d" % TEX_SIZE, "-d", "1"], ROOT, env)
    bad = []
    ntex = hits = 0
    try:
        st, h, b = s.get("/api/scene")
        scene = strict(b)
        if st != 200:
            return ["/api/scene: status %d" % st], 0, 0
        _, info = s.json("/api/info")
        textures = scene.get("textures")
        mats = scene["materials"]
        used = [m["texture"] for m in mats if "texture" in m]
        fx = any(e["name"] == "textures" for e in info["effects"])
        if fx != bool(used):
            bad.append("effects say textures %s, materials with a texture: %s" % (fx, used))
        if textures is None:
            if used:
                bad.append("materials name textures %s and there is no \"textures\"" % used)
            textures = []
        elif not textures:
            bad.append("\"textures\" is there and empty")
        ntex = len(textures)
        if any(not (isinstance(t, int) and 0 <= t < ntex) for t in used):
            bad.append("a material's texture is not one of the %d listed: %s" % (ntex, used))
        # An untextured object sends nothing new (a scene without textures
        # sends what it sent before).
        for i, sh in enumerate(scene["shapes"]):
            tx = "texture" in mats[sh["material"]]
            if not tx and ("uv" in sh or (sh["kind"] in ("sphere", "cone") and "e1" in sh)):
                bad.append("object %d is untextured and has texture fields" % i)
            if tx and sh["kind"] in ("sphere", "cone"):
                e1, e2 = sh.get("e1"), sh.get("e2")
                if not (e1 and e2 and abs(dot3(e1, e1) - 1) < 1e-12 and abs(dot3(e2, e2) - 1) < 1e-12 and
                        abs(dot3(e1, e2)) < 1e-12):
                    bad.append("object %d (%s): e1, e2 are not a unit frame: %r %r" % (i, sh["kind"], e1, e2))
            if tx and sh["kind"] not in ("sphere", "cone", "mesh"):
                n = len(sh.get("verts", []))
                want = {"rect": 8, "implicit": 2, "polygon": 2 * n}.get(
                    sh["kind"], 6 * (n - 2) if n > 3 else 2 * n)
                if len(sh.get("uv", [])) != want:
                    bad.append("object %d (%s): %d uv numbers, not %d" % (i, sh["kind"], len(sh.get("uv", [])), want))
        mesh_tris = {}
        for m in scene["meshes"]:
            tx = "texture" in mats[scene["shapes"][m["object"]]["material"]]
            v = m["verts"]
            if tx != ("uv" in m) or (tx and len(m["uv"]) * 3 != len(v) * 2):
                bad.append("mesh object %d: textured %s, %d uv numbers for %d triangles"
                           % (m["object"], tx, len(m.get("uv", [])), len(v) // 9))
            elif tx:
                mesh_tris[m["object"]] = [(v[k:k + 3], v[k + 3:k + 6], v[k + 6:k + 9], m["uv"][6 * (k // 9):6 * (k // 9) + 6])
                                          for k in range(0, len(v), 9)]
        # /api/texture: every image as a PNG of its size; a checker has none.
        texels = {}
        for i, t in enumerate(textures):
            st, h, b = s.get("/api/texture?index=%d" % i)
            if t["kind"] == "image":
                try:
                    w, hh, px = png_pixels(b)
                except (AssertionError, ValueError, zlib.error) as e:
                    bad.append("texture %d: not a PNG (%s): %s" % (i, e, b[:100]))
                    continue
                if st != 200 or h.get("content-type") != "image/png" or (w, hh) != (t["width"], t["height"]):
                    bad.append("texture %d: status %d, %dx%d, /api/scene says %dx%d"
                               % (i, st, w, hh, t["width"], t["height"]))
                texels[i] = (w, hh, [srgb_to_linear(c) for c in px])
                if t["wrap"] not in ("repeat", "clamp") or t["filter"] not in ("bilinear", "nearest"):
                    bad.append("texture %d: wrap %r, filter %r" % (i, t["wrap"], t["filter"]))
            elif not (t["kind"] == "checker" and t["n"] > 0 and len(t["a"]) == 3 and len(t["b"]) == 3 and
                      st == 404 and strict(b)["status"] == 404):
                bad.append("texture %d: a checker %r, /api/texture %d %s" % (i, t, st, b[:100]))
        # Refusals: JSON with the status.
        for q, want in (("index=%d" % ntex, 404), ("index=-1", 400), ("index=x", 400), ("", 400),
                        ("index=99999999999", 400), ("index=0&x=1", 400)):
            st, h, b = s.get("/api/texture" + ("?" + q if q else ""))
            try:
                j = strict(b)
                good = st == want and j.get("status") == want and h.get("content-type") == "application/json"
            except ValueError:
                good = False
            if not good:
                bad.append("/api/texture?%s: %d %s, not %d JSON" % (q, st, b[:100], want))
        # Every other pixel: where the eye ray meets a textured object, the
        # (u, v) the page works out from /api/scene is the hit's, and the
        # texture sampled there from /api/scene and /api/texture, times the
        # material colour, is the ray tree's surface colour.
        for y in range(0, TEX_SIZE[1], 2):
            for x in range(0, TEX_SIZE[0], 2):
                if not used:
                    break
                st, h, b = s.get("/api/trace?x=%d&y=%d&sample=0" % (x, y))
                hit = strict(b)["roots"][0].get("hit") if st == 200 else None
                if not hit or "texture" not in mats[hit["material"]]:
                    continue
                tex = textures[mats[hit["material"]]["texture"]]
                uv = page_uv(scene, hit["object"], hit["point"], mesh_tris)
                what = "pixel %d,%d (object %d, %s)" % (x, y, hit["object"], hit["shape"])
                if hit["shape"] == "mesh" and scene.get("simplified"):
                    continue  # the triangle hit may not be listed
                if uv is None:
                    bad.append("%s: the page gets no (u, v) for it" % what)
                    continue
                du = abs(uv[0] - hit["uv"][0])
                if hit["shape"] in ("sphere", "cone"):
                    du = min(du, 1 - du)
                if du > 5e-5 or abs(uv[1] - hit["uv"][1]) > 5e-5:
                    bad.append("%s: (u, v) %r on the page, %r in the render" % (what, uv, hit["uv"]))
                    continue
                if tex["kind"] == "image" and mats[hit["material"]]["texture"] not in texels:
                    continue
                c = texture_sample(tex, texels.get(mats[hit["material"]]["texture"]), *hit["uv"])
                want = [c[k] * mats[hit["material"]]["color"][k] for k in range(3)]
                if max(abs(want[k] - hit["surface"][k]) for k in range(3)) > 1e-6:
                    bad.append("%s: surface %r, the texture from the API gives %r" % (what, hit["surface"], want))
                hits += 1
                sh = scene["shapes"][hit["object"]]
                kinds.add("fan" if sh["kind"] == "triangle" and len(sh["verts"]) > 3 else sh["kind"])
    except (ValueError, KeyError, TypeError, IndexError) as e:
        bad.append("%s: %r" % (type(e).__name__, e))
    finally:
        rc, err = s.stop()
        if rc != 0:
            bad.append("ggrt serve exit %s: %s" % (rc, err[-300:]))
    return bad, ntex, hits


def check_textures(work, env):
    """For every scene file: /api/scene's texture fields (a texture per
    textured material, image or checker; the (u, v) or frame of every
    textured object and mesh triangle, nothing for an untextured one),
    /api/texture (each image a PNG of its size, a checker 404, bad indexes
    refused with JSON), and at every other pixel whose eye ray meets a
    textured object, the (u, v) the page derives from them is the render's
    and the texture sampled there is its surface colour (tests/data/
    textured.nff has every kind of shape textured)."""
    t0 = time.time()
    total_tex = total_hits = with_tex = 0
    kinds = set()
    for path in scene_files():
        problems, ntex, hits = texture_scene(path, work, env, kinds)
        total_tex += ntex
        total_hits += hits
        with_tex += ntex > 0
        check(not problems, "%s: textures in /api/scene and /api/texture (%d textures, %d textured hits checked)"
              % (path, ntex, hits), "\n".join(problems[:20]))
    every = {"sphere", "cone", "rect", "triangle", "fan", "polygon", "mesh", "implicit"}
    check(with_tex >= 10 and total_hits > 1500 and kinds == every,
          "textures: %d scenes of %d have textures, %d textures, %d textured hits agree, on %s (%.1f s)"
          % (with_tex, len(scene_files()), total_tex, total_hits, " ".join(sorted(kinds)), time.time() - t0),
          "missing kinds: %s" % " ".join(sorted(every - kinds)))


MAX_SURFACE_CELLS = 64 ** 3  # serve_api.c: all of a scene's surfaces' grids together
MAX_SURFACE_TRIANGLES = 100000
# The implicit surfaces of the scene files that the box does not cut:
# (file, object) -> (pieces, Euler characteristic). acc-thin's tube (radius
# 0.03) came in 12 pieces when its flat box was cut into flat cells.
CLOSED_SURFACES = {("acc-thin.nff", 1): (1, 0), ("torus.nff", 1): (1, 0),
                   ("textured.nff", 8): (1, 2)}


def grid_problem(sf, lo, hi):
    """Why surface sf's grid breaks ggImplicitTriangulate's rule (cells as
    near cubes as whole counts allow: `resolution` along the longest side,
    the fewest along each other side that are no longer), or None."""
    res, cells = sf["resolution"], sf.get("cells")
    if not (isinstance(res, int) and 1 <= res <= 256 and isinstance(cells, list) and len(cells) == 3):
        return "resolution %r, cells %r" % (res, cells)
    e = [b - a for a, b in zip(lo, hi)]
    cell = max(e) / res
    for c in range(3):
        n = cells[c]
        if not (1 <= n <= res and e[c] / n <= cell * (1 + 1e-9) and
                (n == 1 or e[c] / (n - 1) > cell * (1 - 1e-9))):
            return "%d cells along axis %d of %g at resolution %d" % (n, c, e[c], res)
    return None


def topology(sf, lo, hi, slack):
    """(pieces, Euler characteristic, open edges off the box's faces) of
    surface sf: every edge in two triangles except where the box cuts it."""
    t, v = sf["tris"], sf["verts"]
    count = {}
    for i in range(0, len(t), 3):
        for k in range(3):
            a, b = t[i + k], t[i + (k + 1) % 3]
            key = (min(a, b), max(a, b))
            count[key] = count.get(key, 0) + 1
    up = list(range(len(v) // 3))

    def root(i):
        while up[i] != i:
            up[i] = up[up[i]]
            i = up[i]
        return i
    for a, b in count:
        up[root(a)] = root(b)

    def face(k, c):
        return abs(v[3 * k + c] - lo[c]) <= slack[c] or abs(v[3 * k + c] - hi[c]) <= slack[c]
    loose = [e for e, n in count.items() if n != 2 and
             not (n == 1 and any(face(e[0], c) and face(e[1], c) for c in range(3)))]
    used = set(t)
    return len({root(k) for k in used}), len(used) - len(count) + len(t) // 3, loose


def check_surfaces(work, env):
    """For every scene file: /api/scene is strict JSON; each implicit
    object has its "surface" (docs/serve.md): a grid by the library's rule,
    all of a scene's grids within about 64^3 cells, as many index triples as it
    says triangles, every index a vertex, every vertex inside the object's
    box, every normal unit, every edge in two triangles but where the box
    cuts the surface, the closed ones in the pieces and of the genus they
    have, all scenes' surfaces within the budget together; no other kind
    has one; a second request the same bytes."""
    t0 = time.time()
    total = scenes = closed = 0
    for path in scene_files():
        s = Server([path, "--port", "0", "-s", "32x24", "-d", "1"], ROOT, env)
        bad, tris, cells = [], 0, 0
        try:
            st, _, b = s.get("/api/scene")
            scene = strict(b)
            if st != 200:
                bad.append("/api/scene: status %d" % st)
            for i, sh in enumerate(scene.get("shapes", [])):
                sf = sh and sh.get("surface")
                if not sh or sh["kind"] != "implicit":
                    if sf is not None:
                        bad.append("object %d (%s) has a surface" % (i, sh and sh["kind"]))
                    continue
                if not sf:
                    bad.append("implicit object %d has no surface" % i)
                    continue
                v, n, t = sf["verts"], sf["normals"], sf["tris"]
                nv = len(v) // 3
                lo, hi = sh["lo"], sh["hi"]
                slack = [1e-6 * max(1.0, abs(a), abs(b)) for a, b in zip(lo, hi)]
                grid = grid_problem(sf, lo, hi)
                if grid or len(t) != 3 * sf["triangles"] or not t or len(v) != len(n) or len(v) % 3:
                    bad.append("object %d: %s, %d triangles, %d indices, %d/%d coordinates"
                               % (i, grid or "grid ok", sf["triangles"], len(t), len(v), len(n)))
                    continue
                if any(not (isinstance(k, int) and 0 <= k < nv) for k in t):
                    bad.append("object %d: an index out of 0..%d" % (i, nv - 1))
                out = [k for k in range(nv) if any(not (lo[c] - slack[c] <= v[3 * k + c] <= hi[c] + slack[c])
                                                  for c in range(3))]
                if out:
                    bad.append("object %d: %d vertices outside the box, e.g. %r" % (i, len(out), v[3 * out[0]:3 * out[0] + 3]))
                norm = [abs(math.sqrt(sum(n[3 * k + c] ** 2 for c in range(3))) - 1) for k in range(nv)]
                if max(norm) > 2e-3:
                    bad.append("object %d: a normal of length off 1 by %g" % (i, max(norm)))
                pieces, euler, loose = topology(sf, lo, hi, slack)
                if loose:
                    bad.append("object %d: %d edges not in two triangles off the box's faces, e.g. %r"
                               % (i, len(loose), loose[0]))
                want = CLOSED_SURFACES.get((os.path.basename(path), i))
                if want and (pieces, euler) != want:
                    bad.append("object %d: %d pieces, Euler characteristic %d; expected %d, %d"
                               % ((i, pieces, euler) + want))
                tris += sf["triangles"]
                cells += sf["cells"][0] * sf["cells"][1] * sf["cells"][2]
                closed += bool(want)
            if tris > MAX_SURFACE_TRIANGLES:
                bad.append("%d surface triangles, over the budget of %d" % (tris, MAX_SURFACE_TRIANGLES))
            if cells > MAX_SURFACE_CELLS * 1.2:
                bad.append("%d cells in all, over about %d" % (cells, MAX_SURFACE_CELLS))
            st2, _, b2 = s.get("/api/scene")
            if st2 != 200 or b2 != b:
                bad.append("a second /api/scene: status %d, %d bytes against %d" % (st2, len(b2), len(b)))
        except ValueError as e:
            bad.append(str(e))
        finally:
            rc, err = s.stop()
            if rc != 0:
                bad.append("ggrt serve exit %s: %s" % (rc, err[-300:]))
        total += tris
        scenes += tris > 0
        if bad or tris:
            check(not bad, "%s: /api/scene's implicit surfaces (%d triangles)" % (path, tris), "\n".join(bad[:20]))
    check(scenes >= 3 and total > 0 and closed == len(CLOSED_SURFACES),
          "surfaces: %d of %d scenes have implicit surfaces, %d triangles sent, %d of %d closed "
          "surfaces checked whole, every scene's /api/scene strict JSON (%.1f s)"
          % (scenes, len(scene_files()), total, closed, len(CLOSED_SURFACES), time.time() - t0))


def png_bytes(w, h, rgb):
    """An 8-bit RGB PNG of rows of bytes rgb."""
    def chunk(t, c):
        return struct.pack(">I", len(c)) + t + c + struct.pack(">I", zlib.crc32(t + c))
    raw = b"".join(b"\0" + rgb[y * w * 3:(y + 1) * w * 3] for y in range(h))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def check_texture_reduced(env):
    """A texture wider than 2048 (4099 x 3) comes reduced by 3 (the
    smallest whole factor that fits): 1367 x 1, each texel the mean of its
    3 x 3 block in linear light (the last one of a 1 x 3 block), with
    X-GGRT-Reduced: 3; /api/scene keeps the texture's own size."""
    w, h = 4099, 3
    rgb = bytes((x * 7 + y * 50 + c * 90) % 256 for y in range(h) for x in range(w) for c in range(3))
    with tempfile.TemporaryDirectory() as d:
        with open(os.path.join(d, "wide.png"), "wb") as f:
            f.write(png_bytes(w, h, rgb))
        with open(os.path.join(d, "wide.nff"), "w") as f:
            f.write("v from 0 -3 0 at 0 0 0 up 0 0 1 angle 40 resolution 16 12\nl 0 -3 3\n"
                    "f 1 1 1 1 0 100000 0 0\ntexture \"wide.png\"\nrect -1 0 1  2 0 0  0 0 -2\n")
        s = Server([os.path.join(d, "wide.nff"), "--port", "0"], d, env)
        try:
            _, scene = s.json("/api/scene")
            st, hd, b = s.get("/api/texture?index=0")
        finally:
            s.stop()
    try:
        gw, gh, px = png_pixels(b)
    except (AssertionError, ValueError, zlib.error) as e:
        check(False, "/api/texture reduces a 4099 x 3 texture", "%d %s: %s" % (st, e, b[:200]))
        return

    def mean(x):  # linear mean of block x, back to an sRGB byte as ggLinearToSRGB8
        out = []
        for c in range(3):
            xs = range(3 * x, min(3 * x + 3, w))
            m = sum(srgb_to_linear(rgb[3 * (y * w + i) + c]) for y in range(h) for i in xs) / (len(xs) * h)
            m = 12.92 * m if m <= 0.0031308 else 1.055 * m ** (1 / 2.4) - 0.055
            out.append(int(m * 255 + 0.5))
        return out
    worst = max(abs(a - b) for x in range(gw) for a, b in zip(mean(x), px[3 * x:3 * x + 3]))
    check(st == 200 and (gw, gh) == (1367, 1) and hd.get("x-ggrt-reduced") == "3" and worst <= 1 and
          scene["textures"][0]["width"] == w,
          "/api/texture: a 4099 x 3 texture comes as 1367 x 1, the 3 x 3 means (off by %d at most), "
          "X-GGRT-Reduced: 3" % worst, (st, gw, gh, hd.get("x-ggrt-reduced"), scene.get("textures")))


def file_list(d):
    out = []
    for root, dirs, files in os.walk(d):
        out += [os.path.join(root, f) for f in files + dirs]
    return sorted(out)


def check_opens(workdir, env):
    """With strace (where it works): the server opens the scene, its
    texture and /dev/urandom, and no other file of the repository or
    elsewhere, however it is asked."""
    if subprocess.run(["sh", "-c", "strace -f -o /dev/null true"], stdout=subprocess.DEVNULL,
                      stderr=subprocess.DEVNULL).returncode != 0:
        tap.skip("strace: only the scene is opened", "strace not available")
        return
    log = os.path.join(workdir, "..", "strace.log")
    # LeakSanitizer cannot run under ptrace: leaks are checked by the runs above.
    env = dict(env, ASAN_OPTIONS=(env.get("ASAN_OPTIONS", "") + ":detect_leaks=0").lstrip(":"))
    s = Server([SCENE, "--port", "0"] + size_args(), workdir, env,
               wrap=("strace", "-f", "-qq", "-e", "trace=open,openat,creat,truncate", "-o", log))
    for path in ("/api/trace?x=44&y=40", "/api/trace?x=1&y=1&scene=/etc/passwd", "/../etc/passwd",
                 "/api/trace?x=44&y=40&format=svg", "/api/info", "/api/scene", "/"):
        s.get(path)
    s.wait("/api/image")
    # SIGINT to strace would detach it and leave ggrt running: signal
    # ggrt itself (the first process in the log).
    with open(log) as f:
        os.kill(int(f.readline().split()[0]), signal.SIGINT)
    rc, err = s.proc.wait(60), s.proc.stderr.read()
    with open(log) as f:
        opened = re.findall(r'open(?:at)?\([^"]*"([^"]+)"', f.read())
    files = sorted(set(p for p in opened if not p.startswith(("/lib", "/usr/lib", "/etc/ld.so", "/proc/",
                                                               "/sys/", "/dev/shm"))))
    # glass.nff's floor texture is procedural: the scene is the only file
    # of the repository; /dev/urandom gives the token, /etc/localtime is
    # libc's for the Date header.
    allowed = {SCENE, "/dev/urandom", "/etc/localtime"}
    check(rc == 0 and set(files) <= allowed and SCENE in files,
          "strace: only the scene (and /dev/urandom, /etc/localtime) is opened", (rc, files, err[-500:]))
    os.unlink(log)


def main():
    base = tempfile.mkdtemp(prefix="ggrt-http-")
    try:
        return run(base)
    finally:
        for p in SERVERS:
            if p.poll() is None:
                p.kill()
                p.wait()
        shutil.rmtree(base, ignore_errors=True)


def run(base):
    work, tmp = os.path.join(base, "cwd"), os.path.join(base, "tmp")
    os.mkdir(work)
    os.mkdir(tmp)
    env = dict(os.environ, TMPDIR=tmp)
    r = subprocess.run([GGRT, "serve", "--help"], stdout=subprocess.PIPE, text=True)
    if "built without" in r.stdout:
        bad("ggrt serve is built in", "this ggrt was built without libmicrohttpd")
        return tap.done()
    t0 = time.time()
    s = Server([SCENE, "--port", "0"] + size_args(), work, env)
    try:
        check_pages(s)
        check_info(s)
        check_security(s)
        check_request_body(s)
        check_bad_queries(s)
        check_parse_opts(s)
        check_limit_message(s)
        check_too_large(s)
        check_record_bound(s)
        rgb, stats = check_render(s)
        check_trace(s, rgb)
        check_heatmaps(s, stats)
        check_debug(s)
        check_find_limit0(s)
        check_paths(s)
        check_concurrent(s)
        check_render_stats(s)
    finally:
        rc, err = s.stop()
    check(rc == 0 and "stopping" in err, "SIGINT: clean exit 0", "exit %s: %s" % (rc, err[-2000:]))
    check(file_list(work) == [] and file_list(tmp) == [], "nothing left in the working or temporary folder",
          file_list(work) + file_list(tmp))
    # SIGTERM in the middle of a long render stops it promptly.
    s = Server([SCENE, "--port", "0", "-s", "400x300"], work, env)
    s.get("/api/render?opts=samples%3D64,depth%3D16")
    time.sleep(0.3)
    t1 = time.time()
    rc, err = s.stop(signal.SIGTERM)
    check(rc == 0 and time.time() - t1 < 20, "SIGTERM during a long render: exit 0 in %.1f s" % (time.time() - t1),
          err[-1000:])
    # Cannot listen: the port is taken.
    sk = socket.socket()
    sk.bind(("127.0.0.1", 0))
    sk.listen(1)
    r = subprocess.run([GGRT, "serve", SCENE, "--port", str(sk.getsockname()[1])], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True, timeout=30)
    sk.close()
    check(r.returncode == 3 and "cannot listen" in r.stderr and "Address already in use" in r.stderr and
          "--port 0 takes a free one" in r.stderr, "a port in use: exit 3, the reason and the way out", r.stderr)
    # An address not on this machine: the reason, and no hint of --port 0 (given).
    r = subprocess.run([GGRT, "serve", SCENE, "--host", "192.0.2.1", "--port", "0"], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True, timeout=30)
    check(r.returncode == 3 and "Cannot assign requested address" in r.stderr and "--port 0" not in r.stderr,
          "an address not here: exit 3 with the reason", r.stderr)
    # The URL cannot be printed (stdout full): not started, exit 3 at once.
    with open("/dev/full", "w") as full:
        r = subprocess.run([GGRT, "serve", SCENE, "--port", "0"], stdout=full, stderr=subprocess.PIPE,
                           text=True, timeout=30)
    check(r.returncode == 3 and "cannot print the URL" in r.stderr,
          "stdout full: serve stops at once, exit 3", r.stderr)
    r = subprocess.run([GGRT, "serve", SCENE, "--host", "example.com"], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True, timeout=30)
    check(r.returncode != 0 and "numeric" in r.stderr, "--host must be numeric", r.stderr)
    check_textures(work, env)
    check_surfaces(work, env)
    check_texture_reduced(env)
    check_tracing_first(work, env)
    check_cancel(work, env)
    check_opens(work, env)
    check(file_list(work) == [] and file_list(tmp) == [], "still nothing left behind")
    return tap.done("(%.1f s)" % (time.time() - t0))


if __name__ == "__main__":
    sys.exit(main())
