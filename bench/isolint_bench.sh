#!/usr/bin/env bash
# isolint throughput: generates a program of LINES lines (default 1,000,000; SIDAC blocks and
# classic word-address blocks), then times isolint on it beside `wc -l` on the same file, in
# the same run. Prints MB/s, the ratio to wc -l, and isolint's peak memory.
# Usage: bench/isolint_bench.sh [LINES] [BUILD_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
lines=${1:-1000000}
build=${2:-$here/../build-bench}
. "$here/common.sh"
bench_build isolint
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prog=$work/bench.mpf
python3 "$here/gen_program.py" "$lines" "$prog"
bytes=$(stat -c %s "$prog")
t_lint=$(best "$build/tools/isolint" --color never "$prog")
t_lint1=$(best "$build/tools/isolint" --color never -j 1 "$prog")
t_wc=$(best wc -l "$prog")
rss=$(peak "$build/tools/isolint" --color never "$prog")
diags=$("$build/tools/isolint" --color never "$prog" | tail -1)
python3 - "$bytes" "$lines" "$t_lint" "$t_lint1" "$t_wc" "$rss" "$diags" <<'PY'
import sys
b, n, tl, tl1, tw, rss, diags = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5]), int(sys.argv[6]), sys.argv[7]
mb = b / 1e6
print(f"program: {n} lines, {mb:.1f} MB ({diags.strip()})")
print(f"isolint:      {tl:.3f} s  {mb/tl:8.1f} MB/s  {n/tl/1e6:.2f} M lines/s  peak RSS {rss/1024:.0f} MiB")
print(f"isolint -j 1: {tl1:.3f} s  {mb/tl1:8.1f} MB/s")
print(f"wc -l:        {tw:.3f} s  {mb/tw:8.1f} MB/s")
print(f"ratio isolint/wc -l time: {tl/tw:.1f}x")
PY
