#!/bin/sh
# SPDX-License-Identifier: MIT
# Every repository path that README.md, docs/ (docs/log/ aside: the journal
# keeps the names of its day), the Makefile and the sources' comments name
# must exist. Checked:
#  - path names under the top folders (lib/, cli/, include/, tests/, docs/,
#    examples/, bench/, scripts/) and the top files; a `*` in a name must
#    match a file; a placeholder folder or file name (PLACEHOLDERS below,
#    as in lib/L/ or examples/scenes/NAME.nff) matches any name;
#  - names under build/: the files the Makefile makes (GENERATED below);
#  - a program may be named by its source without the extension
#    (tests/unit/geom/test_bvh_scalar for tests/unit/geom/test_bvh_scalar.c);
#  - markdown links, relative to their file, and their #anchors (a heading
#    of the target);
#  - cited sections, `FILE.md, "Heading"`: a heading or a paragraph of
#    that file starts with the cited words (markup aside);
#  - a Makefile variable a comment cites (an opening parenthesis, then
#    "Makefile, " and the name) is one the Makefile sets.
# Then it plants a missing file, a broken link, a missing section and a
# missing Makefile variable in a temporary copy of README.md and checks
# that each is reported, so the test cannot pass by finding nothing.
#   sh tests/build/paths.sh          (make check runs it)
cd "$(dirname "$0")/../.." || exit 1
command -v python3 >/dev/null || { echo "paths: needs python3"; exit 1; }
tmp=$(mktemp -d /tmp/ggrt-paths-XXXXXX)
trap 'rm -rf "$tmp"' EXIT

cat > "$tmp/check.py" <<'PY'
import glob, os, re, sys

root = sys.argv[1]
os.chdir(root)
TOPS = "lib|cli|include|tests|docs|examples|bench|scripts"
TOPFILES = {"Makefile", "README.md", "LICENSE", "ggrt.pc.in", "ggrt-core.pc.in"}
# Names that stand for any folder or file in a path (lib/L/ is "a layer's
# folder", examples/scenes/NAME.nff "a scene").
PLACEHOLDERS = {"L", "LAYER", "NAME", "SCENE", "CMD", "GROUP", "FILE", "X", "DIR",
                "MODEL", "KIND", "FORMAT", "SUITE", "HARNESS", "dir", "name", "layer"}
# What the Makefile makes under $(BUILD) (build/ by default; make check's
# trees are build/release, build/asan and build/tsan).
GENERATED = [r"release|asan|tsan|o2|o3", r"(release/|asan/|tsan/|o2/|o3/)?ggrt", r"(release/)?libggrt(-core)?\.(a|so)(\.0|\.0\.1\.0)?",
             r"(release/)?libtextbook_refract\.so", r"(\w+/)?(ggrt|ggrt-core)\.pc", r"stage(/.*)?",
             r"(release/|asan/|tsan/)?tests/[\w/]+", r"(\w+/)*tap(/.*)?", r"(\w+/)?(cli|lib|tests|bench|scalar)/.*\.[cho]",
             r"(\w+/)?bench/\w+", r"browser/[\w*-]+\.png", r"fuzz(/.*)?", r"api\.(h|so)\.txt",
             r"(\w+/)?cli/serve\.flag", r"examples(/.*)?"]

def sources():
    out = ["README.md", "Makefile"]
    for p in sorted(glob.glob("docs/**", recursive=True)):
        if os.path.isfile(p) and not p.startswith("docs/log/") and p.endswith((".md", ".1")):
            out.append(p)
    for top in ("lib", "cli", "include", "tests", "bench", "examples", "scripts"):
        for p in sorted(glob.glob(top + "/**", recursive=True)):
            if os.path.isfile(p) and p.endswith((".c", ".h", ".sh", ".py", ".js", ".html", ".css")) \
               and "/corpus/" not in p:
                out.append(p)
    return out

def comments(path, text):
    """A doc and the Makefile whole, a source's comments."""
    if path.endswith(".md") or path == "Makefile":
        return text
    if path.endswith(".1"):
        return text.replace("\\-", "-")
    if path.endswith((".c", ".h", ".js", ".css")):
        parts = re.findall(r"/\*.*?\*/|//[^\n]*", text, re.S)
        return "\n".join(re.sub(r"^[ \t]*\*+", " ", p, flags=re.M) for p in parts)
    if path.endswith(".html"):
        return "\n".join(re.findall(r"<!--.*?-->", text, re.S))
    # sh, py, Makefile: # comments (not #include, #!).
    return "\n".join(m.group(1) for m in re.finditer(r"(?:^|\s)#(?![!{(])([^\n]*)", text))

def isa_again():
    """The objects the Makefile's ISA_AGAIN builds from another source."""
    # (its value may go on over lines ending in a backslash)
    m = re.search(r"^ISA_AGAIN\s*=((?:[^\n]*\\\n)*[^\n]*)", open("Makefile").read(), re.M)
    return {w.split(":")[0] for w in m.group(1).replace("\\", " ").split()} if m else set()

def exists(p):
    p = p.rstrip("/")
    if p.startswith("lib/") and p.endswith(".o"):
        return os.path.exists(p[:-2] + ".c") or p in isa_again()
    if p.startswith("build/"):
        rest = p[len("build/"):]
        return any(re.fullmatch(g, rest) for g in GENERATED)
    parts = ["*" if c in PLACEHOLDERS or re.fullmatch(r"[A-Z][A-Z0-9_]*", c.split(".")[0] or "x")
             and c.split(".")[0] in PLACEHOLDERS else c for c in p.split("/")]
    parts = ["*" + c[c.index("."):] if c.split(".")[0] in PLACEHOLDERS and "." in c else c for c in parts]
    q = "/".join(parts)
    if "*" in q or "?" in q or "[" in q:
        return bool(glob.glob(q))
    return os.path.exists(q) or any(os.path.isfile(q + e) for e in (".c", ".sh", ".py"))

PATH_RE = re.compile(r"(?<![\w./$-])((?:%s)/[A-Za-z0-9_.*/-]*[A-Za-z0-9_*/]|build/[A-Za-z0-9_.*/-]*[A-Za-z0-9_*])" % TOPS)

def slug(h):
    h = h.strip().lower()
    h = re.sub(r"[^\w\- ]", "", h)
    return h.replace(" ", "-")

heads_cache = {}
def headings(md):
    if md not in heads_cache:
        try:
            text = open(md, encoding="utf-8", errors="replace").read()
        except OSError:
            text = ""
        plain = lambda t: re.sub(r"\s+", " ", re.sub(r"[`*_]", "", t)).strip()
        hs = [plain(m.group(1)) for m in re.finditer(r"^#{1,6}\s+(.*)$", text, re.M)]
        paras = [plain(m.group(1)) for m in re.finditer(r"(?:\A|\n\n)([^\n#|].*)", text)]
        heads_cache[md] = (hs, paras)
    return heads_cache[md]

def makefile_vars():
    text = open("Makefile").read()
    return set(re.findall(r"^([A-Za-z_][A-Za-z0-9_]*)\s*(?::=|\?=|\+=|=)", text, re.M)) | \
           set(re.findall(r"^define\s+(\w+)", text, re.M))

bad = []
mvars = makefile_vars()
for src in sources():
    text = open(src, encoding="utf-8", errors="replace").read()
    prose = comments(src, text)
    flat = re.sub(r"\s+", " ", prose)
    for m in PATH_RE.finditer(prose):
        p = m.group(1).rstrip(".")
        if p.endswith("/*"):
            p = p[:-2]
        if prose[m.end():m.end() + 1] in ("%", "$"):
            p += "*"  # a make pattern or a shell variable completes the name
        if not exists(p):
            bad.append("%s: names %s, which does not exist" % (src, p))
    if src.endswith(".md"):
        for m in re.finditer(r"\]\(([^)\s]+)\)", text):
            t = m.group(1)
            if re.match(r"[a-z]+:", t):
                continue
            f, _, anchor = t.partition("#")
            target = os.path.normpath(os.path.join(os.path.dirname(src), f)) if f else src
            if f and not os.path.exists(target):
                bad.append("%s: links to %s, which does not exist" % (src, t))
            elif anchor and target.endswith(".md") and anchor not in [slug(h) for h in headings(target)[0]]:
                bad.append("%s: links to %s, which has no heading #%s" % (src, target, anchor))
    for m in re.finditer(r"((?:[\w./-]+/)?[\w-]+\.md),? \"([^\"]+)\"", flat):
        md, cited = m.group(1), m.group(2).strip().rstrip(".,")
        cands = [md, os.path.join(os.path.dirname(src), md), os.path.join("docs", md)]
        target = next((c for c in cands if os.path.isfile(c)), None)
        if target is None:
            continue  # the file itself is the path check's
        hs, bold = headings(target)
        if not any(h.startswith(cited) for h in hs + bold):
            bad.append("%s: cites %s, \"%s\", which has no such heading" % (src, target, cited))
    for m in re.finditer(r"\(Makefile, ([A-Za-z_][A-Za-z0-9_]*)", flat):
        if m.group(1) not in mvars:
            bad.append("%s: cites the Makefile variable %s, which the Makefile does not set" % (src, m.group(1)))

for b in sorted(set(bad)):
    print("paths: " + b)
print("paths: %d sources checked, %d missing names" % (len(sources()), len(set(bad))))
sys.exit(1 if bad else 0)
PY

python3 "$tmp/check.py" "$(pwd)" > "$tmp/out" 2>&1
rc=$?
cat "$tmp/out"
[ $rc = 0 ] || exit 1

# The planted names: a copy of README.md in a tree that is otherwise this
# one (links), with one name of each kind that does not exist.
mkdir "$tmp/tree"
for f in * .[!.]*; do
  [ -e "$f" ] && [ "$f" != README.md ] && ln -s "$(pwd)/$f" "$tmp/tree/$f"
done
cp README.md "$tmp/tree/README.md"
cat >> "$tmp/tree/README.md" <<'EOF'

Planted: lib/core/no_such_file.c, [a link](docs/no-such-page.md),
[an anchor](docs/performance.md#no-such-section), docs/performance.md,
"No such section", and (Makefile, NO_SUCH_VARIABLE).
EOF
python3 "$tmp/check.py" "$tmp/tree" > "$tmp/planted" 2>&1 && { cat "$tmp/planted"; echo "paths: planted names passed"; exit 1; }
for want in "names lib/core/no_such_file.c" "links to docs/no-such-page.md" "no heading #no-such-section" \
            "\"No such section\", which has no such heading" "variable NO_SUCH_VARIABLE"; do
  grep -qF "README.md: " "$tmp/planted" && grep -qF "$want" "$tmp/planted" ||
    { cat "$tmp/planted"; echo "paths: a planted name was not reported ($want)"; exit 1; }
done
echo "paths: the 5 planted names (file, link, anchor, section, Makefile variable) are reported"
