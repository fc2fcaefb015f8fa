#!/usr/bin/env bash
# Reading an Exodus II file of N^3 hexahedra (default N = 100: a million hexahedra, six million tetrahedra): the load's
# time and the process's peak memory (bench/exodus_bench.cpp), ROUNDS times (default 3), and `uvr info` on it.
#   bash bench/exodus_read.sh [N]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
n=${1:-100}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$here/build/bench/exodus_bench" write "$n" "$dir/block.exo"
echo "file: $(du -h "$dir/block.exo" | cut -f1) for $n^3 hexahedra"
for r in $(seq 1 "${ROUNDS:-3}"); do "$here/build/bench/exodus_bench" read "$dir/block.exo"; done
"$here/build/bench/uvr" info "$dir/block.exo"
