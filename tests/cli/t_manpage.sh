# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: docs/ggrt.1 against every --help
# (tests/cli/manpage.py says how). A new option without a man-page entry
# fails here.
python3 tests/cli/manpage.py "$ggrt" docs/ggrt.1 >"$tmp/man" 2>&1
while IFS= read -r line; do
  case "$line" in
    "ok   "*) ok "${line#ok   }" ;;
    "FAIL "*) bad "${line#FAIL }" ;;
    *) bad "manpage.py: $line" ;;
  esac
done < "$tmp/man"
grep -q '^ok' "$tmp/man" || bad "manpage.py ran" "$(cat "$tmp/man")"
