# SPDX-License-Identifier: MIT
"""Load benchmark of `ggrt serve` (not a test: it prints figures). N
clients, each on its own keep-alive connection, ask /api/trace for random
pixels for M seconds against one server; prints requests per second, the
latency percentiles and the errors (any answer but 200 with a JSON ray
tree, or a failed connection), which must be 0.
    python3 bench/http_bench.py build/ggrt [--clients N] [--seconds M]
        [--scene FILE] [--size WxH] [--render]
--render also keeps a render of new options running in the background,
so that traces share the machine with a render's bands."""
import argparse
import http.client
import json
import os
import random
import re
import signal
import subprocess
import sys
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ggrt")
    ap.add_argument("--clients", type=int, default=8)
    ap.add_argument("--seconds", type=float, default=10)
    ap.add_argument("--scene", default="examples/scenes/glass.nff")
    ap.add_argument("--size", default=None)
    ap.add_argument("--render", action="store_true")
    a = ap.parse_args()
    cmd = [os.path.abspath(a.ggrt), "serve", a.scene, "--port", "0"] + (["-s", a.size] if a.size else [])
    srv = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    url = srv.stdout.readline().strip()
    m = re.match(r"http://127\.0\.0\.1:(\d+)/\?token=([0-9a-f]+)", url)
    if not m:
        print("bench: ggrt serve did not start: " + srv.stderr.read())
        return 1
    port, token = int(m.group(1)), m.group(2)
    try:
        return bench(a, srv, port, token)
    finally:
        if srv.poll() is None:  # the run raised: do not leave the server behind
            srv.kill()
            srv.wait()


def bench(a, srv, port, token):
    hdr = {"Authorization": "Bearer " + token}
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    c.request("GET", "/api/info", headers=hdr)
    info = json.loads(c.getresponse().read())
    w, h = info["width"], info["height"]
    # Wait for the first render, so that it does not share the run.
    while True:
        c.request("GET", "/api/render", headers=hdr)
        r = c.getresponse()
        if json.loads(r.read())["job"]["state"] == "done":
            break
        time.sleep(0.05)
    c.close()
    lat, errors, sizes, lock = [], [], [], threading.Lock()
    stop = time.time() + a.seconds

    def client(k):
        rnd = random.Random(k)
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
        mine, bad, nbytes = [], [], 0
        while time.time() < stop:
            x, y = rnd.randrange(w), rnd.randrange(h)
            t = time.perf_counter()
            try:
                conn.request("GET", "/api/trace?x=%d&y=%d" % (x, y), headers=hdr)
                r = conn.getresponse()
                body = r.read()
                ok = r.status == 200 and body.startswith(b'{"ggrt_trace":2,')
            except (OSError, http.client.HTTPException) as e:
                ok, body = False, str(e).encode()
                conn.close()
                conn = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
            mine.append(time.perf_counter() - t)
            nbytes += len(body)
            if not ok:
                bad.append((x, y, body[:100]))
        conn.close()
        with lock:
            lat.extend(mine)
            errors.extend(bad)
            sizes.append(nbytes)

    def renders():
        # New options every time: each is a new render job.
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
        n = 0
        while time.time() < stop:
            conn.request("GET", "/api/render?opts=cutoff%%3D%g" % (1e-6 * (n + 1)), headers=hdr)
            st = json.loads(conn.getresponse().read())["job"]["state"]
            if st in ("done", "failed"):
                n += 1
            time.sleep(0.05)
        conn.close()
        with lock:
            sizes.append(0)
            print("bench: %d background renders finished during the run" % n)

    ts = [threading.Thread(target=client, args=(k,)) for k in range(a.clients)]
    if a.render:
        ts.append(threading.Thread(target=renders))
    t0 = time.time()
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    el = time.time() - t0
    srv.send_signal(signal.SIGINT)
    rc = srv.wait(60)
    lat.sort()

    def pct(p):
        return 1000 * lat[min(len(lat) - 1, int(p / 100.0 * len(lat)))] if lat else float("nan")

    print("bench: ggrt serve %s (%dx%d), %d clients, %.1f s%s" %
          (a.scene, w, h, a.clients, el, ", renders in the background" if a.render else ""))
    print("bench: %d trace requests, %.0f requests/s, %.1f MB/s" %
          (len(lat), len(lat) / el, sum(sizes) / el / 1e6))
    print("bench: latency p50 %.2f ms, p90 %.2f ms, p99 %.2f ms, max %.2f ms" %
          (pct(50), pct(90), pct(99), 1000 * lat[-1] if lat else 0))
    print("bench: errors %d%s; server exit %d" % (len(errors), (" e.g. %r" % (errors[0],)) if errors else "", rc))
    return 0 if not errors and rc == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
