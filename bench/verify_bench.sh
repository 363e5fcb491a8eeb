#!/usr/bin/env bash
# Verifying an image (issue 10, part 4): on a generated straight-line program of BLOCKS motion
# blocks (default 1,000,000; bench/gen_program.py --kind motion), compiled by isocc:
#   1. iso_verify_bench: CPU time of the verifier as a ratio of one pass over the image bytes
#      (CRC-32) measured in the same run, and the verifier's heap peak beside the image size;
#   2. whole processes (/usr/bin/time): `isocc --verify IMAGE` and isosim loading the image
#      (read, reader, verifier, translation; --max-steps 1), CPU seconds and peak RSS, beside
#      `cat IMAGE` and the image size.
# Usage: bench/verify_bench.sh [BLOCKS] [BUILD_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
blocks=${1:-1000000}
build=${2:-$here/../build-bench}
. "$here/common.sh"
bench_build isocc isosim
[ -x "$build/bench/iso_verify_bench" ] || cmake --build "$build" -j"$(nproc)" --target iso_verify_bench >/dev/null
cc=$build/tools/isocc
sim=$build/tools/isosim
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/straight"
python3 "$here/gen_program.py" "$((blocks + 6))" "$work/straight/straight.mpf" --kind motion
"$cc" "$work/straight/straight.mpf" -o "$work/straight.isob"
img=$work/straight.isob

"$build/bench/iso_verify_bench" "$img" 5

# cpu CMD...: "user+sys seconds, peak RSS KiB" of one run (best CPU of 3)
cpu() {
  local b="" r=""
  for _ in 1 2 3; do
    local line
    line=$(/usr/bin/time -f "%U %S %M" "$@" 2>&1 >/dev/null | tail -1)
    read -r u s m <<<"$line"
    local t
    t=$(python3 -c "print($u + $s)")
    if [ -z "$b" ] || python3 -c "import sys; sys.exit(0 if $t < $b else 1)"; then b=$t; r=$m; fi
  done
  echo "$b $r"
}
read -r t_cat m_cat <<<"$(cpu cat "$img")"
read -r t_ver m_ver <<<"$(cpu "$cc" --verify "$img")"
read -r t_sim m_sim <<<"$(cpu "$sim" "$img" --summary --max-steps 1)"
size=$(stat -c %s "$img")
python3 - <<PY
size = $size / 1024 / 1024
t_cat, t_ver, t_sim = float("$t_cat"), float("$t_ver"), float("$t_sim")
m_cat, m_ver, m_sim = int("$m_cat") / 1024, int("$m_ver") / 1024, int("$m_sim") / 1024
print(f"whole processes on the image ({size:.1f} MiB), CPU seconds (best of 3) and peak RSS:")
print(f"  cat IMAGE                     {t_cat:6.3f} s  {m_cat:6.1f} MiB")
print(f"  isocc --verify IMAGE          {t_ver:6.3f} s  {m_ver:6.1f} MiB = {m_ver/size:.2f} x the image")
print(f"  isosim IMAGE --max-steps 1    {t_sim:6.3f} s  {m_sim:6.1f} MiB = {m_sim/size:.2f} x the image"
      "  (with the translation for the interpreter)")
PY
