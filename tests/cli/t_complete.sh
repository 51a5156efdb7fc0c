# SPDX-License-Identifier: MIT
# Sourced by tests/cli/run.sh: the bash completion (cli/completion.bash)
# over every command, optics form and bench subcommand ggrt's --help
# lists: the commands, each one's long options (exactly its --help's),
# the values of every option that takes one of a list (exactly what the
# parser says it expects), and file names after -o and for a scene.
# Uses run.sh's ggrt, tmp, ok, bad, skip.

if ! command -v bash >/dev/null; then
  skip "bash completion" "no bash on this machine"
else
cat > "$tmp/comp.bash" <<'EOF'
. cli/completion.bash
# comp WORD...: the completions of the last word, one a line, sorted.
comp() { COMP_WORDS=("$@"); COMP_CWORD=$((${#COMP_WORDS[@]} - 1)); COMPREPLY=(); _ggrt
         printf '%s\n' "${COMPREPLY[@]}" | sed '/^$/d' | sort -u; }
"$@"
EOF
comp() { bash "$tmp/comp.bash" comp "$ggrt" "$@"; }
# longs HELP-ARGS...: the long options of a --help, one a line, sorted
# (an option's line starts "  -x, --name" or "      --name"; a help text's
# own lines are indented further).
longs() { "$ggrt" "$@" --help | grep -E '^(  -[a-zA-Z], |      )--[a-z]' |
          sed -E 's/^ +(-[a-zA-Z], )?(--[a-z][a-z0-9-]*).*/\2/' | sort -u; }

cmds=$("$ggrt" --help | awk '/^commands:/ { on = 1; next } on && /^[^ ]/ { on = 0 } on && NF { print $1 }' | sort)
got=$(comp "")
if [ "$got" = "$(printf '%s\nhelp\n' "$cmds" | sort)" ] && [ "$(comp re)" = render ]; then
  ok "completion: the commands of ggrt --help, and 're' to render"
else
  bad "completion: the commands" "got: $got"
fi
got=$(comp help "")
[ "$got" = "$cmds" ] && ok "completion: 'ggrt help' offers every command" ||
  bad "completion: 'ggrt help' offers every command" "got: $got"

forms=$("$ggrt" optics --help | awk '/^forms:/ { on = 1; next } on && /^[^ ]/ { on = 0 } on && NF { print $1 }' | sort)
got=$(comp optics "")
[ -n "$forms" ] && [ "$got" = "$forms" ] && ok "completion: optics offers its forms ($(echo $forms))" ||
  bad "completion: optics offers its forms" "got: $got; want: $forms"
subs=$("$ggrt" bench --help | sed -n 's/^\(usage:\)\{0,1\} *ggrt bench \([a-z][a-z|]*\).*/\2/p' | tr '|' '\n' | sort)
got=$(comp bench "")
[ "$(echo "$subs" | wc -l)" -ge 7 ] && [ "$got" = "$subs" ] && ok "completion: bench offers its subcommands ($(echo $subs))" ||
  bad "completion: bench offers its subcommands" "got: $got; want: $subs"

# Every command (optics by form, bench once with a subcommand): its long
# options, and each option's values where the parser lists them.
nopts=0 nchoice=0 nshort=0 failed=""
for c in $cmds; do
  case $c in
    optics) words=$(for f in $forms; do echo "optics:$f"; done) ;;
    bench) words=$(for b in $subs; do echo "bench:$b"; done) ;;
    *) words=$c ;;
  esac
  for w in $words; do
    set -- $(echo "$w" | tr ':' ' ')
    want=$(longs "$@")
    got=$(comp "$@" --)
    [ "$got" = "$want" ] || failed="$failed
$w: got $(echo $got), want $(echo $want)"
    for o in $want; do
      nopts=$((nopts + 1))
      [ $((nopts % sample)) -eq 0 ] || continue # GG_TEST_SAMPLE: one option in N
      err=$(bulk "$ggrt" "$@" "$o" '?' --ggrt-completion-probe 2>&1 >/dev/null)
      list=$(printf '%s\n' "$err" | sed -n "s/.* for $o: expected one of //p" | tr -d ',' | tr ' ' '\n' | sed '/^$/d' | sort)
      [ -n "$list" ] || continue
      nchoice=$((nchoice + 1))
      got=$(comp "$@" "$o" "")
      [ "$got" = "$list" ] || failed="$failed
$w $o: got $(echo $got), want $(echo $list)"
      # its short name, where it has one ("  -f, --format F")
      s=$("$ggrt" "$@" --help | sed -n "s/^  \(-[a-zA-Z]\), $o .*/\1/p")
      [ -z "$s" ] && continue
      nshort=$((nshort + 1))
      got=$(comp "$@" "$s" "")
      [ "$got" = "$list" ] || failed="$failed
$w $s: got $(echo $got), want $(echo $list)"
    done
  done
done
if [ -z "$failed" ] && [ $nchoice -ge $((5 / sample)) ]; then
  ok "completion: the long options of every command and form ($nopts), and the values of the $nchoice that take one of a list ($nshort by a short name too)"
else
  bad "completion: options and their values ($nopts options, $nchoice lists)" "$failed"
fi

# --format=j: bash hands the words "--format" "=" "j" (COMP_WORDBREAKS).
got=$(comp optics check --format = j)
got2=$(comp optics check --format =)
[ "$got" = json ] && [ "$got2" = "$(printf 'json\ntext')" ] &&
  ok "completion: a value after --format= and --format=j" ||
  bad "completion: a value after --format=" "--format=j: $got; --format=: $got2"

# NAME=VALUE lists (-a offset=fixed,shadows=opaque, --severity): every
# option whose value is one, in every command: the names offered, each
# with its values, every pair one the parser takes; then the list's last
# element completed after a comma, as bash splits the word at '='.
npairs=0 nnames=0 failed=""
for c in $cmds; do
  case $c in optics) continue ;; bench) set -- bench spd ;; *) set -- "$c" ;; esac
  for o in $("$ggrt" "$@" --help | sed -n 's/^ *\(-[a-zA-Z], \)\{0,1\}\(--[a-z-]*\) [A-Z]*=[A-Z]*,.*/\2/p'); do
    names=$(comp "$@" "$o" "")
    [ -n "$names" ] || failed="$failed
$* $o: no names offered"
    for n in $names; do
      nnames=$((nnames + 1))
      case $n in *=) ;; *) failed="$failed
$* $o: '$n' does not end in '='"; continue ;; esac
      for v in $(comp "$@" "$o" "${n%=}" =); do
        npairs=$((npairs + 1))
        err=$("$ggrt" "$@" "$o" "$n$v" --ggrt-completion-probe 2>&1 >/dev/null)
        case $err in *"unknown option '--ggrt-completion-probe'"*) ;; *) failed="$failed
$* $o $n$v: $err" ;; esac
      done
    done
  done
done
got=$(comp render -a offset = fixed,sh)
got2=$(comp check --severity near-tir = info,grazing = w)
if [ -z "$failed" ] && [ $npairs -ge 20 ] && [ "$got" = "fixed,shadows=" ] && [ "$got2" = warning ]; then
  ok "completion: NAME=VALUE lists ($nnames names, $npairs pairs, each taken by the parser), after a comma too"
else
  bad "completion: NAME=VALUE lists ($nnames names, $npairs pairs)" "$failed
offset=fixed,sh: $got; near-tir=info,grazing=w: $got2"
fi

got=$(comp help bench "")
[ "$got" = "$subs" ] && ok "completion: 'ggrt help bench' offers the benchmarks" ||
  bad "completion: 'ggrt help bench' offers the benchmarks" "got: $got"
got=$(comp help optics re)
[ "$got" = "$(printf 'reflect\nrefract')" ] && ok "completion: 'ggrt help optics' offers the forms" ||
  bad "completion: 'ggrt help optics' offers the forms" "got: $got"
got=$(comp optics seeds RE)
got2=$(comp render RE)
[ -z "$got" ] && [ "$got2" = README.md ] && ok "completion: folders only for optics seeds DIR" ||
  bad "completion: folders only for optics seeds DIR" "seeds RE: $got; render RE: $got2"

got=$(comp render -o examples/scenes/defa)
got2=$(comp render examples/scenes/defa)
got3=$(comp bench spd --spd examples/sce)
if [ "$got" = examples/scenes/default.nff ] && [ "$got2" = examples/scenes/default.nff ] &&
   [ "$got3" = examples/scenes ]; then
  ok "completion: file names after -o and for a scene, folders after --spd"
else
  bad "completion: file names" "after -o: $got; scene: $got2; --spd: $got3"
fi
fi
