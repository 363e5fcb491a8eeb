#!/usr/bin/env bash
# A fuzzing campaign over every target of the fuzz build, one after the other, and its table:
# executions, executions per second, coverage (libFuzzer's cov/ft), crashes. Needs the fuzz
# build (CC=clang CXX=clang++ cmake --preset fuzz && cmake --build build-fuzz -j2).
#
# Usage: tests/fuzz/campaign.sh SECONDS_PER_TARGET [TARGET...]   (default: every target)
#   WORK=DIR keeps the new inputs and any crash-* files (default: a temporary folder, kept
#   when something crashed). The committed corpus is only read.
#   FUZZ_BUILD=DIR the fuzz build (default build-fuzz; build-fuzz-fast for the preset without
#   ASan, about three times the rate). RUNS=N stops each target after N executions (then
#   SECONDS_PER_TARGET is only an upper bound).
#   REPLAY_BUILD=DIR afterwards replays each target's new inputs with DIR/tests/fuzz/
#   iso_replay_<target> (an ASan+UBSan build such as build-asan: what a build without ASan
#   could miss).
#   MAX_LEN=N caps the input size (default 1024 bytes for the source-text targets, 512 for the
#   grammar target, whose bytes are choices (a few per statement), 4096 for the image targets: long inputs cost time without reaching new code; the bounds of long input
#   have tests of their own, tests/safety and tests/unit/frontend/BoundsTests.cpp).
# libFuzzer's entropic schedule is off (-entropic=0): with tens of thousands of features its
# bookkeeping took 50-70 % of the time of the source, simulate and grammar targets.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
secs=${1:?seconds per target}
shift
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(source render image imagesim simulate grammar lsp settings)
bin=${FUZZ_BUILD:-$root/build-fuzz}/tests/fuzz
work=${WORK:-$(mktemp -d)}
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
export ASAN_OPTIONS=detect_leaks=1
printf '| target | executions | exec/s | cov | ft | crashes |\n|---|---:|---:|---:|---:|---:|\n'
crashed=0
for t in "${targets[@]}"; do
  [ -x "$bin/iso_fuzz_$t" ] || { echo "| $t | (not built) | | | | |"; continue; }
  mkdir -p "$work/$t/new" "$work/$t/artifacts"
  log=$work/$t/log.txt
  dict=(); [ -f "$here/$t.dict" ] && dict=(-dict="$here/$t.dict")
  case $t in image | imagesim | lsp) maxlen=${MAX_LEN:-4096} ;; grammar) maxlen=${MAX_LEN:-512} ;; *) maxlen=${MAX_LEN:-1024} ;; esac
  "$bin/iso_fuzz_$t" "${dict[@]}" -max_len="$maxlen" -max_total_time="$secs" ${RUNS:+-runs=$RUNS} -entropic=0 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$work/$t/artifacts/" "$work/$t/new" "$here/corpus/$t" >"$log" 2>&1
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  n=$(find "$work/$t/artifacts" -type f | wc -l)
  [ "$n" -gt 0 ] && crashed=1
  echo "| $t | ${execs:-?} | ${rate:-?} | ${cov:-?} | ${ft:-?} | $n |"
done
if [ -n "${REPLAY_BUILD:-}" ]; then
  echo
  for t in "${targets[@]}"; do
    [ -n "$(find "$work/$t/new" -type f 2>/dev/null | head -1)" ] || continue
    if ASAN_OPTIONS=detect_leaks=1 "$REPLAY_BUILD/tests/fuzz/iso_replay_$t" "$work/$t/new" >"$work/$t/replay.txt" 2>&1; then
      echo "replay $t under $REPLAY_BUILD: $(find "$work/$t/new" -type f | wc -l) inputs, ok"
    else
      echo "replay $t under $REPLAY_BUILD: FAILED (see $work/$t/replay.txt)"
      crashed=1
    fi
  done
fi
echo
echo "work folder: $work"
[ "$crashed" = 1 ] && { echo "crashes: see */artifacts and */log.txt"; exit 1; }
exit 0
