#!/usr/bin/env bash
# How cost grows with the mesh. For each N in SIZES, the built-in torus of about N tetrahedra
# (builtin:torus-N: TetGen from a fixed surface, quality bound 1.4, volume bound = torus volume / N; it makes about
# 1.8 N) is exported once to OUT/torus-N/ (binary VTK, transfer function, camera), then every algorithm and backend
# renders it 512 x 512 from the default view in a process of its own, so that the process's peak memory is that path's
# (mesh, topology and the renderer; TetGen's own memory is not in it). Then bench/plots/scaling_plots.py tabulates,
# fits frame time and memory against the count in log-log, and plots them.
#   bash bench/scaling.sh                      # SIZES="10000 30000 100000 300000 1000000 3000000", OUT=scaling
#   SIZES="10000000" OUT=scaling bash bench/scaling.sh     # adds a point; finished runs are kept and not redone
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
uvr="$here/build/bench/uvr"
sizes=${SIZES:-"10000 30000 100000 300000 1000000 3000000"}
out=${OUT:-scaling}
repeat=${REPEAT:-3}
mkdir -p "$out"
for n in $sizes; do
  d="$out/torus-$n"
  if [ ! -f "$d/scene.json" ]; then
    echo "generating builtin:torus-$n" >&2
    "$uvr" export "builtin:torus-$n" --out "$d" >/dev/null
  fi
  # VICP with its default order, MPVONC (the heavier of the two to build).
  for path in "reference emu" "havs emu" "havs gl" "vicp emu" "vicp gl"; do
    set -- $path
    f="$d/bench-$1-$2.json"
    [ -s "$f" ] && continue
    echo "torus-$n: $1 $2" >&2
    "$uvr" bench "$d/mesh.vtk" --tf "$d/tf.json" --camera "$d/camera.json" --size 512x512 --algos "$1" \
      --backend "$2" --orders mpvonc --repeat "$repeat" --json > "$f.part" && mv "$f.part" "$f"
  done
done
/usr/bin/python3 "$here/bench/plots/scaling_plots.py" "$out"
