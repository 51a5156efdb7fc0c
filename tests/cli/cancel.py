# SPDX-License-Identifier: MIT
"""SIGINT and SIGTERM cancel `ggrt render` through the library's progress
callback: the process dies of the signal, says so, leaves the old output as
it was and no temporary file. Also checks that ggrt never wrote into its
argv (/proc/PID/cmdline while it runs). Prints one "ok NAME" or
"FAIL NAME: why" line per check.
usage: cancel.py GGRT TMPDIR"""
import os
import signal
import subprocess
import sys
import time

ggrt, tmp = sys.argv[1], sys.argv[2]
SCENE = "examples/scenes/spd/balls-s4.nff"


def report(good, name, why=""):
    print(("ok   %s" % name) if good else ("FAIL %s: %s" % (name, why)))


def caught(pid, signo):
    """Has process pid installed a handler for signo (SigCgt in /proc)?"""
    try:
        with open("/proc/%d/status" % pid) as f:
            for line in f:
                if line.startswith("SigCgt:"):
                    return int(line.split()[1], 16) >> (signo - 1) & 1
    except OSError:
        pass
    return 0


def default_signals():
    # A test run from a background job may have SIGINT ignored; ggrt keeps
    # ignored signals ignored, so give it the ordinary dispositions.
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


for sig in (signal.SIGINT, signal.SIGTERM):
    name = signal.Signals(sig).name
    d = os.path.join(tmp, "cancel-" + name)
    os.makedirs(d)
    out = os.path.join(d, "old.png")
    with open(out, "wb") as f:
        f.write(b"the previous image\n")
    args = [ggrt, "render", SCENE, "-o", out, "-s", "1024x768", "-n", "9", "-j", "1"]
    p = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                         preexec_fn=default_signals)
    t0 = time.time()
    while not caught(p.pid, sig) and p.poll() is None and time.time() - t0 < 30:
        time.sleep(0.01)
    if not caught(p.pid, sig):
        p.kill()
        p.wait()
        report(False, "%s: ggrt render installs a handler" % name, "no handler in SigCgt")
        continue
    with open("/proc/%d/cmdline" % p.pid, "rb") as f:
        cmdline = f.read().split(b"\0")[:-1]
    report(cmdline == [a.encode() for a in args], "argv is not written into while rendering",
           repr(cmdline))
    time.sleep(0.3)  # well inside the render
    t1 = time.time()
    p.send_signal(sig)
    try:
        _, err = p.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        p.kill()
        p.communicate()
        report(False, "%s cancels the render" % name, "still running 20 s later")
        continue
    took = time.time() - t1
    err = err.decode(errors="replace")
    report(p.returncode == -sig and "cancelled by signal %d" % sig in err,
           "%s: ggrt dies of the signal and says so" % name,
           "exit %r, stderr %r" % (p.returncode, err))
    # The whole render takes about 10 s here; the progress callback stops
    # it within a few hundredths of that.
    report(took < 1.5, "%s stops the render at once (%.2fs)" % (name, took),
           "it took %.2fs: the render ran on" % took)
    with open(out, "rb") as f:
        report(f.read() == b"the previous image\n", "%s: the old output stays" % name,
               "old.png changed")
    left = sorted(os.listdir(d))
    report(left == ["old.png"], "%s: no temporary file left" % name, repr(left))
