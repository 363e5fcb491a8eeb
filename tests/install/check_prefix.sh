#!/bin/sh
# install/prefix: `cmake --install BUILD --prefix PREFIX` into an empty directory, then checks
# what is there: the three tools run (--version), every man page of man/ is installed in its
# section and `groff -man -ww -z` is silent on the installed copy, and the bash, zsh and fish
# completions of each tool are installed and are what the installed tool prints.
#
# Usage: check_prefix.sh CMAKE BUILD_DIR PREFIX BINDIR MANDIR DATADIR MAN_SOURCE_DIR
set -u
cmake=$1 build=$2 prefix=$3 bindir=$4 mandir=$5 datadir=$6 mansrc=$7
fail=0
problem() {
  echo "install/prefix: $*"
  fail=1
}

rm -rf "$prefix"
mkdir -p "$prefix" || exit 1
if ! "$cmake" --install "$build" --prefix "$prefix" >"$prefix.log" 2>&1; then
  cat "$prefix.log"
  echo "install/prefix: cmake --install failed"
  exit 1
fi

for tool in isolint isocc isosim isofmt; do
  bin=$prefix/$bindir/$tool
  if [ ! -x "$bin" ]; then
    problem "$bindir/$tool is not installed"
    continue
  fi
  version=$("$bin" --version) || problem "$bindir/$tool --version failed"
  case $version in
    "$tool "*) ;;
    *) problem "$bindir/$tool --version printed '$version'" ;;
  esac
  for shell in bash zsh fish; do
    case $shell in
      bash) file=$prefix/$datadir/bash-completion/completions/$tool ;;
      zsh) file=$prefix/$datadir/zsh/site-functions/_$tool ;;
      fish) file=$prefix/$datadir/fish/vendor_completions.d/$tool.fish ;;
    esac
    if [ ! -s "$file" ]; then
      problem "the $shell completion of $tool is not installed at ${file#"$prefix"/}"
    elif ! "$bin" --completion "$shell" | cmp -s - "$file"; then
      problem "${file#"$prefix"/} differs from '$tool --completion $shell'"
    fi
  done
done

pages=0
for page in "$mansrc"/*.[157]; do
  name=${page##*/}
  installed=$prefix/$mandir/man${name##*.}/$name
  pages=$((pages + 1))
  if [ ! -f "$installed" ]; then
    problem "man page $name is not installed at ${installed#"$prefix"/}"
    continue
  fi
  cmp -s "$page" "$installed" || problem "${installed#"$prefix"/} differs from man/$name"
  if command -v groff >/dev/null 2>&1; then
    out=$(groff -man -ww -z "$installed" 2>&1) || problem "groff failed on ${installed#"$prefix"/}"
    [ -z "$out" ] || problem "groff -man -ww -z ${installed#"$prefix"/}: $out"
  fi
done
[ "$pages" -ge 5 ] || problem "only $pages man pages in $mansrc"

if [ "$fail" -eq 0 ]; then
  echo "install/prefix: 3 tools, $pages man pages and 9 completions under $prefix"
fi
exit "$fail"
