#!/usr/bin/env bash
# The ground truth beside VTK 9's unstructured-grid ray caster on the same scene, in one run (the goal). VTK's
# image is measured by `uvr compare --image` (bench/peers/measure_images.py), on its colour: it is 8-bit RGB.
#   bash bench/peers/reference_vs_vtk.sh MESH [scene options...]     e.g.
#   bash bench/peers/reference_vs_vtk.sh data/vtk-data/bluntfinxyz.bin --q data/vtk-data/bluntfinq.bin
# Needs Debian's python3-vtk9, python3-numpy and xvfb (apt-get install python3-vtk9 python3-numpy xvfb).
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
uvr="$here/build/bench/uvr"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$uvr" export "$@" --out "$dir" >/dev/null
"$uvr" render "$@" --algo reference --no-cache --out "$dir/reference.npy"
"$uvr" bench "$@" --algos reference --repeat 5 --json > "$dir/uvr.json"
mkdir -p "$dir/vtk"
xvfb-run -a /usr/bin/python3 "$here/bench/peers/vtk_peers.py" "$dir" --mappers raycast --repeat 5 --save "$dir/vtk" \
  > "$dir/vtk.json"
/usr/bin/python3 "$here/bench/peers/measure_images.py" --uvr "$uvr" --report "$dir/measured" \
  --image "vtk-raycast=$dir/vtk/vtk-raycast.npy" -- "$@" > "$dir/measured.json"
/usr/bin/python3 - "$dir/uvr.json" "$dir/vtk.json" "$dir/measured.json" <<'PY'
import json, sys
u = json.load(open(sys.argv[1])); v = json.load(open(sys.argv[2])); m = json.load(open(sys.argv[3]))
ref = u["results"][0]; vr = v["results"][0]
e = next(r for r in m["results"] if r["label"] == "vtk-raycast")
print(f"{u['mesh']}: {u['tetrahedra']} tetrahedra, {u['width']}x{u['height']}, {u['machine']['cpu']}")
print(f"  uvr reference        {ref['frame_ms']:8.1f} ms/frame (median of 5)")
print(f"  VTK {v['vtk']} ray caster {vr['frame_ms']:8.1f} ms/frame (median of 5), RMSE (RGB) against the reference "
      f"{e['rmse']:.4f}, visible {e['visible_fraction']:.3f}, covered pixels left empty {e['covered_left_empty']:.4f}")
print(f"  ratio reference / VTK: {ref['frame_ms'] / vr['frame_ms']:.2f}")
PY
