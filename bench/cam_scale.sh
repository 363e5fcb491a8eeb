#!/usr/bin/env bash
# The speed and memory table at CAM scale in one run, as ratios measured side by side:
#   1. isolint on a SIDAC program of LINES lines (default 1,200,000) alone in its folder, beside
#      the minimal tokenizer of ../shared/bench-peers/floor (built here with g++ -O2): time
#      ratio (goal <= 3x) and peak RSS over the file size (goal <= 5x);
#   2. the same program beside 9 subprograms of its size (the folder must not matter);
#   3. isocc --strip image size over the source size, beside gzip -9 and xz -9 (goal <= 25 %);
#   4. isosim --summary on the image of MOTION motion blocks (default 1,000,000) beside the floor
#      on the image's source (goal <= 5x) and its peak RSS (goal <= 100 MiB).
#   5. isocc on the LINES-line program beside isolint (goal <= 1.5x) and its peak RSS (<= 5x
#      the file); isosim on the motion source beside isocc + isosim on its image (<= 1.0x);
#      isosim's peak RSS on the stripped image beside twice the image + 16 MiB.
# The folder rows (a small program beside 9 programs of 30 MB) are bench/folder_scale.sh's.
# The floor is skipped (its ratios print as -) when ../shared/bench-peers is not there.
# Usage: bench/cam_scale.sh [LINES] [MOTION] [BUILD_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
lines=${1:-1200000}
motion=${2:-1000000}
build=${3:-$here/../build-bench}
. "$here/common.sh"
bench_build isolint isocc isosim
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
floor_src=$here/../../shared/bench-peers/floor/floor_lex.cpp
floor=""
if [ -f "$floor_src" ]; then
  g++ -O2 -std=c++20 "$floor_src" -o "$work/floor_lex" && floor=$work/floor_lex
fi
mkdir -p "$work/alone" "$work/crowd" "$work/motion"
prog=$work/alone/cam.mpf
python3 "$here/gen_program.py" "$lines" "$prog" >/dev/null
cp "$prog" "$work/crowd/cam.mpf"
for i in 1 2 3 4 5 6 7 8 9; do
  { echo "PROC SUB$i SAVE"; tail -n +2 "$prog" | sed 's/M30/M17/'; } > "$work/crowd/s$i.spf"
done
mprog=$work/motion/motion.mpf
python3 "$here/gen_program.py" "$motion" "$mprog" --kind motion >/dev/null
"$build/tools/isocc" "$mprog" -o "$work/motion.isob" --strip
"$build/tools/isocc" "$prog" -o "$work/cam.isob" --strip 2>/dev/null || true

t_floor=-; t_mfloor=-
[ -n "$floor" ] && t_floor=$(best "$floor" "$prog") && t_mfloor=$(best "$floor" "$mprog")
t_lint=$(best "$build/tools/isolint" --color never "$prog")
m_lint=$(peak "$build/tools/isolint" --color never "$prog")
# isolint checks a file of 1 MiB or more with two threads: its CPU time, and one thread's time
c_lint=$(/usr/bin/time -f "%U %S" "$build/tools/isolint" --color never "$prog" 2>&1 >/dev/null | tail -1 |
  python3 -c "import sys; u, s = sys.stdin.read().split(); print(float(u) + float(s))")
t_lint1=$(best "$build/tools/isolint" -j 1 --color never "$prog")
t_crowd=$(best "$build/tools/isolint" --color never "$work/crowd/cam.mpf")
m_crowd=$(peak "$build/tools/isolint" --color never "$work/crowd/cam.mpf")
# isocc on the SIDAC program and on the motion source; isosim straight from the motion source
t_cc=$(best "$build/tools/isocc" "$prog" -o "$work/cam2.isob")
m_cc=$(peak "$build/tools/isocc" "$prog" -o "$work/cam2.isob")
t_ccm=$(best "$build/tools/isocc" "$mprog" -o "$work/motion2.isob")
t_simsrc=$(best "$build/tools/isosim" "$mprog" --summary --max-time 1e9)
t_sim=$(best "$build/tools/isosim" "$work/motion.isob" --summary --max-time 1e9)
m_sim=$(peak "$build/tools/isosim" "$work/motion.isob" --summary --max-time 1e9)
src_b=$(stat -c %s "$mprog")
img_b=$(stat -c %s "$work/motion.isob")
gz_b=$(gzip -9 -c "$mprog" | wc -c)
xz_b=$(xz -9 -c "$mprog" | wc -c)
cam_b=$(stat -c %s "$prog")
cam_img=$( [ -f "$work/cam.isob" ] && stat -c %s "$work/cam.isob" || echo 0)
python3 - "$lines" "$cam_b" "$t_floor" "$t_lint" "$m_lint" "$t_crowd" "$m_crowd" "$motion" "$src_b" "$img_b" \
  "$gz_b" "$xz_b" "$t_mfloor" "$t_sim" "$m_sim" "$cam_img" "$c_lint" "$t_lint1" "$t_cc" "$m_cc" "$t_ccm" "$t_simsrc" <<'PY'
import sys
a = sys.argv[1:]
lines, cam_b = int(a[0]), int(a[1])
tf = None if a[2] == "-" else float(a[2])
tl, ml, tc, mc = float(a[3]), int(a[4]), float(a[5]), int(a[6])
motion, src_b, img_b, gz_b, xz_b = int(a[7]), int(a[8]), int(a[9]), int(a[10]), int(a[11])
tmf = None if a[12] == "-" else float(a[12])
ts, ms, cam_img = float(a[13]), int(a[14]), int(a[15])
cl, tl1 = float(a[16]), float(a[17])
tcc, mcc, tccm, tss = float(a[18]), int(a[19]), float(a[20]), float(a[21])
r = lambda x, y: "-" if y is None else f"{x / y:.1f}x"
print(f"| | measured | goal |")
print(f"|---|---|---|")
print(f"| isolint, {lines:,}-line SIDAC program ({cam_b/1e6:.0f} MB), alone | {tl:.2f} s = {r(tl, tf)} the floor; RSS {ml/1024:.0f} MiB = {ml*1024/cam_b:.1f}x the file | <= 3x the floor, RSS <= 5x the file |")
print(f"| the same with one thread (-j 1); CPU time of the two-thread run | {tl1:.2f} s = {r(tl1, tf)} the floor; CPU {cl:.2f} s | - |")
print(f"| the same beside 9 programs of its size | {tc:.2f} s = {r(tc, tf)} the floor; RSS {mc/1024:.0f} MiB = {mc*1024/cam_b:.1f}x the file | the same, whatever is in the folder |")
cam = f"{cam_img/cam_b:.0%} (CAM-style program), " if cam_img else ""
print(f"| isocc --strip image / source | {cam}{img_b/src_b:.0%} ({motion:,} motion blocks); gzip -9 {gz_b/src_b:.0%}, xz -9 {xz_b/src_b:.0%} | <= 25 % |")
print(f"| isosim --summary, image of {motion:,} motion blocks | {ts:.2f} s = {r(ts, tmf)} the floor on its source, {motion/ts/1e6:.2f} M blocks/s; RSS {ms/1024:.0f} MiB | <= 5x the floor (>= 2.5 M blocks/s); RSS <= 100 MiB |")
print(f"| isocc, the {lines:,}-line program | {tcc:.2f} s = {tcc / tl:.2f}x isolint; RSS {mcc/1024:.0f} MiB = {mcc*1024/cam_b:.1f}x the file | <= 1.5x isolint; RSS <= 5x the file |")
print(f"| isosim --summary on the {motion:,}-block source | {tss:.2f} s = {tss / (tccm + ts):.2f}x (isocc {tccm:.2f} s + isosim on the image) | <= 1.0x |")
lim = 2 * img_b / 1048576 + 16
print(f"| isosim --summary, stripped image: peak RSS | {ms/1024:.0f} MiB; limit 2x the image + 16 MiB = {lim:.0f} MiB | <= the limit |")
if tf is not None:
    print(f"\nfloor (../shared/bench-peers/floor, g++ -O2): {tf:.3f} s on the SIDAC program ({cam_b/1e6/tf:.0f} MB/s), {tmf:.3f} s on the motion source")
PY
