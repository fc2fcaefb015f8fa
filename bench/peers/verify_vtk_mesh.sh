#!/usr/bin/env bash
# VTK 9's unstructured mappers verified under mesh refinement (docs/verification.md, "Outside renderers"):
# builtin:grid-N for N = 4, 8, 16, 32 (each cube split into eight from one level to the next), drawn by VTK's
# projected tetrahedra and unstructured ray caster with the transfer function and camera `uvr verify --refine mesh`
# uses, each sequence measured by `uvr verify --images` against the integral of the grid's analytic field.
#   bash bench/peers/verify_vtk_mesh.sh [--size WxH] [--view AZ,EL]     (default 256x256, 30,20)
# Needs Debian's python3-vtk9, python3-numpy and xvfb (apt-get install python3-vtk9 python3-numpy xvfb).
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
uvr="$here/build/bench/uvr"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
scene=("$@")
[ ${#scene[@]} -gt 0 ] || scene=(--size 256x256 --view 30,20)
# uvr's own levels; the exact image, tf.json and camera.json land in $dir/uvr/runs.
"$uvr" verify builtin:grid-4 "${scene[@]}" --algo reference --refine mesh --report "$dir/uvr" --json > "$dir/uvr.json"
size=$(/usr/bin/python3 -c "import sys; a=sys.argv[1:]; print(a[a.index('--size')+1] if '--size' in a else '512x512')" \
  "${scene[@]}")
h=""
for n in 4 8 16 32; do
  "$uvr" export "builtin:grid-$n" --tf "$dir/uvr/runs/tf.json" --camera "$dir/uvr/runs/camera.json" --size "$size" \
    --out "$dir/grid-$n" >/dev/null
  xvfb-run -a /usr/bin/python3 "$here/bench/peers/vtk_peers.py" "$dir/grid-$n" --mappers pt,raycast --repeat 1 \
    --save "$dir/grid-$n" >/dev/null
  h="$h${h:+,}$(/usr/bin/python3 -c "print(2 / $n)")"
done
for mapper in pt raycast; do
  images=$(printf "$dir/grid-%s/vtk-$mapper.npy," 4 8 16 32)
  "$uvr" verify --images "${images%,}" --h "$h" --reference "$dir/uvr/runs/exact.npy" --expected 2 --json \
    > "$dir/vtk-$mapper.json"
done
/usr/bin/python3 - "$dir" <<'PY'
import json, sys
d = sys.argv[1]
for name, path in (("uvr reference", "uvr.json"), ("VTK projected tetrahedra", "vtk-pt.json"),
                   ("VTK unstructured ray caster", "vtk-raycast.json")):
    j = json.load(open(f"{d}/{path}"))
    r, m = j["measures"]["rmse"], j["measures"]["max_abs"]
    print(f"{name}: RMSE {', '.join('%.3g' % e for e in r['errors'])}: order {r['order']:.2f} "
          f"(per level {' '.join('%.2f' % o for o in r['orders'])}); largest: order {m['order']:.2f}; "
          f"verdict {j['verdict']}")
PY
