# SPDX-License-Identifier: MIT
"""Every scene through `ggrt serve` (docs/serve.md): for EVERY scene file
under examples/scenes (recursively: NFF, and the OBJ and PLY models) and
tests/data/debug, and the scenes at the top of tests/data, start the server on a small image and parse, strictly
(json.loads that refuses NaN and Infinity), /api/info, /api/scene,
/api/trace of the four corners, the centre and a random pixel, /api/find,
/api/find and /api/trace with light-path expressions, /api/check and
/api/diff. A few servers run at once.
    python3 tests/http/http_scenes_test.py build/ggrt [--seed N]
Prints TAP (tests/http/tap.py)."""
import concurrent.futures
import http.client
import json
import os
import random
import re
import subprocess
import sys
import time
import urllib.parse

import tap

GGRT = os.path.abspath(sys.argv[1]) if len(sys.argv) > 1 else "build/ggrt"
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SIZE = (40, 30)
SCENE_EXT = (".nff", ".obj", ".ply")
PARALLEL = 3  # servers at once: the machine is small, each one mostly waits
TIMEOUT = 120  # seconds for one scene (a test that hangs fails instead)
# Light-path expressions asked of every scene: every path (so every pixel
# with light matches), and the direct diffuse light or a refraction chain.
PATHS = ("C.*", "C<RD>L|C<TS>+.*")


def scene_files():
    out = []
    for top in ("examples/scenes", "tests/data/debug"):
        for d, _, files in os.walk(os.path.join(ROOT, top)):
            out += [os.path.relpath(os.path.join(d, f), ROOT) for f in files if f.endswith(SCENE_EXT)]
    # the scenes at the top of tests/data: not hostile/, whose inputs must
    # fail, nor meshes/, loader fixtures of which flat.obj must fail too
    out += [os.path.join("tests/data", f) for f in os.listdir(os.path.join(ROOT, "tests/data")) if f.endswith(".nff")]
    return sorted(out)


def strict(body):
    """The document, or raise: JSON has no NaN or Infinity."""
    def refuse(name):
        raise ValueError("not JSON: " + name)
    return json.loads(body.decode("utf-8"), parse_constant=refuse)


class Server:
    def __init__(self, scene):
        self.proc = subprocess.Popen([GGRT, "serve", scene, "--port", "0", "-s", "%dx%d" % SIZE, "-d", "3"],
                                     cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        url = self.proc.stdout.readline().strip()
        m = re.match(r"^http://127\.0\.0\.1:(\d+)/\?token=([0-9a-f]{32})$", url)
        if not m:
            self.stop()
            raise RuntimeError("no URL printed: %r %s" % (url, self.proc.stderr.read()[-500:]))
        self.port, self.token = int(m.group(1)), m.group(2)
        self.conn = http.client.HTTPConnection("127.0.0.1", self.port, timeout=TIMEOUT)

    def get(self, path):
        self.conn.request("GET", path, headers={"Authorization": "Bearer " + self.token})
        r = self.conn.getresponse()
        return r.status, r.read()

    def wait(self, path, deadline):
        while True:
            st, b = self.get(path)
            if st not in (202, 503) or time.time() > deadline:
                return st, b
            time.sleep(0.05)

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(30)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()


def one_scene(scene, rnd):
    """Every route on scene: a list of (ok, name, detail)."""
    res = []
    deadline = time.time() + TIMEOUT

    def parse(name, st, b, check=None):
        try:
            j = strict(b)
            good = st == 200 and (check is None or check(j))
            res.append((good, "%s: %s" % (scene, name), "" if good else "status %d: %s" % (st, b[:300])))
        except (ValueError, UnicodeDecodeError) as e:
            res.append((False, "%s: %s parses" % (scene, name), "status %d: %s; %s" % (st, e, b[:300])))

    try:
        s = Server(scene)
    except RuntimeError as e:
        return [(False, "%s: ggrt serve starts" % scene, str(e))]
    try:
        st, b = s.get("/api/info")
        parse("/api/info", st, b, lambda j: j["width"] == SIZE[0] and j["objects"] >= 1)
        st, b = s.get("/api/scene")
        parse("/api/scene", st, b,
              lambda j: len(j["shapes"]) == min(j["objects"], 20000) and
              all(sh is not None and all(len(v) == 3 for v in sh.get("verts", [])) for sh in j["shapes"]))
        w, h = SIZE
        pixels = [(0, 0), (w - 1, 0), (0, h - 1), (w - 1, h - 1), (w // 2, h // 2),
                  (rnd.randrange(w), rnd.randrange(h))]
        for x, y in pixels:
            st, b = s.get("/api/trace?x=%d&y=%d" % (x, y))
            parse("/api/trace %d,%d" % (x, y), st, b, lambda j: j["pixel"] == [x, y] and j["roots"])
        where = urllib.parse.quote("some(kind == eye)")
        st, b = s.wait("/api/find?where=" + where, deadline)
        parse("/api/find", st, b, lambda j: j["matched"] == j["scanned"] == w * h)
        for lpe in PATHS:
            q = urllib.parse.quote(lpe)
            st, b = s.wait("/api/find?limit=%d&path=%s" % (w * h, q), deadline)
            parse("/api/find?path=" + lpe, st, b,
                  lambda j: j["path"] == lpe and j["scanned"] == w * h and len(j["matches"]) == j["matched"] and
                  all(0 <= m["share"] <= 1 + 1e-6 for m in j["matches"]))
            for x, y in pixels[4:]:
                st, b = s.get("/api/trace?x=%d&y=%d&path=%s" % (x, y, q))
                parse("/api/trace %d,%d path=%s" % (x, y, lpe), st, b,
                      lambda j: j["pixel"] == [x, y] and j["matched"] == len(j["terms"]) <= j["paths"] and
                      abs(j["share"] - sum(t["share"] for t in j["terms"])) < 1e-9)
        st, b = s.wait("/api/check", deadline)
        parse("/api/check", st, b, lambda j: j["scanned"] == w * h)
        st, b = s.wait("/api/diff?b=depth%3D2", deadline)
        parse("/api/diff", st, b, lambda j: j["scanned"] == w * h)
    except (OSError, http.client.HTTPException) as e:
        res.append((False, "%s: the server answers" % scene, repr(e)))
    finally:
        s.stop()
    return res


def main():
    seed = int(sys.argv[sys.argv.index("--seed") + 1]) if "--seed" in sys.argv else int(time.time())
    tap.note("seed %d (--seed %d repeats the random pixels)" % (seed, seed))
    scenes = scene_files()
    bad_scenes = set()
    t0 = time.time()
    with concurrent.futures.ThreadPoolExecutor(PARALLEL) as ex:
        futs = [ex.submit(one_scene, sc, random.Random("%d %s" % (seed, sc))) for sc in scenes]
        for sc, fu in zip(scenes, futs):
            for good, name, detail in fu.result():
                if good:
                    tap.ok(name)
                else:
                    bad_scenes.add(sc)
                    tap.bad(name, detail, 10)
    tap.note("scenes: %d files, %d with a failure%s" % (len(scenes), len(bad_scenes),
                                                        (": " + " ".join(sorted(bad_scenes))) if bad_scenes else ""))
    if not scenes:
        tap.bad("scene files found", "no scene under examples/scenes")
    return tap.done("(%.1f s)" % (time.time() - t0))


if __name__ == "__main__":
    sys.exit(main())
