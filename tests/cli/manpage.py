# SPDX-License-Identifier: MIT
"""docs/ggrt.1 documents every command and option that --help prints, and
nothing else: each command's own options in its "ggrt CMD ..." subsection,
the shared render options under RENDER OPTIONS, --help and --version under
OPTIONS. Prints one "ok NAME" or "FAIL NAME: why" line per check.
usage: manpage.py GGRT docs/ggrt.1"""
import re
import subprocess
import sys

ggrt, manpath = sys.argv[1], sys.argv[2]
OPT = re.compile(r"(?<![\w-])(--[a-z][\w-]*|-[a-zA-Z])(?![\w-])")


def report(good, name, why=""):
    print(("ok   %s" % name) if good else ("FAIL %s: %s" % (name, why)))


def help_of(*words):
    p = subprocess.run([ggrt, *words, "--help"], capture_output=True, text=True)
    if p.returncode != 0:
        report(False, "ggrt %s --help" % " ".join(words), "exit %d" % p.returncode)
    return p.stdout


def blocks(text):
    """{heading: [lines]} for each 'heading:' line at column 0."""
    out, cur = {}, None
    for line in text.splitlines():
        if re.match(r"^\S.*:$", line) and not line.startswith("usage"):
            cur = line[:-1]
            out[cur] = []
        elif not line.strip():
            cur = None
        elif cur is not None:
            out[cur].append(line)
    return out


def help_options(text):
    """(own, shared): the options of the 'options' and 'render options' blocks."""
    own, shared = set(), set()
    for head, lines in blocks(text).items():
        if "options" not in head:
            continue
        dst = shared if head.startswith("render options") else own
        for line in lines:
            m = re.match(r"^  (?:(-\w)(?:, (--[\w-]+))?|    (--[\w-]+))", line)
            if m:
                dst.update(o for o in m.groups() if o)
    return own - {"-h", "--help"}, shared - {"-h", "--help"}


def man_sections(path):
    """{section title: set of options in its .TP tags}; .SS titles are
    'ggrt CMD ...', .SH titles upper case."""
    secs, cur, tag = {}, None, False
    for raw in open(path, encoding="utf-8"):
        line = re.sub(r"\\f[BIRP]", "", raw.rstrip("\n")).replace("\\-", "-")
        line = line.replace('"', "")
        if line.startswith(".SH ") or line.startswith(".SS "):
            cur = line[4:].strip()
            secs[cur] = set()
            tag = False
        elif line.startswith(".TP"):
            tag = True
        elif tag and cur is not None:
            secs[cur].update(OPT.findall(line))
            tag = False
    return secs


man = man_sections(manpath)
top = help_of()
top_blocks = blocks(top)
commands = [l.split()[0] for l in top_blocks.get("commands", [])]
report(bool(commands), "ggrt --help lists commands", top)
report("--version" in top, "ggrt --help mentions --version")
report({"--help", "-h", "--version"} <= man.get("OPTIONS", set()),
       "ggrt(1) OPTIONS documents -h, --help, --version", repr(man.get("OPTIONS")))

shared_all = set()
for c in commands:
    key = [s for s in man if s == "ggrt " + c or s.startswith("ggrt %s " % c)]
    if not key:
        report(False, "ggrt(1) has a section for '%s'" % c, "no .SS \"ggrt %s ...\"" % c)
        continue
    text = help_of(c)
    own, shared = help_options(text)
    # Commands with forms (optics) have a --help per form.
    for form in [l.split()[0] for l in blocks(text).get("forms", [])]:
        o, s = help_options(help_of(c, form))
        own |= o
        shared |= s
    shared_all |= shared
    documented = man[key[0]]
    missing, extra = sorted(own - documented), sorted(documented - own)
    report(not missing, "ggrt(1) documents every option of '%s' (%d)" % (c, len(own)),
           "not in the man page's section: %s" % " ".join(missing))
    report(not extra, "ggrt(1) documents no option '%s' lacks" % c,
           "in the man page but not in --help: %s" % " ".join(extra))
    render = man.get("RENDER OPTIONS", set())
    report(shared <= render, "ggrt(1) RENDER OPTIONS covers those of '%s'" % c,
           "missing: %s" % " ".join(sorted(shared - render)))
for s in man:
    if s.startswith("ggrt ") and s.split()[1] not in commands and not s.split()[1].startswith("-"):
        report(False, "ggrt(1) section '%s' is a command" % s, "not in ggrt --help")
extra = sorted(man.get("RENDER OPTIONS", set()) - shared_all)
report(not extra, "ggrt(1) RENDER OPTIONS lists only real options",
       "not in any --help: %s" % " ".join(extra))
