#!/usr/bin/env bash
# isosim speed and memory (issue 4, item 7). Reports, in one run:
#   1. blocks per second with --summary on a generated straight-line program of BLOCKS motion
#      blocks (default 1,000,000): from its image (isocc first) and from the source; the time
#      `isocc --verify` takes on the same image is shown as the share of loading the image;
#   2. blocks per second of the engine alone: a loop executing BLOCKS motion blocks (a tiny
#      program, so loading costs nothing), also with --profile; a loop of feed blocks in G60 and
#      in G64 (chains read ahead and planned), as ratios of the same run;
#   3. the wall time and size of a 9-axis trace at --dt 0.001 for one hour of motion (CSV and
#      JSON), and the peak memory (/usr/bin/time) of a 1-minute and a 1-hour program writing
#      such a trace: it must not grow with simulated time.
# Usage: bench/isosim_bench.sh [BLOCKS] [BUILD_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
blocks=${1:-1000000}
build=${2:-$here/../build-bench}
. "$here/common.sh"
bench_build isosim isocc
sim=$build/tools/isosim
cc=$build/tools/isocc
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Each program in its own directory: a program set is every .mpf/.spf beside the one named.
mkdir -p "$work/straight" "$work/loop" "$work/minute" "$work/hour"

# the `blocks:` line of a summary
blocks_of() { "$@" 2>/dev/null | sed -n 's/^blocks: //p'; }

# 1. straight-line program: BLOCKS motion blocks (+ a few set-up lines)
straight=$work/straight/straight.mpf
python3 "$here/gen_program.py" "$((blocks + 6))" "$straight" --kind motion
motion=$(grep -c '^G01\|^X' "$straight")
t_cc=$(best "$cc" "$straight" -o "$work/straight.isob")
"$cc" "$straight" -o "$work/straight.isob"
t_verify=$(best "$cc" --verify "$work/straight.isob")
t_img=$(best "$sim" "$work/straight.isob" --summary --max-time 1e9)
t_src=$(best "$sim" "$straight" --summary --max-time 1e9)
n_img=$(blocks_of "$sim" "$work/straight.isob" --summary --max-time 1e9)
rss_img=$(peak "$sim" "$work/straight.isob" --summary --max-time 1e9)

# 2. the engine alone: a loop of 4 motion blocks and 2 control statements per pass
passes=$(( (blocks + 3) / 4 ))
cat > "$work/loop/loop.mpf" <<EOF
; $passes passes of 4 motion blocks
G90 G01 F=400
R1 = 0
L: X100 Y50
G00 X0 Y0 Z-10
G01 X100 Z0
G00 X0
R1 = R1 + 1
IF R1 < $passes GOTOB L
M30
EOF
t_loop=$(best "$sim" "$work/loop/loop.mpf" --summary --max-time 1e9)
n_loop=$(blocks_of "$sim" "$work/loop/loop.mpf" --summary --max-time 1e9)
t_prof=$(best "$sim" "$work/loop/loop.mpf" --profile --max-time 1e9)

# 2b. a loop of feed blocks only, in G60 and in G64 (in G64 the loop's R and IF statements are
#     read ahead: one chain per lookahead_blocks blocks, planned); ratios of the same run
mkdir -p "$work/loop60" "$work/loop64"
square() { # FILE G60|G64
  cat > "$1" <<EOF
R1 = 0
G90 $2 G01 F=400
L: X100 Y50
X200 Y0
X100 Y-50
X0 Y0
R1 = R1 + 1
IF R1 < $passes GOTOB L
M30
EOF
}
square "$work/loop60/loop60.mpf" G60
square "$work/loop64/loop64.mpf" G64
t_loop60=$(best "$sim" "$work/loop60/loop60.mpf" --summary --max-time 1e9)
t_loop64=$(best "$sim" "$work/loop64/loop64.mpf" --summary --max-time 1e9)

# 3. nine axes moving for about a minute and about an hour
nine() { # FILE PASSES: 9-axis back-and-forth moves, 20.1 s per pass
  cat > "$1" <<EOF
R1 = 0
L: G01 X1000 Y500 Z-300 A90 B45 C180 U200 V100 W50 F100
G01 X0 Y0 Z0 A0 B0 C0 U0 V0 W0 F100
R1 = R1 + 1
IF R1 < $2 GOTOB L
M30
EOF
}
nine "$work/minute/minute.mpf" 3
nine "$work/hour/hour.mpf" 180
cyc_hour=$("$sim" "$work/hour/hour.mpf" --summary | sed -n 's/^cycle_time_s: //p')
cyc_min=$("$sim" "$work/minute/minute.mpf" --summary | sed -n 's/^cycle_time_s: //p')
t_csv=$(best "$sim" "$work/hour/hour.mpf" --dt 0.001 -o "$work/hour.csv")
t_json=$(best "$sim" "$work/hour/hour.mpf" --dt 0.001 -o "$work/hour.json")
size_csv=$(stat -c %s "$work/hour.csv")
size_json=$(stat -c %s "$work/hour.json")
rows=$(( $(wc -l < "$work/hour.csv") - 1 ))
rss_min=$(peak "$sim" "$work/minute/minute.mpf" --dt 0.001 -o "$work/minute.csv")
rss_hour=$(peak "$sim" "$work/hour/hour.mpf" --dt 0.001 -o "$work/hour.csv")
rss_min_j=$(peak "$sim" "$work/minute/minute.mpf" --dt 0.001 -o "$work/minute.json")
rss_hour_j=$(peak "$sim" "$work/hour/hour.mpf" --dt 0.001 -o "$work/hour.json")

python3 - <<PY
blocks_img, motion = int("$n_img"), int("$motion")
t_cc, t_verify, t_img, t_src = float("$t_cc"), float("$t_verify"), float("$t_img"), float("$t_src")
n_loop, t_loop = int("$n_loop"), float("$t_loop")
print(f"straight-line program: {motion} motion blocks, {blocks_img} statements")
print(f"  isocc compile               {t_cc:7.3f} s")
print(f"  isocc --verify (load share) {t_verify:7.3f} s")
print(f"  isosim IMAGE --summary      {t_img:7.3f} s  {blocks_img/t_img/1e6:6.2f} M blocks/s"
      f"  (without the load share: {blocks_img/max(t_img-t_verify,1e-9)/1e6:.2f} M blocks/s)  peak RSS {int('$rss_img')/1024:.0f} MiB")
print(f"  isosim SOURCE --summary     {t_src:7.3f} s  {blocks_img/t_src/1e6:6.2f} M blocks/s")
print(f"engine alone (loop, $passes passes x 4 motion blocks): {n_loop} statements in {t_loop:.3f} s"
      f"  {4*$passes/t_loop/1e6:.2f} M motion blocks/s  {n_loop/t_loop/1e6:.2f} M statements/s")
print(f"  with --profile: {float('$t_prof'):.3f} s = {float('$t_prof')/t_loop:.2f} x without")
print(f"feed-block loop ($passes passes x 4 G01 blocks): G60 {float('$t_loop60'):.3f} s, G64 {float('$t_loop64'):.3f} s"
      f" = {float('$t_loop64')/float('$t_loop60'):.2f} x (read-ahead and planning)")
print(f"9-axis trace, --dt 0.001, {float('$cyc_hour'):.0f} s of motion ({$rows} rows):")
print(f"  CSV  {float('$t_csv'):7.3f} s  {int('$size_csv')/1e6:7.1f} MB")
print(f"  JSON {float('$t_json'):7.3f} s  {int('$size_json')/1e6:7.1f} MB")
print(f"peak RSS, trace at --dt 0.001 to a file:")
print(f"  1-minute program ({float('$cyc_min'):.1f} s): CSV {int('$rss_min')/1024:.1f} MiB, JSON {int('$rss_min_j')/1024:.1f} MiB")
print(f"  1-hour program ({float('$cyc_hour'):.0f} s):  CSV {int('$rss_hour')/1024:.1f} MiB, JSON {int('$rss_hour_j')/1024:.1f} MiB")
PY
