#!/usr/bin/env bash
# check_format.sh SOURCE_DIR: every C++ file of the project (lib/, tools/, tests/, bench/)
# follows .clang-format. Prints each file that does not, with the command that fixes it.
# Exit 0 when all do, 1 otherwise, 77 (CTest SKIP) when clang-format is not installed.
set -u
src=${1:?usage: check_format.sh SOURCE_DIR}
cf=$(command -v clang-format || true)
if [ -z "$cf" ]; then
  echo "clang-format is not installed (Debian: apt-get install clang-format): skipped"
  exit 77
fi
cd "$src" || exit 1
bad=0
n=0
while IFS= read -r f; do
  n=$((n + 1))
  if ! "$cf" --dry-run -Werror "$f" >/dev/null 2>&1; then
    echo "not formatted: $f (run: clang-format -i $f)"
    bad=$((bad + 1))
  fi
done < <(find lib tools tests bench -type f \( -name '*.cpp' -o -name '*.h' \) -not -path '*/node_modules/*' | sort)
echo "$n files checked with $("$cf" --version | head -1): $bad not formatted"
[ "$bad" -eq 0 ]
