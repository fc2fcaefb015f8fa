#!/usr/bin/env bash
# One `uvr render` timed by two builds of uvr in alternating rounds: the median of the per-round ratios of the frame's
# own time (the JSON's "seconds": the frame, not the load), AFTER / BEFORE. For changes that must not slow a renderer
# down (docs/reference.md, "Speed").
#   bash bench/binary_ratio.sh BEFORE_UVR AFTER_UVR RENDER_ARGS...
#   e.g. bash bench/binary_ratio.sh /tmp/uvr-old build/bench/uvr DATA/bluntfinxyz.bin --q DATA/bluntfinq.bin \
#          --algo reference --size 512x512
# Environment: ROUNDS (default 7). The reference cache is off (--no-cache) so that every round renders.
set -euo pipefail
before=$1 after=$2
shift 2
rounds=${ROUNDS:-7}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
seconds() {  # UVR: the frame's time in seconds
  "$1" render "${@:2}" --no-cache --json --out "$dir/frame.npy" |
    /usr/bin/python3 -c 'import json, sys; print(json.load(sys.stdin)["seconds"])'
}
for r in $(seq 1 "$rounds"); do
  b=$(seconds "$before" "$@")
  a=$(seconds "$after" "$@")
  echo "$r $b $a" | tee -a "$dir/times"
done
/usr/bin/python3 - "$dir/times" <<'PY'
import statistics, sys
rows = [tuple(map(float, l.split()[1:])) for l in open(sys.argv[1])]
print(f"before median {statistics.median(b for b, _ in rows):.4f} s, after median "
      f"{statistics.median(a for _, a in rows):.4f} s, median of after / before per round "
      f"{statistics.median(a / b for b, a in rows):.4f} ({len(rows)} rounds)")
PY
