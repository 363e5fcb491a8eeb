#!/usr/bin/env bash
# isolint on one program in a folder of large programs: generates a main program of LINES
# lines (default 100,000) alone in a folder, and the same program beside 9 subprograms of
# the same size that it does not call; times isolint on the main program in both folders, in
# the same run. The ratio crowd/alone shows what the siblings cost (a sibling is parsed only
# when called: the ratio should stay near 1 for time and memory).
# Usage: bench/isolint_siblings.sh [LINES] [BUILD_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
lines=${1:-100000}
build=${2:-$here/../build-bench}
. "$here/common.sh"
bench_build isolint
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/alone" "$work/crowd"
python3 "$here/gen_program.py" "$lines" "$work/alone/big.mpf" >/dev/null
cp "$work/alone/big.mpf" "$work/crowd/big.mpf"
for i in 1 2 3 4 5 6 7 8 9; do
  { echo "PROC SUB$i SAVE"; tail -n +2 "$work/alone/big.mpf" | sed 's/M30/M17/'; } > "$work/crowd/s$i.spf"
done
t_alone=$(best "$build/tools/isolint" --color never "$work/alone/big.mpf")
t_crowd=$(best "$build/tools/isolint" --color never "$work/crowd/big.mpf")
m_alone=$(peak "$build/tools/isolint" --color never "$work/alone/big.mpf")
m_crowd=$(peak "$build/tools/isolint" --color never "$work/crowd/big.mpf")
bytes=$(stat -c %s "$work/alone/big.mpf")
python3 - "$lines" "$bytes" "$t_alone" "$t_crowd" "$m_alone" "$m_crowd" <<'PY'
import sys
n, b, ta, tc, ma, mc = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5]), int(sys.argv[6])
print(f"main program: {n} lines, {b/1e6:.1f} MB; crowd: the same beside 9 uncalled subprograms of that size")
print(f"alone: {ta:.3f} s  peak RSS {ma/1024:.0f} MiB")
print(f"crowd: {tc:.3f} s  peak RSS {mc/1024:.0f} MiB")
print(f"ratio crowd/alone: time {tc/ta:.2f}x, memory {mc/ma:.2f}x")
PY
