#!/usr/bin/env bash
# The data-parallel reference's speed-up: RANKS ranks of one thread each (mpirun --bind-to core) against one process
# of one thread (taskset -c 0, the image cache off) and against one rank (mpirun -np 1), the same .pvtu and view, in
# ROUNDS alternating rounds; prints each round and the medians of the wall time (program start to exit, mpirun's start
# included), the one process's render against the slowest rank's trace, and the render read to image of one rank
# against RANKS ranks. The peer that says what the machine allows: the one process on every core (its threads share
# the tiles as they go), its render against the one thread's. docs/distributed.md, "Cost".
#   bash bench/rank_speedup.sh DIR/NAME.pvtu --view -40,70 --size 512x512     # ROUNDS=3 RANKS=2
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
uvr="$here/build/bench/uvr"
rounds=${ROUNDS:-3}
ranks=${RANKS:-2}
[ $# -ge 1 ] || { echo "usage: $0 DIR/NAME.pvtu [render options]" >&2; exit 2; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for r in $(seq "$rounds"); do
  s0=$(date +%s.%N)
  taskset -c 0 "$uvr" render "$@" --no-cache --out "$tmp/one.npy" --json > "$tmp/one-$r.json"
  s1=$(date +%s.%N)
  mpirun --bind-to core -np "$ranks" "$uvr" render "$@" --out "$tmp/ranks.npy" --json > "$tmp/ranks-$r.json"
  s2=$(date +%s.%N)
  mpirun --bind-to core -np 1 "$uvr" render "$@" --out "$tmp/rank.npy" --json > "$tmp/rank-$r.json"
  "$uvr" render "$@" --no-cache --out "$tmp/threads.npy" --json > "$tmp/threads-$r.json"
  echo "$s0 $s1 $s2" > "$tmp/wall-$r"
  # The promise of docs/spec.md §9: the data-parallel image within 1e-6 of one process's in every channel.
  /usr/bin/python3 -c "import numpy as n, sys; d = float(abs(n.load(sys.argv[1]) - n.load(sys.argv[2])).max()); \
print(f'round $r: largest difference from one process {d:.2g}'); sys.exit(d > 1e-6)" "$tmp/one.npy" "$tmp/ranks.npy"
done
/usr/bin/python3 - "$tmp" "$rounds" <<'PY'
import json, statistics, sys
tmp, rounds = sys.argv[1], int(sys.argv[2])
rows = []
for r in range(1, rounds + 1):
    one = json.load(open(f"{tmp}/one-{r}.json"))
    many = json.load(open(f"{tmp}/ranks-{r}.json"))
    s0, s1, s2 = map(float, open(f"{tmp}/wall-{r}").read().split())
    wall1, wallN = s1 - s0, s2 - s1
    trace = max(k["seconds"]["trace"] for k in many["ranks"])
    rank = json.load(open(f"{tmp}/rank-{r}.json"))
    threads = json.load(open(f"{tmp}/threads-{r}.json"))
    rows.append((wall1, wallN, one["seconds"], many["seconds"], trace, rank["seconds"], threads["seconds"]))
    segs = " ".join(str(k["segments"]) for k in many["ranks"])
    print(f"round {r}: wall {wall1:.3f} / {wallN:.3f} s, render {one['seconds']:.3f} / {many['seconds']:.3f} s, "
          f"slowest trace {trace:.3f} s, 1 rank's render {rank['seconds']:.3f} s, one process on every core "
          f"{threads['seconds']:.3f} s; segments per rank {segs}")
med = [statistics.median(c) for c in zip(*rows)]
print(f"medians: wall {med[0]:.3f} / {med[1]:.3f} s ({med[0] / med[1]:.2f}x), "
      f"render {med[2]:.3f} / {med[3]:.3f} s ({med[2] / med[3]:.2f}x), "
      f"one process's render / slowest trace {med[2] / med[4]:.2f}x, "
      f"1 rank's render (read to image) / {len(many['ranks'])} ranks' {med[5] / med[3]:.2f}x; "
      f"the machine's own: one process's render on 1 thread / on every core {med[2] / med[6]:.2f}x")
PY
