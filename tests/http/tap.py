# SPDX-License-Identifier: MIT
"""TAP output for the HTTP suites, which tests/run-tests.sh reads: "ok N -
name" or "not ok N - name" per check, details as "# " lines, a skip as
"ok N - name # SKIP reason", and the plan "1..N" last (done())."""
import sys
import threading

passed = failed = count = 0
_lock = threading.Lock()


def _desc(name):
    # '#' would start a TAP directive.
    return str(name).replace("#", "\\#")


def ok(name):
    global passed, count
    with _lock:
        passed += 1
        count += 1
        print("ok %d - %s" % (count, _desc(name)), flush=True)


def bad(name, detail="", lines=30):
    global failed, count
    with _lock:
        failed += 1
        count += 1
        print("not ok %d - %s" % (count, _desc(name)))
        for line in str(detail).splitlines()[:lines] if detail != "" else []:
            print("# " + line)
        sys.stdout.flush()


def skip(name, reason):
    global count
    with _lock:
        count += 1
        print("ok %d - %s # SKIP %s" % (count, _desc(name), reason), flush=True)


def note(text):
    print("# " + text, flush=True)


def done(summary=""):
    """The plan and a closing comment; the exit status (0: no failure)."""
    print("1..%d" % count)
    note("http: %d passed, %d failed%s" % (passed, failed, (" " + summary) if summary else ""))
    return 0 if failed == 0 and count > 0 else 1
