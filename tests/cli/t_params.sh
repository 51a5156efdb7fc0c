# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: physically invalid scene parameters are
# errors at the value that set them (file:line:col), exit 2, for every
# command that loads a scene (docs/scene-format.md, "Parameter ranges").
# Uses run.sh's ggrt, tmp, ok, bad and expect_err.

# param NAME TEXT MESSAGE: the scene TEXT fails with "ggrt render: FILE:MESSAGE".
param() {
  printf "$2" > "$tmp/param.nff"
  expect_err 2 "ggrt render: $tmp/param.nff:$3" "params: $1 (exit 2 at the value)" \
    "$ggrt" render "$tmp/param.nff" -s 8x6 -q -o "$tmp/param.png"
}
pre='l 0 5 5\n'
param "negative colour" "${pre}f 1 -0.5 1 1 0 1 0 0\ns 0 0 0 1\n" \
  "2:5: the colour must not be negative, got -0.5"
param "material error at the f line, not the object's" "f 1 1 1 -1 0 1 0 0\n\n\ns 0 0 0 1\n" \
  "1:9: Kd (the diffuse weight) must not be negative, got -1"
param "negative ks" "f 1 1 1 1 -0.25 1 0 0\ns 0 0 0 1\n" \
  "1:11: Ks (the specular weight) must not be negative, got -0.25"
param "negative Phong exponent" "f 1 1 1 1 0.5 -3 0 0\ns 0 0 0 1\n" \
  "1:15: the Phong exponent must not be negative, got -3"
param "negative kt" "f 1 1 1 1 0 1 -0.5 1.5\ns 0 0 0 1\n" \
  "1:15: T (the transmittance) must not be negative, got -0.5"
param "negative light" "l 1 2 3 1 1 -2\ns 0 0 0 1\n" \
  "1:13: a light's colour must not be negative, got -2"
param "negative ambient" "ambient 0.1 -0.1 0.1\ns 0 0 0 1\n" \
  "1:13: ambient must not be negative, got -0.1"
param "negative background" "b 0 0 -1\ns 0 0 0 1\n" \
  "1:7: the background must not be negative, got -1"
param "zero conductor index" "conductor 0.2 0 0.3  3 0 3\ns 0 0 0 1\n" \
  "1:15: conductor: n and k are both 0 in the G channel (the index n + ik must not be 0)"
param "from == at" "v\nfrom 0 0 5\nat 0 0 5\nup 0 1 0\nangle 40\nresolution 8 6\ns 0 0 0 1\n" \
  "3:4: view: 'from' and 'at' are the same point (or within 1e-9 of their size)"
param "up parallel to the view" "v\nfrom 0 0 5\nat 0 0 0\nup 0 0 -3\nangle 40\nresolution 8 6\n" \
  "4:4: view: 'up' is parallel to the view direction"
param "zero up" "v\nfrom 0 0 5\nat 0 0 0\nup 0 0 0\nangle 40\nresolution 8 6\n" \
  "4:4: view: 'up' is the zero vector"
param "zero angle" "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 0\n" \
  "5:7: angle must be in (0, 180), got 0"
# The same error from the other commands that load scenes.
printf 'f 1 1 1 1 0 1 0 0\nb -1 0 0\ns 0 0 0 1\n' > "$tmp/param.nff"
for c in trace info check; do
  o=""; [ $c = trace ] && o="--pixel 1,1"
  # shellcheck disable=SC2086
  expect_err 2 "ggrt $c: $tmp/param.nff:2:3: the background must not be negative, got -1" \
    "params: $c reports it too (exit 2)" "$ggrt" $c "$tmp/param.nff" $o
done
