#!/usr/bin/env bash
# VTK 9's GPU ray caster verified (docs/verification.md, "Outside renderers"): the volume rendered by VTK at sample
# distances S, S/2, S/4, S/8 (S: twice uvr's default step, as `uvr verify --refine step` starts), each image measured
# by `uvr verify --images` against uvr's reference of the same scene, beside uvr's own ray caster refined the same way.
#   bash bench/peers/verify_vtk.sh VOLUME [scene options...]     e.g.
#   bash bench/peers/verify_vtk.sh data/vtk-data/hydrogen.vti --size 256x256
# FROM=S sets the first step (uvr verify's --from): VTK's 8-bit frame buffer rounds its colours to 1/255, so its
# error stops falling once below that; coarse steps keep the levels above it.
# Needs Debian's python3-vtk9, python3-numpy and xvfb (apt-get install python3-vtk9 python3-numpy xvfb).
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
uvr="$here/build/bench/uvr"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$uvr" export "$@" --out "$dir" >/dev/null
# uvr's own levels (post-classified, as VTK's mapper; early termination off in both: VTK stops at 1 - 1/255).
"$uvr" verify "$@" --algo raycast --refine step --threshold 1 ${FROM:+--from "$FROM"} --json > "$dir/uvr.json"
steps=$(/usr/bin/python3 -c "import json,sys; print(' '.join(str(x) for x in json.load(open(sys.argv[1]))['h']))" \
  "$dir/uvr.json")
images=""
for s in $steps; do
  mkdir -p "$dir/vtk-$s"
  xvfb-run -a /usr/bin/python3 "$here/bench/peers/vtk_peers.py" "$dir" --mappers gpu --step "$s" --repeat 1 \
    --save "$dir/vtk-$s" >/dev/null
  images="$images${images:+,}$dir/vtk-$s/vtk-gpu.npy"
done
"$uvr" verify --images "$images" --h "${steps// /,}" "$@" --expected 1 --json > "$dir/vtk.json"
/usr/bin/python3 - "$dir/uvr.json" "$dir/vtk.json" <<'PY'
import json, sys
for name, path in (("uvr ray caster", sys.argv[1]), ("VTK GPU ray caster", sys.argv[2])):
    j = json.load(open(path))
    r, m = j["measures"]["rmse"], j["measures"]["max_abs"]
    print(f"{name}: steps {', '.join('%.4g' % h for h in j['h'])}")
    print(f"  RMSE {', '.join('%.3g' % e for e in r['errors'])}: order {r['order']:.2f} "
          f"(per level {' '.join('%.2f' % o for o in r['orders'])})")
    print(f"  largest {', '.join('%.3g' % e for e in m['errors'])}: order {m['order']:.2f}; verdict {j['verdict']}")
PY
