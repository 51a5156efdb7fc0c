# SPDX-License-Identifier: MIT
"""HTTP test of `ggrt serve` (docs/serve.md): starts the server on a free
port and checks every route, the token and Host checks, the limits, the
errors (always JSON with the HTTP status), /api/trace against
`ggrt trace --format json`, concurrent requests, and that shutdown leaves
nothing behind. Standard library only (http.client).
    python3 tests/http_test.py build/ggrt
Prints one line per check and ends with "http: N passed, M failed"."""
import http.client
import json
import os
import re
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
import xml.dom.minidom
import zlib

GGRT = os.path.abspath(sys.argv[1]) if len(sys.argv) > 1 else "build/ggrt"
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "examples", "scenes", "glass.nff")
SIZE = (160, 120)
passed = failed = 0


def ok(name):
    global passed
    passed += 1
    print("ok   " + name)


def bad(name, detail=""):
    global failed
    failed += 1
    print("FAIL " + name)
    if detail:
        for line in str(detail).splitlines()[:30]:
            print("     " + line)


def check(cond, name, detail=""):
    (ok if cond else lambda n: bad(n, detail))(name)
    return cond


class Server:
    def __init__(self, args, cwd, env=None, wrap=()):
        self.proc = subprocess.Popen(list(wrap) + [GGRT, "serve"] + args, cwd=cwd, env=env,
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
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


def cli(*args):
    r = subprocess.run([GGRT] + list(args), stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    if r.returncode != 0:
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
                              ("/app.css", "text/css", b"box-sizing")):
        st, h, b = s.get(path)
        check(st == 200 and h["content-type"].startswith(typ) and needle in b, path)
    st, h, b = s.get("/favicon.ico")
    json_error(st, h, b, 404, "an unknown page is 404 JSON")
    st, h, b = s.get("/", headers={"Authorization": "Bearer " + s.token}, token=False)
    check(st == 200, "Authorization: Bearer works as well as ?token=")


def check_info(s):
    st, j = s.json("/api/info")
    check(st == 200 and j["width"] == SIZE[0] and j["height"] == SIZE[1] and j["scene"] == SCENE and
          any(e["name"] == "refraction" for e in j["effects"]) and j["limits"]["max_depth"] == 16,
          "/api/info: size, scene, effects, limits", j)
    st, j = s.json("/api/scene")
    check(st == 200 and len(j["shapes"]) == 3 and j["shapes"][1]["kind"] == "sphere" and
          len(j["materials"]) == 3, "/api/scene: shapes and materials", j)


def check_render(s):
    st, h, b = s.wait("/api/render")
    j = json.loads(b)
    check(st == 200 and j["render"]["state"] == "done" and j["render"]["total"] == SIZE[0] * SIZE[1],
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
    return struct.unpack("<%df" % (SIZE[0] * SIZE[1] * 3), f32), j["render"]["stats"]


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
    for q, args in (("depth=3", ["-d", "3"]), ("samples=4&sample=2", ["-n", "4", "--sample", "2"]),
                    ("samples=4", ["-n", "4"]), ("spd=1", ["--spd"]), ("force=1", ["--force-effects"])):
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
    st, j = s.json("/api/trace?x=44&y=40&refract=textbook&fresnel=schlick")
    check(st == 200 and j["ggrt_trace"] == 1, "/api/trace with accuracy knobs")


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
    st, h, b = s.wait("/api/image?kind=depth&format=f32")
    depth = struct.unpack("<%df" % (SIZE[0] * SIZE[1]), b)
    check(st == 200 and max(depth) == 5 and min(depth) >= 1, "depth heatmap: 1 to the limit 5",
          "%s..%s" % (min(depth), max(depth)))


def check_diff(s, rgb):
    st, h, b = s.wait("/api/diff?b.depth=2")
    j = json.loads(b)
    check(st == 200 and j["state"] == "done" and 0 < j["pixels_differ"] < j["pixels"] and j["max_abs"] > 0
          and j["b"]["depth"] == 2, "/api/diff A against depth 2: some pixels differ", j)
    st, h, b = s.wait("/api/diff?b.depth=2&format=f32")
    d = struct.unpack("<%df" % (SIZE[0] * SIZE[1]), b)
    check(st == 200 and sum(1 for v in d if v > 0) == j["pixels_differ"], "diff map: as many pixels differ")
    st, h, b = s.wait("/api/diff?b.depth=2&format=png")
    check(st == 200 and png_pixels(b)[0] == SIZE[0], "diff map as a PNG")
    st, j = s.json("/api/diff")
    check(st == 200 and j["pixels_differ"] == 0, "/api/diff of equal options: nothing differs", j)


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
    st, h, b = s.get("/api/info", token=False, headers={"Authorization": "Basic " + s.token})
    json_error(st, h, b, 401, "another auth scheme: 401")
    for host in ("evil.example:%d" % s.port, "127.0.0.1:%d" % (s.port + 1), "127.0.0.1",
                 "localhost.evil.example:%d" % s.port, "127.0.0.2:%d" % s.port, "[::1]:%d" % s.port,
                 "127.0.0.1:%d@evil" % s.port, ""):
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
                       ("/api/info?path=/etc/passwd", 400), ("/../../../etc/passwd", 404),
                       ("/%2e%2e/%2e%2e/etc/passwd", 404), ("/app.js/../../etc/passwd", 404),
                       ("//etc/passwd", 404), ("/api/trace?x=1&y=1&texture=/etc/passwd", 400)):
        st, h, b = s.get(path)
        json_error(st, h, b, want, "refused: %s -> %d" % (path, want))
        check(b"root:" not in b, "no file content in the answer to " + path)


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
        ("/api/trace?x=1&y=1&depth=17", 400, "depth over the limit"),
        ("/api/trace?x=1&y=1&depth=0x3", 400, "depth in hex"),
        ("/api/trace?x=1&y=1&samples=65", 400, "samples over the limit"),
        ("/api/trace?x=1&y=1&refract=bogus", 400, "unknown knob value"),
        ("/api/trace?x=1&y=1&cutoff=nan", 400, "NaN knob"),
        ("/api/trace?x=1&y=1&cutoff=-1", 400, "negative knob"),
        ("/api/trace?x=1&y=1&spd=maybe", 400, "not a boolean"),
        ("/api/trace?x=1&y=1&b.depth=2", 400, "b.* outside diff"),
        ("/api/image?kind=heat", 400, "unknown heatmap kind"),
        ("/api/image?format=jpeg", 400, "unknown image format"),
        ("/api/diff?format=gif", 400, "unknown diff format"),
        ("/api/diff?b.depth=x", 400, "bad b option"),
        ("/api/nothing", 404, "unknown route"),
        ("/api/trace?x=1&y=1&" + "&".join("p%d=1" % i for i in range(50)), 400, "too many parameters"),
        ("/api/trace?x=1&y=%s" % ("1" * 1100), 414, "a value over 1024 bytes"),
        ("/api/trace?x=1&y=1&pad=%s" % ("a" * 5000), 414, "a request target over 4096 bytes"),
        ("/api/trace?x=1&y=1&%ff%fe=1", 400, "a strange parameter name"),
        ("/api/trace?x=%00&y=1", 400, "a NUL in a value"),
    ]
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
    s.get("/api/render?samples=16")  # a slower render in the background
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
        print("skip opens: strace not available")
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
    work, tmp = os.path.join(base, "cwd"), os.path.join(base, "tmp")
    os.mkdir(work)
    os.mkdir(tmp)
    env = dict(os.environ, TMPDIR=tmp)
    r = subprocess.run([GGRT, "serve", "--help"], stdout=subprocess.PIPE, text=True)
    if "built without" in r.stdout:
        bad("ggrt serve is built in", "this ggrt was built without libmicrohttpd")
        print("http: %d passed, %d failed" % (passed, failed))
        return 1
    t0 = time.time()
    s = Server([SCENE, "--port", "0"] + size_args(), work, env)
    try:
        check_pages(s)
        check_info(s)
        check_security(s)
        check_bad_queries(s)
        rgb, stats = check_render(s)
        check_trace(s, rgb)
        check_heatmaps(s, stats)
        check_diff(s, rgb)
        check_concurrent(s)
    finally:
        rc, err = s.stop()
    check(rc == 0 and "stopping" in err, "SIGINT: clean exit 0", "exit %s: %s" % (rc, err[-2000:]))
    check(file_list(work) == [] and file_list(tmp) == [], "nothing left in the working or temporary folder",
          file_list(work) + file_list(tmp))
    # SIGTERM in the middle of a long render stops it promptly.
    s = Server([SCENE, "--port", "0", "-s", "400x300"], work, env)
    s.get("/api/render?samples=64&depth=16")
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
    check(r.returncode == 3 and "cannot listen" in r.stderr, "a port in use: exit 3 with a message", r.stderr)
    r = subprocess.run([GGRT, "serve", SCENE, "--host", "example.com"], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True, timeout=30)
    check(r.returncode != 0 and "numeric" in r.stderr, "--host must be numeric", r.stderr)
    check_opens(work, env)
    check(file_list(work) == [] and file_list(tmp) == [], "still nothing left behind")
    subprocess.run(["rm", "-rf", base])
    print("http: %d passed, %d failed (%.1f s)" % (passed, failed, time.time() - t0))
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
