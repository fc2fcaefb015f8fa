#!/usr/bin/env bash
# The ground truth beside VTK 9's unstructured-grid ray caster on the same scene, in one run (issue 3's goal).
#   bash bench/peers/reference_vs_vtk.sh MESH [scene options...]     e.g.
#   bash bench/peers/reference_vs_vtk.sh ../shared/data/vtk-data/bluntfinxyz.bin --q ../shared/data/vtk-data/bluntfinq.bin
# Needs Debian's python3-vtk9, python3-numpy and xvfb (apt-get install python3-vtk9 python3-numpy xvfb).
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
uvr="$here/build/bench/uvr"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$uvr" export "$@" --out "$dir" >/dev/null
"$uvr" render "$@" --algo reference --no-cache --out "$dir/reference.npy"
"$uvr" bench "$@" --algos reference --repeat 5 --json > "$dir/uvr.json"
xvfb-run -a /usr/bin/python3 "$here/bench/peers/vtk_peers.py" "$dir" --reference "$dir/reference.npy" \
  --mappers raycast --repeat 5 > "$dir/vtk.json"
/usr/bin/python3 - "$dir/uvr.json" "$dir/vtk.json" <<'PY'
import json, sys
u = json.load(open(sys.argv[1])); v = json.load(open(sys.argv[2]))
ref = u["results"][0]; vr = v["results"][0]
print(f"{u['mesh']}: {u['tetrahedra']} tetrahedra, {u['width']}x{u['height']}, {u['machine']['cpu']}")
print(f"  uvr reference        {ref['frame_ms']:8.1f} ms/frame (median of 5)")
print(f"  VTK {v['vtk']} ray caster {vr['frame_ms']:8.1f} ms/frame (median of 5), RMSE against the reference "
      f"{vr['rmse_rgb']:.4f}, visible {vr['visible_fraction']:.3f}, covered pixels left empty {vr['missing_fraction_of_covered']:.4f}")
print(f"  ratio reference / VTK: {ref['frame_ms'] / vr['frame_ms']:.2f}")
PY
