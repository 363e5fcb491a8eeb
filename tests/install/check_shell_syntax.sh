#!/bin/sh
# install/completion-zsh, install/completion-fish: the generated scripts parse (zsh -n,
# fish --no-execute), and fish completes choices for real. Skipped (77) when the shell is
# not installed (.ci/deps.sh installs zsh and fish).
#
# Usage: check_shell_syntax.sh zsh|fish COMPLETIONS_DIR
set -u
shell=$1 dir=$2
if ! command -v "$shell" >/dev/null 2>&1; then
  echo "$shell is not installed: skipped"
  exit 77
fi
fail=0
for tool in isolint isocc isosim isofmt; do
  case $shell in
    zsh) file=$dir/zsh/_$tool; set -- zsh -n "$file" ;;
    fish) file=$dir/fish/$tool.fish; set -- fish --no-execute "$file" ;;
    *) echo "unknown shell $shell"; exit 2 ;;
  esac
  if [ ! -s "$file" ]; then
    echo "FAIL: $file is missing"
    fail=1
  elif ! "$@"; then
    echo "FAIL: $* reports errors"
    fail=1
  fi
done
# fish can also complete without a terminal: ask it for the choices of --dialect and --format
if [ "$shell" = fish ] && [ "$fail" -eq 0 ]; then
  got=$(fish -c "source $dir/fish/isosim.fish; complete -C 'isosim --dialect '" | cut -f1 | sort | tr '\n' ' ')
  [ "$got" = "sidac z32 " ] || { echo "FAIL: fish completes 'isosim --dialect ' as '$got'"; fail=1; }
  got=$(fish -c "source $dir/fish/isolint.fish; complete -C 'isolint --format '" | cut -f1 | sort | tr '\n' ' ')
  [ "$got" = "github json sarif text " ] || { echo "FAIL: fish completes 'isolint --format ' as '$got'"; fail=1; }
fi
[ "$fail" -eq 0 ] && echo "the $shell completions of isolint, isocc and isosim parse"
exit "$fail"
