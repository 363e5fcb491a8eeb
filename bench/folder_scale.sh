#!/usr/bin/env bash
# isocc and isosim on small programs alone in their folder, and in the same folder beside 9
# main programs of LINES lines each (default 1,200,000: about 30 MB, bench/gen_program.py)
# that nothing calls: time (best of RUNS runs, default 5) and peak RSS of `isocc MAIN -o OUT`
# and `isosim MAIN --summary`, and the ratios crowd/alone (the folder must not matter: goal
# <= 1.1x for time and memory). The programs are samples/ sets, copied (the generated files
# live in a temporary folder and are removed at the end).
# Usage: bench/folder_scale.sh [LINES] [BUILD_DIR] [SET/MAIN.mpf...]
#   RUNS=N   runs per time (default 5)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
lines=${1:-1200000}
build=${2:-$here/../build-bench}
shift $(($# < 2 ? $# : 2))
programs=("$@")
[ ${#programs[@]} -gt 0 ] || programs=(pallet_loader/pallettizzatore.mpf semi_auto/fresatura_cornice.mpf
                                      drilling_when/foratura_piastra.mpf z32_toolchange/fresatura_flangia.mpf)
runs=${RUNS:-5}
. "$here/common.sh"
bench_build isocc isosim
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/cams" "$work/alone" "$work/crowd"
python3 "$here/gen_program.py" "$lines" "$work/cams/cam1.mpf" >/dev/null
for i in 2 3 4 5 6 7 8 9; do cp "$work/cams/cam1.mpf" "$work/cams/cam$i.mpf"; done
cam_bytes=$(stat -c %s "$work/cams/cam1.mpf")

# fastest CMD...: wall seconds of the best of $runs runs, output discarded
fastest() {
  local b="" s e t
  for ((k = 0; k < runs; ++k)); do
    s=$(date +%s%N); "$@" >/dev/null 2>&1 || true; e=$(date +%s%N)
    t=$((e - s))
    if [ -z "$b" ] || [ "$t" -lt "$b" ]; then b=$t; fi
  done
  python3 -c "print($b / 1e9)"
}

rows=()
for p in "${programs[@]}"; do
  set_dir=${p%%/*}
  [ -d "$here/../samples/$set_dir" ] || { echo "no sample set $set_dir" >&2; exit 2; }
  cp -r "$here/../samples/$set_dir" "$work/alone/$set_dir"
  cp -r "$here/../samples/$set_dir" "$work/crowd/$set_dir"
  for i in 1 2 3 4 5 6 7 8 9; do ln "$work/cams/cam$i.mpf" "$work/crowd/$set_dir/cam$i.mpf"; done
  for tool in isocc isosim; do
    for where in alone crowd; do
      main=$work/$where/$p
      if [ "$tool" = isocc ]; then
        cmd=("$build/tools/isocc" "$main" -o "$work/$where.isob")
      else
        cmd=("$build/tools/isosim" "$main" --summary)
      fi
      "${cmd[@]}" >/dev/null 2>"$work/err" || { echo "failed: ${cmd[*]}" >&2; cat "$work/err" >&2; exit 1; }
      t=$(fastest "${cmd[@]}")
      m=$(peak "${cmd[@]}")
      eval "t_$where=\$t; m_$where=\$m"
    done
    rows+=("$p $tool $t_alone $t_crowd $m_alone $m_crowd")
  done
done

python3 - "$lines" "$cam_bytes" "$runs" "${rows[@]}" <<'PY'
import sys
lines, cam, runs = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
print(f"crowd: the program's folder plus 9 main programs of {lines} lines ({cam / 1e6:.1f} MB each) that it "
      f"does not call; times: best of {runs}")
print(f"{'program':38} {'tool':6} {'alone s':>8} {'crowd s':>8} {'time':>6} {'alone MiB':>9} {'crowd MiB':>9} "
      f"{'memory':>6}")
worst_t = worst_m = 0.0
for row in sys.argv[4:]:
    p, tool, ta, tc, ma, mc = row.split()
    ta, tc, ma, mc = float(ta), float(tc), int(ma), int(mc)
    rt, rm = tc / ta, mc / ma
    worst_t, worst_m = max(worst_t, rt), max(worst_m, rm)
    print(f"{p:38} {tool:6} {ta:8.3f} {tc:8.3f} {rt:5.2f}x {ma / 1024:9.1f} {mc / 1024:9.1f} {rm:5.2f}x")
print(f"worst ratio crowd/alone: time {worst_t:.2f}x, memory {worst_m:.2f}x (goal <= 1.1x)")
PY
