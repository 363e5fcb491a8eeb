#!/usr/bin/env bash
# isolint at any size (issue "Crash-proof at any size", item 6): for each shape that hurts
# editors and linters (bench/gen_scaling.py --list: labels and jumps, nested IF, WHEN, `$`
# continuation chains, comments, CASE arms, many diagnostics, long lines, call chains and
# fan-out across files, many files in one folder) generates inputs of 1k, 10k and 100k (lines,
# or files/subprograms for the set shapes), times isolint on each (best of 3, text format) and
# prints the time per size and the growth exponent: the log-log slope between the two largest
# sizes (1.0 is linear). A slope above 1.15 is flagged "> n log n". A run that crashes (exit
# code above 2) or takes longer than LIMIT seconds is reported as such.
# Usage: bench/scaling.sh [BUILD_DIR] [SIZES] [SHAPES]
#   defaults: build-bench, "1000 10000 100000", every shape; LIMIT (env) defaults to 300.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-$here/../build-bench}
sizes=${2:-"1000 10000 100000"}
shapes=${3:-$(python3 "$here/gen_scaling.py" --list)}
limit=${LIMIT:-300}
. "$here/common.sh"
bench_build isolint
lint=$build/tools/isolint
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
results=$work/results.txt
: >"$results"
for shape in $shapes; do
  for n in $sizes; do
    dir=$work/$shape-$n
    path=$(python3 "$here/gen_scaling.py" "$shape" "$n" "$dir")
    # one run first: its exit code (0/1 fine, 2 usage, anything else a crash) and a time limit
    set +e
    timeout "$limit" "$lint" --color never "$path" >"$work/out.txt" 2>&1
    rc=$?
    set -e
    if [ "$rc" -eq 124 ]; then
      t=timeout
    elif [ "$rc" -gt 2 ]; then
      t="crash($rc)"
    else
      t=$(best "$lint" --color never "$path")
    fi
    echo "$shape $n $t $(tail -1 "$work/out.txt" | tr ' ' '_')" >>"$results"
    rm -rf "$dir"
  done
done
python3 - "$results" "$sizes" <<'PY'
import math, sys
rows = [l.split() for l in open(sys.argv[1]) if l.strip()]
sizes = [int(s) for s in sys.argv[2].split()]
by = {}
for shape, n, t, last in rows:
    by.setdefault(shape, {})[int(n)] = (t, last.replace("_", " "))
head = "shape".ljust(18) + "".join(f"{('n=' + str(n)):>12}" for n in sizes) + "   exponent"
print(head)
print("-" * len(head))
flagged = []
for shape, d in by.items():
    cells, times = [], []
    for n in sizes:
        t = d.get(n, ("-", ""))[0]
        try:
            v = float(t)
            cells.append(f"{v:11.3f}s")
            times.append(v)
        except ValueError:
            cells.append(f"{t:>12}")
            times.append(None)
    exp = "-"
    note = ""
    if len(sizes) >= 2 and times[-1] is not None and times[-2] is not None:
        a, b = max(times[-2], 1e-4), max(times[-1], 1e-4)
        e = math.log(b / a) / math.log(sizes[-1] / sizes[-2])
        exp = f"{e:.2f}"
        if e > 1.15:
            note = "  > n log n"
            flagged.append(shape)
    elif any(isinstance(t, str) and t != "-" for t in (d.get(n, ("-",))[0] for n in sizes)):
        note = "  FAILED"
        flagged.append(shape)
    print(shape.ljust(18) + "".join(cells) + f"{exp:>11}" + note)
print()
print("exponent: log-log slope between the two largest sizes; 1.00 = linear")
print("largest input's last line of output:")
for shape, d in by.items():
    print(f"  {shape}: {d.get(sizes[-1], ('', ''))[1]}")
if flagged:
    print("flagged: " + ", ".join(flagged))
PY
