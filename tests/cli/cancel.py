# SPDX-License-Identifier: MIT
"""SIGINT and SIGTERM cancel `ggrt render` through the library's progress
callback: the process dies of the signal, says so, leaves the old output as
it was and no temporary file; SIGTERM does the same to a tile, to ggrt
plan's measuring, to trace --svg's camera view, to trace --scene-obj's
write and to find's paths pass.
Also checks that ggrt never wrote into its argv (/proc/PID/cmdline while
it runs), and that render, a tile, plan, find,
check and diff draw their progress bar on a terminal (a pseudo-terminal
here) and not under -q, and every command that reads a scene its
loading and preparing bars once GGRT_PROGRESS_DELAY has passed.
Prints one "ok NAME" or "FAIL NAME: why" line per check.
usage: cancel.py GGRT TMPDIR"""
import os
import re
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


def signal_and_wait(p, sig):
    """Send sig to p and wait: its stderr, or None if it still ran 20 s
    later (then it is killed)."""
    p.send_signal(sig)
    try:
        _, err = p.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        p.kill()
        p.communicate()
        return None
    return err.decode(errors="replace")


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
    err = signal_and_wait(p, sig)
    if err is None:
        report(False, "%s cancels the render" % name, "still running 20 s later")
        continue
    took = time.time() - t1
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


def start_over(args, out):
    """args started with the ordinary signal dispositions, out first
    holding "the previous file"."""
    with open(out, "wb") as f:
        f.write(b"the previous file\n")
    return subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            preexec_fn=default_signals)


def cancel_other(what, args, out):
    """SIGTERM during a tile's render or a plan's measuring: dies of it,
    says so, keeps the old output and leaves no temporary file."""
    d = os.path.dirname(out)
    p = start_over(args, out)
    t0 = time.time()
    while not caught(p.pid, signal.SIGTERM) and p.poll() is None and time.time() - t0 < 30:
        time.sleep(0.01)
    if not caught(p.pid, signal.SIGTERM):
        p.kill()
        p.communicate()
        report(False, "%s installs a handler" % what, "no handler in SigCgt")
        return
    time.sleep(0.3)
    err = signal_and_wait(p, signal.SIGTERM)
    if err is None:
        report(False, "SIGTERM cancels %s" % what, "still running 20 s later")
        return
    report(p.returncode == -signal.SIGTERM and
           "cancelled by signal %d; %s not written" % (signal.SIGTERM, out) in err,
           "SIGTERM: %s dies of the signal and says so" % what,
           "exit %r, stderr %r" % (p.returncode, err))
    with open(out, "rb") as f:
        report(f.read() == b"the previous file\n", "SIGTERM: %s keeps the old output" % what,
               "the file changed")
    left = sorted(os.listdir(d))
    report(left == [os.path.basename(out)], "SIGTERM: %s leaves no temporary file" % what,
           repr(left))


# A plan was killed silently (no handler); a tile said so from the start.
d = os.path.join(tmp, "cancel-plan")
os.makedirs(d)
cancel_other("ggrt plan", [ggrt, "plan", SCENE, "--tiles", "4", "-s", "1024x768", "-n", "9",
                           "-j", "1", "--scale", "1", "-o", os.path.join(d, "p.json")],
             os.path.join(d, "p.json"))
d = os.path.join(tmp, "cancel-tile")
os.makedirs(d)
cancel_other("a tile", [ggrt, "render", SCENE, "--tile", "0/2", "-s", "1024x768", "-n", "9",
                        "-j", "1", "-o", os.path.join(d, "t.exr")], os.path.join(d, "t.exr"))


# A render whose one tile is long (16x16 pixels of 256 samples through
# nested glass, about 20 s): the cancel waited for the tile, some 15 s.
# The tile's per-pixel loop now asks the progress callback as it goes.
d = os.path.join(tmp, "cancel-long-tile")
os.makedirs(d)
out = os.path.join(d, "n.png")
p = start_over([ggrt, "render", "tests/data/nested-glass.nff", "-s", "16x16", "-n", "256", "-j",
                "1", "-q", "-o", out], out)
t0 = time.time()
while not caught(p.pid, signal.SIGTERM) and p.poll() is None and time.time() - t0 < 30:
    time.sleep(0.01)
time.sleep(1)
t1 = time.time()
err = signal_and_wait(p, signal.SIGTERM)
waited = time.time() - t1
report(err is not None and p.returncode == -signal.SIGTERM and waited < 5,
       "SIGTERM: a render of one long tile stops within the tile",
       "exit %r after %.1f s, stderr %r" % (p.returncode, waited, err))

# trace --svg renders a camera view first (seconds, deep): it was not
# cancellable and left OUT.tmpPID and a /tmp file behind on a signal.
d = os.path.join(tmp, "cancel-svg")
os.makedirs(d)
cancel_other("trace --svg", [ggrt, "trace", "examples/scenes/glass.nff", "--pixel", "110,100",
                             "-d", "64", "-j", "1", "--svg", os.path.join(d, "t.svg")],
             os.path.join(d, "t.svg"))

def cancel_while_writing(what, args, out, bound=None):
    """SIGTERM once args' temporary file beside out has begun to grow:
    ggrt dies of it and says so (within bound seconds, if given), keeps
    out as it was and leaves no temporary file."""
    d = os.path.dirname(out)
    p = start_over(args, out)
    t0 = time.time()
    started = False
    while p.poll() is None and time.time() - t0 < 60 and not started:
        started = any(".tmp" in n and os.path.getsize(os.path.join(d, n)) > 0
                      for n in os.listdir(d))
        time.sleep(0.01)
    if not started:
        p.kill()
        p.communicate()
        report(False, "%s: SIGTERM while it writes" % what, "the write was not seen")
        return
    t1 = time.time()
    err = signal_and_wait(p, signal.SIGTERM)
    took = time.time() - t1
    report(err is not None and p.returncode == -signal.SIGTERM and
           "cancelled by signal %d; %s not written" % (signal.SIGTERM, out) in err,
           "SIGTERM: %s dies of it while it writes and says so" % what,
           "exit %r, stderr %r" % (p.returncode, err))
    if bound is not None:
        report(took < bound, "SIGTERM stops %s at once" % what,
               "it took %.2fs: the write ran on" % took)
    with open(out, "rb") as f:
        report(f.read() == b"the previous file\n", "SIGTERM: %s keeps the old file" % what,
               "the file changed")
    left = sorted(os.listdir(d))
    report(left == [os.path.basename(out)], "SIGTERM: %s leaves no temporary file" % what,
           repr(left))


# find --paths-jsonl traces every matched pixel again after its scan:
# SIGTERM in that pass was lost (the files were written, exit 0). The
# signal goes once the paths file has begun (its temporary file grows).
d = os.path.join(tmp, "cancel-paths")
os.makedirs(d)
out = os.path.join(d, "p.jsonl")
cancel_while_writing("find --paths-jsonl", [ggrt, "find", "examples/scenes/glass.nff", "-s",
                                            "300x225", "-j", "1", "-q", "--path", "C.*", "--limit",
                                            "1", "--paths-jsonl", out], out)

# trace --scene-obj of rough implicit surfaces took seconds with the
# signals held: SIGTERM at 3 s took effect at 9 s, once the file (436 MB)
# was complete. It must stop within a surface (12 s before), write
# nothing and leave no temporary file.
d = os.path.join(tmp, "cancel-scene-obj")
os.makedirs(d)
rough = os.path.join(tmp, "rough.nff")
with open(rough, "w") as f:
    for i in range(8):
        f.write('implicit "sin(50*x)+sin(50*y)+sin(50*z)+%g" -1 -1 -1 1 1 1\n' % (i / 10))
out = os.path.join(d, "s.obj")
cancel_while_writing("trace --scene-obj", [ggrt, "trace", rough, "-p", "8,8", "--scene-obj", out],
                     out, bound=5.0)


def on_terminal(args, delay=None):
    """stderr of args run on a pseudo-terminal (the bar is drawn only there),
    with GGRT_PROGRESS_DELAY set to delay unless it is None."""
    import pty
    env = dict(os.environ)
    env.pop("GGRT_PROGRESS_DELAY", None)
    if delay is not None:
        env["GGRT_PROGRESS_DELAY"] = delay
    pid, fd = pty.fork()
    if pid == 0:
        os.execve(args[0], args, env)
    out = b""
    while True:
        try:
            chunk = os.read(fd, 65536)
        except OSError:
            break
        if not chunk:
            break
        out += chunk
    os.waitpid(pid, 0)
    return out.decode(errors="replace")


# The progress bar: a whole render had it; a tile and a plan's measuring
# renders were silent until the end.
d = os.path.join(tmp, "bars")
os.makedirs(d)
for what, args, label in (
        ("render", [ggrt, "render", SCENE, "-s", "128x96", "-o", os.path.join(d, "w.png")], "\r["),
        ("a tile", [ggrt, "render", SCENE, "-s", "128x96", "--tile", "1/2", "-o",
                    os.path.join(d, "t.exr")], "\rtile 1/2 ["),
        ("ggrt plan", [ggrt, "plan", SCENE, "-s", "128x96", "--tiles", "2", "-o",
                       os.path.join(d, "p.json")], "\rmeasuring 3/3 ["),
        ("ggrt find", [ggrt, "find", SCENE, "-s", "128x96", "-w", "some(kind == reflect)"],
         "\rfind ["),
        ("ggrt check", [ggrt, "check", SCENE, "-s", "128x96"], "\rcheck ["),
        ("ggrt diff", [ggrt, "diff", SCENE, "-s", "128x96", "--b", "depth=2"], "\rdiff [")):
    text = on_terminal(args)
    report(label in text and "100%" in text, "%s draws a progress bar on a terminal" % what,
           repr(text[-300:]))
    q = on_terminal(args + ["-q"])
    report(label not in q and "] 100%" not in q, "%s -q draws none" % what, repr(q[-300:]))
    report("loading [" not in text and "preparing [" not in text,
           "%s: no loading bar for a scene read in under half a second" % what, repr(text[:300]))

# Loading and preparing show bars once they take half a second: with
# GGRT_PROGRESS_DELAY=0 every command that reads a scene draws both
# (and not under -q); with a long delay no bar at all, the work's too.
for what, args, quiet in (
        ("render", [ggrt, "render", SCENE, "-s", "32x24", "-o", os.path.join(d, "w.png")], "-q"),
        ("ggrt plan", [ggrt, "plan", SCENE, "-s", "32x24", "--tiles", "2", "-o",
                       os.path.join(d, "p.json")], "-q"),
        ("ggrt find", [ggrt, "find", SCENE, "-s", "32x24", "-w", "some(kind == reflect)"], "-q"),
        ("ggrt check", [ggrt, "check", SCENE, "-s", "32x24"], "-q"),
        ("ggrt diff", [ggrt, "diff", SCENE, "-s", "32x24", "--b", "depth=2"], "-q"),
        ("ggrt trace", [ggrt, "trace", SCENE, "-p", "10,10"], None),
        ("ggrt info", [ggrt, "info", SCENE], None)):
    text = on_terminal(args, "0")
    report("\rloading [" in text and "\rpreparing [" in text and "] 100%" in text,
           "%s: GGRT_PROGRESS_DELAY=0 draws the loading and preparing bars" % what,
           repr(text[:400]))
    if quiet:
        q = on_terminal(args + [quiet], "0")
        report("loading [" not in q and "preparing [" not in q,
               "%s %s: GGRT_PROGRESS_DELAY=0 draws no loading bar" % (what, quiet), repr(q[:300]))
    late = on_terminal(args, "600")
    report(not re.search(r"\] +[0-9]+%", late),
           "%s: GGRT_PROGRESS_DELAY=600 draws no bar" % what, repr(late[:300]))
text = on_terminal([ggrt, "info", SCENE], "soon")
report("GGRT_PROGRESS_DELAY=soon: not a number" in text and "loading [" not in text,
       "GGRT_PROGRESS_DELAY that is not a number: a warning, and the default delay",
       repr(text[:300]))
text = on_terminal([ggrt, "trace", SCENE, "-p", "10,10", "--format", "json"], "0")
report("loading [" not in text, "trace --format json: no loading bar", repr(text[:300]))
