#!/usr/bin/env bash
# What one `uvr budget` costs against the default frame of the same algorithm (the performance question: a
# full budget should cost no more than 1 + (number of factors) renders). Per round, alternating: `uvr budget` and
# `uvr render` of the default configuration, each timed as a whole process (both load the scene; the reference comes
# from the cache, filled before the first round); the ratio is taken within a round and its median reported.
#   bash bench/budget_cost.sh                 # HAVS and VICP on Blunt Fin 512², the ray caster on neghip 512²
# Environment: ROUNDS (default 5), SIZE (default 512x512), ALGOS (default "havs vicp raycast").
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
uvr="$here/build/bench/uvr"
data="$here/data/vtk-data"
rounds=${ROUNDS:-5}
size=${SIZE:-512x512}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export UVR_CACHE_DIR="$dir/cache"
bluntfin="$data/bluntfinxyz.bin --q $data/bluntfinq.bin"
declare -A scenes=([havs]="$bluntfin" [vicp]="$bluntfin" [raycast]="$data/neghip.slc")
nanoseconds() {  # COMMAND...: the wall time of one run
  local t0
  t0=$(date +%s%N)
  "$@" > /dev/null || true  # a budget whose baseline check fails exits 1 after its work: it is timed all the same
  echo $(($(date +%s%N) - t0))
}
for a in ${ALGOS:-havs vicp raycast}; do
  # shellcheck disable=SC2086
  "$uvr" render ${scenes[$a]} --size "$size" --algo reference --out "$dir/ref.npy" > /dev/null  # fills the cache
  for r in $(seq 1 "$rounds"); do
    # shellcheck disable=SC2086
    b=$(nanoseconds "$uvr" budget ${scenes[$a]} --size "$size" --algo "$a" --report "$dir/budget-$a")
    # shellcheck disable=SC2086
    f=$(nanoseconds "$uvr" render ${scenes[$a]} --size "$size" --algo "$a" --out "$dir/frame.npy")
    echo "$a $r $b $f" >> "$dir/times"
  done
  cp "$dir/budget-$a/budget.json" "$dir/$a.json"
done
/usr/bin/python3 - "$dir" <<'PY'
import json, statistics, sys
d = sys.argv[1]
rows = {}
for line in open(f"{d}/times"):
    a, r, b, f = line.split()
    rows.setdefault(a, []).append((int(b) / 1e9, int(f) / 1e9))
print("| algorithm | `uvr budget` (median) | default frame (median) | budget / frame (median of rounds) | goal: 1 + factors | runs rendered |")
print("|---|---|---|---|---|---|")
for a, t in rows.items():
    j = json.load(open(f"{d}/{a}.json"))
    factors = len(j["factor_order"])
    runs = [j["baseline"], j["total"]] + [j["factors"][n] for n in j["factor_order"]]
    rendered = sum(1 for x in runs if "same_as" not in x)
    ratio = statistics.median(b / f for b, f in t)
    print(f"| {a} | {statistics.median(b for b, _ in t):.2f} s | {statistics.median(f for _, f in t):.2f} s | "
          f"{ratio:.2f} | {1 + factors} | {rendered} of {len(runs)} |")
PY
