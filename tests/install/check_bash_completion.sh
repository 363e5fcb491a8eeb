#!/bin/bash
# install/completion-bash: loads the generated bash completions (the files that `cmake --install`
# installs) in a non-interactive bash and asks them what they complete.
#
# Usage: check_bash_completion.sh COMPLETIONS_DIR
set -u
dir=$1
fail=0

# complete TOOL WORD...: what the completion of TOOL offers for the last WORD, one a line.
complete_words() {
  local tool=$1
  shift
  (
    # shellcheck disable=SC1090
    source "$dir/bash/$tool" || exit 1
    COMP_WORDS=("$tool" "$@")
    COMP_CWORD=$#
    "_$tool" || exit 1
    printf '%s\n' "${COMPREPLY[@]}"
  )
}

# expect 'WANTED WORDS' TOOL WORD...: the offers, sorted, joined with spaces.
expect() {
  local want=$1 got
  shift
  got=$(complete_words "$@" | LC_ALL=C sort | tr '\n' ' ')
  got=${got% }
  if [ "$got" != "$want" ]; then
    echo "FAIL: completing '$*' offers '$got', expected '$want'"
    fail=1
  fi
}

for tool in isolint isocc isosim isofmt; do
  if [ ! -s "$dir/bash/$tool" ]; then
    echo "FAIL: $dir/bash/$tool is missing (built by the target 'completions')"
    exit 1
  fi
  registered=$(source "$dir/bash/$tool" && complete -p "$tool")
  [ "$registered" = "complete -F _$tool $tool" ] || { echo "FAIL: $tool registers '$registered'"; fail=1; }
done

expect "--format" isolint --for
expect "github json sarif text" isolint --format ""
expect "json" isolint --format j
expect "github json sarif text" isolint --format = ""   # = in COMP_WORDBREAKS: three words
expect "--format=sarif" isolint --format=s       # = not in COMP_WORDBREAKS: one word
expect "always auto never" isolint --color ""
expect "" isolint --jobs ""                       # a number: nothing to offer
expect "sidac z32" isosim --dialect ""
expect "csv github json" isosim --format ""
expect "off on" isosim --optional-stop ""
expect "" isosim --feed-override ""                # a percent: nothing to offer
expect "" isosim --rapid-override ""
expect "--feed-override" isosim --feed
expect "hex" isocc --dump ""
expect "--dialect --disasm" isocc --di
expect "" isolint --comp                         # the hidden --completion is not offered

# Files: isolint and isocc offer .mpf/.spf files (any case) and directories, isosim any file.
work=$(mktemp -d) || exit 1
trap 'rm -rf "$work"' EXIT
mkdir "$work/set"
touch "$work/a.mpf" "$work/B.SPF" "$work/notes.txt" "$work/c.isob"
cd "$work" || exit 1
expect "B.SPF a.mpf set" isolint ""
expect "B.SPF a.mpf set" isocc --werror ""
expect "a.mpf" isolint a
expect "B.SPF a.mpf c.isob notes.txt set" isosim ""
expect "B.SPF a.mpf c.isob notes.txt set" isosim --machine ""
expect "B.SPF a.mpf c.isob notes.txt set" isocc --disasm ""
expect "c.isob set" isocc -o ""

[ "$fail" -eq 0 ] && echo "install/completion-bash: all completions as expected"
exit "$fail"
