# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: truncated or short image data is an error,
# never uninitialised memory. The image fuzz corpus
# (tests/fuzz/corpus/image: truncated PNGs and EXRs, an uncompressed EXR
# chunk shorter than its pixels) replays under valgrind with no error, and
# ggrt refuses a texture with a short chunk. valgrind cannot run the ASan
# build, so build/asan skips the valgrind runs (tests/unit/imageio/test_truncated.c
# covers both builds). Uses run.sh's ggrt, tmp, ok, bad, skip and t_args.sh's
# expect_msg.

tr="$tmp/trunc"
mkdir -p "$tr"
python3 tests/data/hostile.py "$tr"
printf 'texture "short.exr"\nrect -1 -1 0 2 0 0 0 2 0\n' >"$tr/t.nff"
expect_msg 2 "ggrt render: $tr/t.nff:1:9: cannot read texture: $tr/short.exr: invalid OpenEXR file: chunk 1 holds 20 bytes, its pixels take 48" \
  "an uncompressed EXR chunk shorter than its pixels is refused" "$ggrt" render "$tr/t.nff" -q -o "$tr/x.png"
replay="$(dirname "$ggrt")/tests/replay_image"
case $ggrt in
  */asan/*) ;;
  *)
    if command -v valgrind >/dev/null 2>&1; then
      vg="valgrind -q --error-exitcode=99"
      $vg "$replay" tests/fuzz/corpus/image >"$tmp/out" 2>"$tmp/err"; got=$?
      if [ $got = 0 ] && [ ! -s "$tmp/err" ]; then
        ok "valgrind clean: $vg replay_image tests/fuzz/corpus/image ($(sed -n 's/.*: \([0-9]*\) inputs.*/\1/p' "$tmp/out") inputs)"
      else bad "valgrind clean on tests/fuzz/corpus/image (exit $got)" "$(head -30 "$tmp/err")"; fi
      $vg "$ggrt" render "$tr/t.nff" -q -o "$tr/x.png" >/dev/null 2>"$tmp/err"; got=$?
      if [ $got = 2 ] && ! grep -q "^==" "$tmp/err"; then ok "valgrind clean: ggrt render with the short EXR chunk (exit 2)"
      else bad "valgrind clean: ggrt render with the short EXR chunk (exit $got)" "$(head -30 "$tmp/err")"; fi
    else
      skip "valgrind runs" "valgrind is not installed (scripts/deps.sh check installs it)"
    fi ;;
esac
