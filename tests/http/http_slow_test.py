# SPDX-License-Identifier: MIT
"""Slow clients cannot stop `ggrt serve` (docs/serve.md, "Limits"): 200
sockets from other loopback addresses (127.0.0.2 and up: each client
socket is bound to its source address) send a request head one byte a
second, and are opened again whenever the server cuts them, while a
normal client on 127.0.0.1 asks for /api/info, on new connections and on
one kept alive: every answer must be 200 and the p99 latency under
100 ms. Also: the server cuts the slow sockets (the request-head
deadline), and one address gets no more than its share of connections.
All traffic stays on 127.0.0.0/8; the test stops by itself (about 20 s).
    python3 tests/http/http_slow_test.py build/ggrt
Prints TAP (tests/http/tap.py)."""
import http.client
import os
import re
import socket
import subprocess
import sys
import threading
import time

import tap

GGRT = os.path.abspath(sys.argv[1]) if len(sys.argv) > 1 else "build/ggrt"
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(ROOT, "examples", "scenes", "glass.nff")
SLOW = 200          # slow sockets, one per address 127.0.0.2 ...
SECONDS = 12        # how long the normal client measures (past two head deadlines of 5 s)
P99_MS = 100.0
HEAD = b"GET /api/info HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: " + b"s" * 200


def check(cond, name, detail=""):
    if cond:
        tap.ok(name)
    else:
        tap.bad(name, detail, 20)
    return cond


def slow_socket(addr, port):
    s = socket.socket()
    s.settimeout(2)
    s.bind((addr, 0))
    s.connect(("127.0.0.1", port))
    s.setblocking(False)
    return s


class Slowloris:
    """SLOW sockets that each send one byte of a request head a second;
    a socket the server cuts is counted and opened again."""

    def __init__(self, port):
        self.port, self.stop, self.cut, self.opened, self.errors = port, False, 0, 0, []
        self.socks = [None] * SLOW
        self.sent = [0] * SLOW
        self.thread = threading.Thread(target=self.run, daemon=True)

    def addr(self, i):
        return "127.0.%d.%d" % ((i + 2) // 256, (i + 2) % 256)

    def reopen(self, i):
        try:
            self.socks[i] = slow_socket(self.addr(i), self.port)
            self.sent[i] = 0
            self.opened += 1
        except OSError as e:
            self.socks[i] = None
            self.errors.append("%s: %s" % (self.addr(i), e))

    def run(self):
        # Opened over the first second, so that their deadlines (and the
        # server's cuts) are spread out rather than all at once.
        for i in range(SLOW):
            self.reopen(i)
            time.sleep(1.0 / SLOW)
        while not self.stop:
            t = time.time()
            for i in range(SLOW):
                s = self.socks[i]
                if s is None:
                    self.reopen(i)
                    continue
                try:
                    if s.recv(4096) == b"":  # the server closed it
                        raise ConnectionResetError("closed")
                except BlockingIOError:
                    pass
                except OSError:
                    self.cut += 1
                    s.close()
                    self.reopen(i)
                    continue
                try:
                    s.send(HEAD[self.sent[i] % len(HEAD):][:1])
                    self.sent[i] += 1
                except BlockingIOError:
                    pass
                except OSError:
                    self.cut += 1
                    s.close()
                    self.reopen(i)
            time.sleep(max(0.0, 1.0 - (time.time() - t)))
        for s in self.socks:
            if s is not None:
                s.close()


def timed_get(conn, token):
    t = time.perf_counter()
    conn.request("GET", "/api/info", headers={"Authorization": "Bearer " + token})
    r = conn.getresponse()
    r.read()
    return r.status, 1000 * (time.perf_counter() - t)


def normal_client(port, token):
    """/api/info for SECONDS: alternately on a new connection (connect
    time included) and on one kept alive. Returns (latencies, failures)."""
    lat, fails = [], []
    kept = http.client.HTTPConnection("127.0.0.1", port, timeout=5)
    end, k = time.time() + SECONDS, 0
    while time.time() < end:
        k += 1
        try:
            if k % 2:
                t = time.perf_counter()
                c = http.client.HTTPConnection("127.0.0.1", port, timeout=5)
                st, ms = timed_get(c, token)
                c.close()
                ms = 1000 * (time.perf_counter() - t)
            else:
                st, ms = timed_get(kept, token)
            lat.append(ms)
            if st != 200:
                fails.append("status %d" % st)
        except (OSError, http.client.HTTPException) as e:
            fails.append(repr(e))
            kept.close()
            kept = http.client.HTTPConnection("127.0.0.1", port, timeout=5)
        time.sleep(0.02)
    kept.close()
    return lat, fails


def per_address(port):
    """40 idle sockets from one address: how many the server keeps open."""
    socks = []
    for _ in range(40):
        try:
            socks.append(slow_socket("127.0.1.250", port))
        except OSError:
            pass
    time.sleep(1.0)
    alive = 0
    for s in socks:
        try:
            alive += s.recv(1) != b""
        except BlockingIOError:
            alive += 1
        except OSError:
            pass
        s.close()
    return alive


def slow_main(port, seconds):
    """The slow sockets, in a process of their own (so that the normal
    client's latency is the server's, not this interpreter's): run for
    `seconds`, then print what happened."""
    slow = Slowloris(port)
    slow.thread.start()
    time.sleep(seconds)
    slow.stop = True
    slow.thread.join(10)
    print("opened %d cut %d errors %d" % (slow.opened, slow.cut, len(slow.errors)))
    for e in slow.errors[:5]:
        print("error " + e)
    return 0


def main():
    if "--slow" in sys.argv:
        i = sys.argv.index("--slow")
        return slow_main(int(sys.argv[i + 1]), float(sys.argv[i + 2]))
    proc = subprocess.Popen([GGRT, "serve", SCENE, "--port", "0", "-s", "80x60"], cwd=ROOT,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    t0 = time.time()
    try:
        url = proc.stdout.readline().strip()
        m = re.match(r"^http://127\.0\.0\.1:(\d+)/\?token=([0-9a-f]{32})$", url)
        if not check(m is not None, "ggrt serve starts", url):
            return tap.done()
        port, token = int(m.group(1)), m.group(2)
        slow = subprocess.Popen([sys.executable, os.path.abspath(__file__), GGRT, "--slow", str(port),
                                 str(SECONDS + 2)], stdout=subprocess.PIPE, text=True)
        time.sleep(1.5)  # all 200 open and sending
        lat, fails = normal_client(port, token)
        try:
            out = slow.communicate(timeout=30)[0]
        except subprocess.TimeoutExpired:
            slow.kill()
            out = slow.communicate()[0]
        m = re.search(r"opened (\d+) cut (\d+) errors (\d+)", out)
        opened, cut, nerr = (int(v) for v in m.groups()) if m else (0, 0, -1)
        lat.sort()
        p99 = lat[min(len(lat) - 1, int(0.99 * len(lat)))] if lat else float("inf")
        check(opened >= SLOW and nerr == 0, "%d slow sockets opened from 127.0.0.2 up" % opened, out)
        check(not fails and len(lat) > 50,
              "a normal client from 127.0.0.1 served meanwhile: %d requests, %d failed" % (len(lat), len(fails)),
              fails[:5])
        check(p99 < P99_MS, "its p99 latency %.1f ms (p50 %.1f, max %.1f) is under %.0f ms"
              % (p99, lat[len(lat) // 2] if lat else -1, lat[-1] if lat else -1, P99_MS))
        check(cut >= SLOW, "the server cut the slow sockets at the head deadline (%d cuts in %d s)"
              % (cut, SECONDS))
        alive = per_address(port)
        check(0 < alive <= 16, "one address keeps at most 16 connections (%d of 40 kept)" % alive)
        try:
            c = http.client.HTTPConnection("127.0.0.1", port, timeout=5)
            st, ms = timed_get(c, token)
            c.close()
        except (OSError, http.client.HTTPException) as e:
            st, ms = repr(e), -1
        check(st == 200, "still serving afterwards (%s, %.1f ms)" % (st, ms))
    finally:
        proc.terminate()
        try:
            rc = proc.wait(30)
        except subprocess.TimeoutExpired:
            proc.kill()
            rc = "hung"
    check(rc == 0, "SIGTERM: exit 0 (got %s)" % rc)
    return tap.done("(%.1f s)" % (time.time() - t0))


if __name__ == "__main__":
    sys.exit(main())
