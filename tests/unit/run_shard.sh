#!/usr/bin/env bash
# Runs shard K of N of the unit tests: doctest's --first/--last over its test cases in file
# order, so that the N shards together run each test case once.
#   run_shard.sh UNIT_TEST_BINARY K N
# The sanitizer build registers the unit tests this way (tests/CMakeLists.txt): there every
# process start costs about 0.4 s, which one CTest test per test case paid 615 times.
set -euo pipefail
bin=$1 k=$2 n=$3
total=$("$bin" --count | sed -n 's/.*passing the current filters: *\([0-9][0-9]*\).*/\1/p')
if [ -z "$total" ] || [ "$total" -eq 0 ]; then
  echo "run_shard.sh: $bin lists no test case" >&2
  exit 1
fi
first=$(((k - 1) * total / n + 1))
last=$((k * total / n))
echo "unit test cases $first to $last of $total (file order)"
[ "$first" -le "$last" ] || exit 0
exec "$bin" --order-by=file --first="$first" --last="$last"
