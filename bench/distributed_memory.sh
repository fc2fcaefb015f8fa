#!/usr/bin/env bash
# The data-parallel reference's memory and time on builtin:grid-N (6 N^3 tetrahedra, each rank making its z-slab
# without a file): for each rank count in RANKS, `mpirun -np R uvr render builtin:grid-N --size 512x512 --json`, one
# line per run with the tetrahedra, each rank's cells and peak memory (MiB), the largest of each stage's seconds over
# the ranks, and the whole run's wall time. docs/distributed.md has the figures.
#   bash bench/distributed_memory.sh                  # N=120 (10.4 M tetrahedra), RANKS="1 2 4"
#   N=256 RANKS=4 bash bench/distributed_memory.sh    # 100.7 M tetrahedra on 4 ranks
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
uvr="$here/build/bench/uvr"
n=${N:-120}
ranks=${RANKS:-"1 2 4"}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
for r in $ranks; do
  start=$(date +%s.%N)
  mpirun --oversubscribe -np "$r" "$uvr" render "builtin:grid-$n" --size 512x512 --out "$out/image.npy" --json \
    > "$out/run.json"
  wall=$(echo "$(date +%s.%N) - $start" | bc)
  /usr/bin/python3 - "$out/run.json" "$n" "$r" "$wall" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
n, r, wall = int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
ranks = j["ranks"]
stages = {s: max(x["seconds"][s] for x in ranks) for s in ("read", "build", "trace", "exchange", "composite")}
print(f"grid-{n}: {6 * n**3} tetrahedra on {r} rank(s), wall {wall:.1f} s")
print("  cells per rank:", [x["cells"] for x in ranks])
print("  peak memory per rank (MiB):", [round(x["peak_memory_bytes"] / 2**20) for x in ranks])
print("  slowest rank's seconds:", {s: round(v, 2) for s, v in stages.items()})
PY
done
