#!/usr/bin/env bash
# isolint beside the peer G-code parsers of ../shared/bench-peers, in one run (issue #14:
# isolint >= 30x faster than LinuxCNC rs274 and >= 10x faster than cncjs gcode-parser on the
# 100k-line word-address file). The kit is copied to $PEERS_KIT (default ~/.cache/isotools-peers)
# and run there with isolint added through its EXTRA_PEERS; nothing is written into ../shared.
#
# Usage: bench/peers.sh [--setup] [SIZES]    SIZES: 10k,100k,1m (default 100k)
#   --setup  install the peers first (apt-get install linuxcnc-uspace; npm ci in the copy);
#            without root it prints the apt-get command instead.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
setup=0
[ "${1:-}" = --setup ] && { setup=1; shift; }
sizes=${1:-100k}
build=${BUILD:-$here/../build-bench}
kit_src=$here/../../shared/bench-peers
if [ ! -d "$kit_src" ]; then
  echo "skipped: $kit_src is not there (the peer kit lives beside the project)"
  exit 0
fi
. "$here/common.sh"
bench_build isolint
build=$(cd "$build" && pwd) # the wrapper below runs wherever the kit runs it
kit=${PEERS_KIT:-$HOME/.cache/isotools-peers}
mkdir -p "$kit"
cp -r "$kit_src"/. "$kit"/
chmod -R u+w "$kit"
if [ "$setup" = 1 ]; then
  if [ ! -x /usr/bin/rs274 ]; then
    if [ "$(id -u)" = 0 ]; then
      DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends linuxcnc-uspace
    else
      echo "run: sudo apt-get install -y --no-install-recommends linuxcnc-uspace" >&2
    fi
  fi
  (cd "$kit" && npm ci --no-audit --no-fund)
fi
# isolint exits 1 when it finds errors (the peer files use G21 G94 G54, which SIDAC lacks):
# that is a finished run, which the kit's gate must accept.
wrap=$kit/isolint-peer.sh
cat > "$wrap" <<SH
#!/bin/sh
"$build/tools/isolint" --color never --max-diagnostics 0 "\$1"
[ \$? -le 1 ]
SH
chmod +x "$wrap"
out=$(mktemp -d)
OUT=$out EXTRA_PEERS="isolint=$wrap" "$kit/run_peers.sh" --sizes "$sizes" \
  --only rs274,gcode-parser,gcode-interpreter,gcode-toolpath,floor:wc-l,isolint
python3 - "$out/results.tsv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
wall = {}
for r in rows:
    peer, size = r["label"].rsplit("@", 1)
    wall[(peer, size)] = float(r["wall_med_s"])
print()
for (peer, size), t in sorted(wall.items()):
    if peer != "isolint":
        continue
    for other, goal in (("rs274", 30), ("gcode-parser", 10), ("gcode-interpreter", None)):
        if (other, size) in wall:
            g = f" (goal >= {goal}x)" if goal else ""
            print(f"{size}: isolint {t:.3f} s is {wall[(other, size)] / t:.1f}x faster than {other} ({wall[(other, size)]:.3f} s){g}")
PY
