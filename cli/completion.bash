# SPDX-License-Identifier: MIT
# bash completion for ggrt: commands, optics forms and bench subcommands,
# each command's options, the choices an option lists (--format text|json)
# and file names where an option or argument takes a file. Everything is
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
    local prog cur prev i w cmd="" sub="" subpos=0 help opts names meta
    local -a path=()
    COMPREPLY=()
    cur=${COMP_WORDS[COMP_CWORD]}
    prev=""
    ((COMP_CWORD > 0)) && prev=${COMP_WORDS[COMP_CWORD - 1]}
    # --format=te: bash splits it at the '=' (COMP_WORDBREAKS) into
    # "--format" "=" "te"; "--format=" alone ends in the word "=".
    if [[ $cur == = ]] && ((COMP_CWORD > 1)); then
        prev=${COMP_WORDS[COMP_CWORD - 1]} cur=""
    elif [[ $prev == = ]] && ((COMP_CWORD > 1)); then
        prev=${COMP_WORDS[COMP_CWORD - 2]}
    fi
    prog=$(_ggrt_prog)
    # The command: the first word after ggrt that is not an option.
    for ((i = 1; i < COMP_CWORD; i++)); do
        w=${COMP_WORDS[i]}
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
        if ((COMP_CWORD == subpos)); then
            mapfile -t COMPREPLY < <(compgen -W "$(_ggrt_section "$("$prog" --help 2>/dev/null)" commands)" -- "$cur")
        elif ((COMP_CWORD == subpos + 1)) && [[ ${COMP_WORDS[subpos]} == optics ]]; then
            mapfile -t COMPREPLY < <(compgen -W "$(_ggrt_section "$("$prog" optics --help 2>/dev/null)" forms)" -- "$cur")
        fi
        return
    fi
    path=("$prog" "$cmd")
    help=$("$prog" "$cmd" --help 2>/dev/null) || return
    # optics FORM and bench SUB: the word after the command, from the
    # forms: section or the usage's a|b|c.
    if [[ $cmd == optics || $cmd == bench ]]; then
        if ((COMP_CWORD == subpos)) && [[ $cur != -* ]]; then
            if [[ $cmd == optics ]]; then
                mapfile -t COMPREPLY < <(compgen -W "$(_ggrt_section "$help" forms)" -- "$cur")
            else
                mapfile -t COMPREPLY < <(compgen -W "$(printf '%s\n' "$help" |
                    sed -n 's/^\(usage:\)\{0,1\} *ggrt bench \([a-z|]*\).*/\2/p' | tr '|' ' ')" -- "$cur")
            fi
            return
        fi
        sub=${COMP_WORDS[subpos]}
        [[ $cmd == bench && $sub != -* && -n $sub ]] && path+=("$sub")
        if [[ $cmd == optics && $sub != -* && -n $sub ]]; then
            help=$("$prog" optics "$sub" --help 2>/dev/null) || return
            path+=("$sub")
        fi
    fi
    opts=$(_ggrt_options "$help")
    # A value for the option before the cursor.
    if [[ $prev == -* ]]; then
        while read -r names meta; do
            [[ ,$names, == *",$prev,"* ]] || continue
            # the parser's messages name the long option: probe with it
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
