# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: hostile inputs cost no more than their
# size (issue 32). A PNG texture whose ancillary chunk before IDAT
# declares 2^31 - 16 bytes (every ancillary kind libpng reads there, and
# an unknown one) made libpng allocate and zero 2 GiB before failing; -s
# over the image-size limit with --heatmap allocated the heat map before
# ggRender checked the size. Each runs on the plain build under
# `ulimit -v 262144` (256 MiB of address space), must exit 2 with the
# right message and a peak RSS under 64 MB (printed). Under ASan
# (build/asan), whose shadow memory cannot run under the ulimit, only the
# exit codes and messages are checked. Uses run.sh's ggrt, tmp, ok and bad.

ho="$tmp/hostile"
mkdir -p "$ho"
case $ggrt in */asan/*) asan=1 ;; *) asan= ;; esac

# under_64m CODE TEXT NAME CMD...: exit code and message under 256 MiB of
# address space, peak RSS under 64 MB.
under_64m() {
  want=$1; text=$2; name=$3; shift 3
  if [ -n "$asan" ]; then
    "$@" >/dev/null 2>"$tmp/err"; got=$?; mb=0
  else
    (ulimit -v 262144 && python3 -c '
import resource, subprocess, sys
rc = subprocess.run(sys.argv[2:], stdout=subprocess.DEVNULL, stderr=open(sys.argv[1], "w")).returncode
print(rc, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss // 1024)' "$tmp/err" "$@") >"$tmp/rss"
    read -r got mb <"$tmp/rss"
  fi
  if [ "$got" = "$want" ] && grep -qF -- "$text" "$tmp/err" && [ "${mb:-999}" -lt 64 ]
  then ok "$name: exit $got (peak RSS ${asan:+(ASan, not measured) }$mb MB)"
  else bad "$name (exit $got, want $want; peak RSS $mb MB, want < 64)" "want: $text
got:  $(cat "$tmp/err")"; fi
}

# A 4x4 RGB PNG with a chunk KIND before IDAT whose length field says
# 0x7ffffff0 and which holds 16 bytes.
python3 -c '
import struct, sys, zlib
def chunk(kind, data, n=None):
    n = len(data) if n is None else n
    return struct.pack(">I", n) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
raw = zlib.compress(b"".join(b"\0" + b"\x40" * 12 for _ in range(4)))
for kind in sys.argv[2:]:
    with open("%s/%s.png" % (sys.argv[1], kind), "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 4, 4, 8, 2, 0, 0, 0)) +
                chunk(kind.encode(), b"x" * 16, 0x7ffffff0) + chunk(b"IDAT", raw) + chunk(b"IEND", b""))
' "$ho" tEXt zTXt iTXt sPLT pCAL iCCP eXIf tIME prVt
for kind in tEXt zTXt iTXt sPLT pCAL iCCP eXIf tIME prVt; do
  printf 'v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 resolution 8 8\nl 1 1 5\ntexture "%s.png"\n%s\n' \
    "$kind" 'rect -1 -1 0 2 0 0 0 2 0' >"$ho/$kind.nff"
  under_64m 2 "ggrt render: $ho/$kind.nff:3:9: cannot read texture: $ho/$kind.png: invalid PNG: truncated file (byte 33: a chunk of 2147483632 bytes, 54 are left)" \
    "a $(wc -c <"$ho/$kind.png")-byte PNG whose $kind chunk says 2 GiB" \
    "$ggrt" render "$ho/$kind.nff" -q -o "$ho/x.png"
done

# Every command taking -s, at 65536x65536 (16 GiB of heat map) and at
# 8192x8192 (256 MiB, over the pixel limit too): the option parser refuses
# both (a usage error) before anything is loaded or allocated.
g=examples/scenes/glass.nff
for s in 65536x65536 8192x8192; do
  lim="bad value '$s' for --size: expected WxH, two whole numbers from 1 to 65536, at most 16777216 pixels"
  for k in rays depth time; do
    under_64m 1 "ggrt render: $lim" "render -s $s --heatmap $k" "$ggrt" render $g -s $s --heatmap $k -q -o "$ho/x.png"
  done
  under_64m 1 "ggrt render: $lim" "render -s $s" "$ggrt" render $g -s $s -q -o "$ho/x.png"
  under_64m 1 "ggrt check: $lim" "check -s $s" "$ggrt" check $g -s $s
  under_64m 1 "ggrt find: $lim" "find -s $s" "$ggrt" find $g -s $s --where 'some(kind == tir)' -o "$ho/x.png"
  under_64m 1 "ggrt diff: $lim" "diff -s $s" "$ggrt" diff $g $g -s $s
  under_64m 1 "ggrt trace: $lim" "trace -s $s" "$ggrt" trace $g -s $s --pixel 1,1
  # serve is refused as early; the timeout only matters if it were not.
  if "$ggrt" serve --help >/dev/null 2>&1; then
    under_64m 1 "ggrt serve: $lim" "serve -s $s" timeout 20 "$ggrt" serve $g -s $s --port 0
  fi
done
# A report of 1.3 million values (2.5 MiB of [1,1,...]): its nodes take one
# block of 32 bytes each (about 42 MB), where values grown array by array
# took about 75 MB.
python3 -c 'import sys; sys.stdout.write("[" + "1," * (5 << 18) + "1]")' >"$ho/ones.json"
under_64m 2 "ggrt merge: $ho/ones.json: not a JSON report: not an object" \
  "merge --reports: $(wc -c <"$ho/ones.json") bytes of [1,1,...]" \
  "$ggrt" merge -q --reports "$ho/ones.json" -o "$ho/x.json"
[ ! -e "$ho/x.png" ] && ok "refused hostile inputs leave no image" ||
  bad "refused hostile inputs leave no image"

# An 88 KB OBJ that is its own MTL library (1000 newmtl lines), named on
# 4000 mtllib lines: each library is read once. Read at every mtllib line,
# it took 1.16 GB and 4.4 s before the error at its last line.
python3 -c '
import sys
with open(sys.argv[1], "w") as f:
    f.write("".join("newmtl m%d\n" % i for i in range(1000)) + "mtllib selfmtl.obj\n" * 4000 +
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
' "$ho/selfmtl.obj"
under_64m 2 "ggrt info: $ho/selfmtl.obj:5004:7: vertex index 9 is out of range (3 defined so far)" \
  "a $(wc -c <"$ho/selfmtl.obj")-byte OBJ naming itself as its MTL library 4000 times" \
  "$ggrt" info "$ho/selfmtl.obj"

# A PNG texture with 100 zTXt chunks of 7.9 MB of text each, 7.7 KB
# compressed: libpng inflated and kept every one (about 800 MB for this
# 0.8 MB file; the reader now skips the chunks no sample depends on).
python3 -c '
import struct, sys, zlib
def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
text = chunk(b"zTXt", b"k\0\0" + zlib.compress(b"A" * 7900000, 9))
raw = zlib.compress(b"".join(b"\0" + b"\x40" * 12 for _ in range(4)))
with open(sys.argv[1], "wb") as f:
    f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 4, 4, 8, 2, 0, 0, 0)) +
            text * 100 + chunk(b"IDAT", raw) + chunk(b"IEND", b""))
' "$ho/ztxt.png"
printf 'v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 resolution 8 8\nl 1 1 5\ntexture "ztxt.png"\n%s\n' \
  'rect -1 -1 0 2 0 0 0 2 0' >"$ho/ztxt.nff"
under_64m 0 "rendered" "a $(wc -c <"$ho/ztxt.png")-byte PNG texture of 100 zTXt chunks (790 MB of text) reads" \
  sh -c '"$0" render "$1" -q -o "$2" && echo rendered >&2' "$ggrt" "$ho/ztxt.nff" "$ho/ztxt-out.png"
