# SPDX-License-Identifier: MIT
# bash completion for ggrt: commands, optics forms and bench subcommands,
# each command's options (an optics form's and a benchmark's own), the choices an option
# lists (--format text|json), the names and values of NAME=VALUE lists
# (-a offset=fixed,shadows=opaque) and file names where an option or
# argument takes a file. Everything is
# read from ggrt's own --help at the moment of completing, so it knows
# what that ggrt knows; nothing here lists an option.
# `make install` puts it in $(BASHCOMPDIR) as "ggrt", where bash-completion
# loads it the first time ggrt is completed; or source it from ~/.bashrc.

# The ggrt being completed: the word typed, if it names a program (a
# build tree's build/ggrt), else the one on PATH.
_ggrt_prog() {
    local p=${COMP_WORDS[0]}
    [[ $p == */* && -x $p && ! -d $p ]] && { printf '%s\n' "$p"; return; }
    printf 'ggrt\n'
}

# _ggrt_section HELP TITLE: the first word of each line of the section
# "TITLE:" of a --help text (commands:, forms:).
_ggrt_section() {
    printf '%s\n' "$1" | awk -v t="$2:" '
        $0 == t { on = 1; next }
        on && /^[^ ]/ { on = 0 }
        on && /^  [a-z]/ { print $1 }'
}

# _ggrt_benches HELP: the benchmarks of ggrt bench --help, from its usage
# lines ("ggrt bench spd|counts [options]").
_ggrt_benches() {
    printf '%s\n' "$1" | sed -n 's/^\(usage:\)\{0,1\} *ggrt bench \([a-z][a-z|]*\).*/\2/p' | tr '|' ' '
}

# _ggrt_options HELP: one line per option of a --help text, "NAMES META",
# NAMES as "-o,--output" or "--pixel", META the value's name or "".
_ggrt_options() {
    printf '%s\n' "$1" | awk '
        /^  -[a-zA-Z], --|^      --[a-z]/ {
            s = $0; sub(/^ +/, "", s); sub(/  .*/, "", s)
            n = split(s, w, " "); names = ""; meta = ""
            for (i = 1; i <= n; i++)
                if (w[i] ~ /^-/) { sub(/,$/, "", w[i]); names = names (names == "" ? "" : ",") w[i] }
                else { meta = w[i]; break }
            print names, meta
        }'
}

# _ggrt_desc HELP OPTION: OPTION's entry in a --help text, its first line
# and the lines indented under it, joined.
_ggrt_desc() {
    printf '%s\n' "$1" | awk -v o="$2" '
        on && (/^  -/ || /^[^ ]/ || /^$/) { exit }
        on { printf " %s", $0 }
        !on && /^  / { s = $0; sub(/  [^ -].*/, "", s); n = split(s, w, /[ ,]+/)
            for (i = 1; i <= n; i++) if (w[i] == o) { on = 1; printf "%s", $0 } }'
}

# _ggrt_pairs META CUR OPTION HELP WORDS...: complete the last element of
# a NAME=VALUE,... list (--accuracy offset=fixed,sph): a NAME, or a
# VALUE for the NAME typed. Names and values come from "name=a|b" in the
# option's --help entry; where it has none, from the parser's message
# for a bad list ("a NAME of x, y and a LEVEL of p, q"). Placeholders in
# capitals (EPS, W) are not offered.
_ggrt_pairs() {
    local meta=$1 cur=$2 opt=$3 help=$4 pre elem name names vals desc err a b
    shift 4
    pre="" elem=$cur
    [[ $cur == *,* ]] && pre=${cur%,*}, elem=${cur##*,}
    desc=$(_ggrt_desc "$help" "$opt" | grep -oE '[a-z][a-z0-9-]*=[a-z0-9|-]*')
    if [[ -n $desc ]]; then
        names=$(printf '%s\n' "$desc" | sed 's/=.*//')
        [[ $elem == *=* ]] && vals=$(printf '%s\n' "$desc" | sed -n "s/^${elem%%=*}=//p" | tr '|' ' ')
    else
        a=${meta%%=*} b=${meta#*=} b=${b%%,*}
        err=$("$@" "$opt" '?' --ggrt-completion-probe 2>&1 >/dev/null </dev/null)
        names=$(printf '%s\n' "$err" | sed -n "s/.* $a of \(.*\) and a $b of .*/\1/p" | tr -d ',')
        vals=$(printf '%s\n' "$err" | sed -n "s/.* and a $b of \(.*\)/\1/p" | tr -d ',')
    fi
    if [[ $elem == *=* ]]; then
        name=${elem%%=*}
        mapfile -t COMPREPLY < <(compgen -P "$pre$name=" -W "$vals" -- "${elem#*=}")
    else
        mapfile -t COMPREPLY < <(compgen -P "$pre" -S = -W "$names" -- "$elem")
        compopt -o nospace 2>/dev/null
    fi
}

# _ggrt_value META CUR OPTION WORDS...: complete OPTION's value, named
# META in --help: a file or folder, or one of the values the parser
# lists when given one it does not know ("expected one of text, json").
# That probe ends with an option no command has, so it stops at parsing
# whatever the value does: nothing runs.
_ggrt_value() {
    local meta=$1 cur=$2 opt=$3 err
    shift 3
    case $meta in
        *DIR*) mapfile -t COMPREPLY < <(compgen -d -- "$cur") ;;
        *FILE* | *PATH* | *BIN* | *.exr* | *.png* | *.json* | SCENE*)
            mapfile -t COMPREPLY < <(compgen -f -- "$cur") ;;
        *)
            err=$("$@" "$opt" '?' --ggrt-completion-probe 2>&1 >/dev/null </dev/null)
            err=$(printf '%s\n' "$err" | sed -n "s/.* for $opt: expected one of //p" | head -n 1)
            mapfile -t COMPREPLY < <(compgen -W "${err//,/ }" -- "$cur") ;;
    esac
}

_ggrt() {
    local prog cur prev i w cmd="" sub="" subpos=0 help opts names meta cword=-1 strip r
    local -a path=() words=()
    COMPREPLY=()
    # bash splits a word at '=' (COMP_WORDBREAKS): --format=te arrives as
    # "--format" "=" "te", -a offset=fixed,sh as "-a" "offset" "=" "fixed,sh".
    # Join them again into the words as typed.
    for ((i = 0; i <= COMP_CWORD; i++)); do
        w=${COMP_WORDS[i]}
        if ((cword >= 0)) && [[ $w == = || ${COMP_WORDS[i - 1]} == = ]]; then
            words[cword]+=$w
        else
            words[++cword]=$w
        fi
    done
    cur=${words[cword]}
    prev=""
    ((cword > 0)) && prev=${words[cword - 1]}
    [[ $cur == --*=* ]] && prev=${cur%%=*} cur=${cur#*=}
    _ggrt_complete
    # What bash replaces is the part of the word after its last '=': the
    # completions go back without what comes before it.
    strip=""
    [[ $cur == *=* ]] && strip=${cur%=*}=
    [[ -n $strip ]] && for i in "${!COMPREPLY[@]}"; do
        r=${COMPREPLY[i]}
        COMPREPLY[i]=${r#"$strip"}
    done
}

# _ggrt's work on words[0..cword], cur and prev, filling COMPREPLY.
_ggrt_complete() {
    prog=$(_ggrt_prog)
    # The command: the first word after ggrt that is not an option.
    for ((i = 1; i < cword; i++)); do
        w=${words[i]}
        [[ $w == -* ]] && continue
        cmd=$w subpos=$((i + 1))
        break
    done
    if [[ -z $cmd ]]; then
        if [[ $cur == -* ]]; then
            mapfile -t COMPREPLY < <(compgen -W "--help --version" -- "$cur")
        else
            mapfile -t COMPREPLY < <(compgen -W "$(_ggrt_section "$("$prog" --help 2>/dev/null)" commands) help" -- "$cur")
        fi
        return
    fi
    if [[ $cmd == help ]]; then
        if ((cword == subpos)); then
            mapfile -t COMPREPLY < <(compgen -W "$(_ggrt_section "$("$prog" --help 2>/dev/null)" commands)" -- "$cur")
        elif ((cword == subpos + 1)) && [[ ${words[subpos]} == optics ]]; then
            mapfile -t COMPREPLY < <(compgen -W "$(_ggrt_section "$("$prog" optics --help 2>/dev/null)" forms)" -- "$cur")
        elif ((cword == subpos + 1)) && [[ ${words[subpos]} == bench ]]; then
            mapfile -t COMPREPLY < <(compgen -W "$(_ggrt_benches "$("$prog" bench --help 2>/dev/null)")" -- "$cur")
        fi
        return
    fi
    path=("$prog" "$cmd")
    help=$("$prog" "$cmd" --help 2>/dev/null) || return
    # optics FORM and bench SUB: the word after the command, from the
    # forms: section or the usage's a|b|c.
    if [[ $cmd == optics || $cmd == bench ]]; then
        if ((cword == subpos)) && [[ $cur != -* ]]; then
            if [[ $cmd == optics ]]; then
                mapfile -t COMPREPLY < <(compgen -W "$(_ggrt_section "$help" forms)" -- "$cur")
            else
                mapfile -t COMPREPLY < <(compgen -W "$(_ggrt_benches "$help")" -- "$cur")
            fi
            return
        fi
        # optics FORM and bench NAME: the options of its own --help
        sub=${words[subpos]}
        if [[ $sub != -* && -n $sub ]]; then
            help=$("$prog" "$cmd" "$sub" --help 2>/dev/null) || return
            path+=("$sub")
        fi
    fi
    opts=$(_ggrt_options "$help")
    # A value for the option before the cursor.
    if [[ $prev == -* ]]; then
        while read -r names meta; do
            [[ ,$names, == *",$prev,"* ]] || continue
            # the parser's messages name the long option: probe with it
            [[ $meta == [A-Z]*=[A-Z]*,* ]] && { _ggrt_pairs "$meta" "$cur" "${names##*,}" "$help" "${path[@]}"; return; }
            [[ -n $meta ]] && { _ggrt_value "$meta" "$cur" "${names##*,}" "${path[@]}"; return; }
            break
        done <<<"$opts"
    fi
    if [[ $cur == -* ]]; then
        mapfile -t COMPREPLY < <(compgen -W "$(printf '%s\n' "$opts" | awk '{ gsub(/,/, " ", $1); print $1 }')" -- "$cur")
        return
    fi
    # Positional arguments: scenes, images, tiles, reports; a folder where
    # the usage's first argument is DIR (optics seeds DIR).
    if [[ $help =~ ^usage:\ ggrt\ [a-z\ ]*\ DIR ]]; then
        mapfile -t COMPREPLY < <(compgen -d -- "$cur")
    else
        mapfile -t COMPREPLY < <(compgen -f -- "$cur")
    fi
}
complete -o filenames -o bashdefault -F _ggrt ggrt
