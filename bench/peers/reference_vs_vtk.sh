#!/usr/bin/env bash
# The ground truth beside VTK 9's unstructured-grid ray caster on the same scene (the goal). Rounds alternate uvr and
# VTK, so that both see the same state of a shared machine; each round's ratio is of the two medians of REPEAT frames,
# and the figure reported is the median of the rounds' ratios. VTK's image is measured by `uvr compare --image`
# (bench/peers/measure_images.py), on its colour: it is 8-bit RGB.
#   bash bench/peers/reference_vs_vtk.sh MESH [scene options...]     e.g.
#   bash bench/peers/reference_vs_vtk.sh data/vtk-data/bluntfinxyz.bin --q data/vtk-data/bluntfinq.bin
# Environment: REPEAT (default 5), ROUNDS (default 5).
# Needs Debian's python3-vtk9, python3-numpy and xvfb (apt-get install python3-vtk9 python3-numpy xvfb).
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
uvr="$here/build/bench/uvr"
repeat=${REPEAT:-5}
rounds=${ROUNDS:-5}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$uvr" export "$@" --out "$dir" >/dev/null
"$uvr" render "$@" --algo reference --no-cache --out "$dir/reference.npy"
for r in $(seq 1 "$rounds"); do
  "$uvr" bench "$@" --algos reference --repeat "$repeat" --json > "$dir/uvr-$r.json"
  mkdir -p "$dir/vtk"
  xvfb-run -a /usr/bin/python3 "$here/bench/peers/vtk_peers.py" "$dir" --mappers raycast --repeat "$repeat" \
    --save "$dir/vtk" > "$dir/vtk-$r.json"
done
/usr/bin/python3 "$here/bench/peers/measure_images.py" --uvr "$uvr" --report "$dir/measured" \
  --image "vtk-raycast=$dir/vtk/vtk-raycast.npy" -- "$@" > "$dir/measured.json"
/usr/bin/python3 - "$dir" "$rounds" "$repeat" <<'PY'
import json, statistics, sys
d, rounds, repeat = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
m = json.load(open(f"{d}/measured.json"))
e = next(r for r in m["results"] if r["label"] == "vtk-raycast")
ratios = []
for r in range(1, rounds + 1):
    u = json.load(open(f"{d}/uvr-{r}.json")); v = json.load(open(f"{d}/vtk-{r}.json"))
    ref, vr = u["results"][0]["frame_ms"], v["results"][0]["frame_ms"]
    if r == 1:
        print(f"{u['mesh']}: {u['tetrahedra']} tetrahedra, {u['width']}x{u['height']}, {u['machine']['cpu']}; "
              f"VTK {v['vtk']}, RMSE (RGB) against the reference {e['rmse']:.4f}, visible {e['visible_fraction']:.3f}, "
              f"covered pixels left empty {e['covered_left_empty']:.4f}")
    ratios.append(ref / vr)
    print(f"  round {r}: uvr reference {ref:8.1f} ms/frame, VTK ray caster {vr:8.1f} ms/frame (medians of {repeat}), "
          f"ratio {ref / vr:.2f}")
print(f"  ratio reference / VTK, median of {rounds} rounds: {statistics.median(ratios):.2f}")
PY
