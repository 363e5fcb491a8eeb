# Shared by the bench/*_bench.sh scripts (sourced, not run). They set `here` and `build` first.

# bench_build TOOL...: builds the Release tools into $build unless they are all there
bench_build() {
  local t missing=""
  for t in "$@"; do [ -x "$build/tools/$t" ] || missing=1; done
  if [ -n "$missing" ]; then
    cmake -S "$here/.." -B "$build" -DCMAKE_BUILD_TYPE=Release -DISO_BUILD_TESTS=OFF >/dev/null
    cmake --build "$build" -j"$(nproc)" --target "$@" >/dev/null
  fi
  command -v /usr/bin/time >/dev/null || { echo "needs /usr/bin/time (apt-get install time)" >&2; exit 2; }
}

# best CMD...: wall seconds of the best of 3 runs, output discarded
best() {
  local b=""
  for _ in 1 2 3; do
    local s e
    s=$(date +%s.%N); "$@" >/dev/null 2>&1 || true; e=$(date +%s.%N)
    b=$(python3 -c "t=$e-$s; b='$b'; print(t if not b or t<float(b) else b)")
  done
  echo "$b"
}

# peak CMD...: peak resident memory in KiB
peak() { /usr/bin/time -f %M "$@" 2>&1 >/dev/null | tail -1 || true; }
