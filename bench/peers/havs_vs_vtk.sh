#!/usr/bin/env bash
# HAVS (emulated, and on GL through OSMesa or EGL) beside VTK 9's projected tetrahedra on the same scene, in one run
# (issues 4 and 5's performance goals).
#   bash bench/peers/havs_vs_vtk.sh MESH [scene options...]     e.g.
#   bash bench/peers/havs_vs_vtk.sh ../shared/data/vtk-data/bluntfinxyz.bin --q ../shared/data/vtk-data/bluntfinq.bin \
#        --size 512x512
# Environment: K (default 6), GL (osmesa | egl, default osmesa), REPEAT (default 5).
# Needs Debian's python3-vtk9, python3-numpy and xvfb (apt-get install python3-vtk9 python3-numpy xvfb).
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
uvr="$here/build/bench/uvr"
k=${K:-6}
gl=${GL:-osmesa}
repeat=${REPEAT:-5}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$uvr" export "$@" --out "$dir" >/dev/null
"$uvr" render "$@" --algo reference --no-cache --out "$dir/reference.npy"
"$uvr" bench "$@" --algos havs --backend emu,gl --gl "$gl" --k "$k" --repeat "$repeat" --json > "$dir/uvr.json"
xvfb-run -a /usr/bin/python3 "$here/bench/peers/vtk_peers.py" "$dir" --reference "$dir/reference.npy" \
  --mappers pt --repeat "$repeat" > "$dir/vtk.json"
/usr/bin/python3 - "$dir/uvr.json" "$dir/vtk.json" <<'PY'
import json, sys
u = json.load(open(sys.argv[1])); v = json.load(open(sys.argv[2]))
emu, gl = u["results"]; pt = v["results"][0]
print(f"{u['mesh']}: {u['tetrahedra']} tetrahedra, {u['width']}x{u['height']}, k={emu['k']}, {u['machine']['cpu']} "
      f"({u['machine']['threads']} threads)")
for r in (emu, gl):
    s = r["stages"]
    print(f"  uvr HAVS {r['backend']:3s}  {r['frame_ms']:8.1f} ms/frame (median of {len(r['frame_ms_all'])}): sort "
          f"{s['sort']:.1f}, vertex+setup {s['vertex_and_setup']:.1f}, raster+fragment {s['raster_and_fragment']:.1f}, "
          f"flush {s['flush']:.1f}, readback {s['readback']:.1f} ms; {r['tetrahedra_per_s'] / 1e6:.2f} Mtet/s")
print(f"  GL: {gl['gl']}")
print(f"  VTK {v['vtk']} projected tetrahedra {pt['frame_ms']:8.1f} ms/frame (median of {len(pt['frame_ms_all'])}), "
      f"RMSE against the reference {pt['rmse_rgb']:.4f}")
print(f"  ratios: GL / VTK PT {gl['frame_ms'] / pt['frame_ms']:.2f}, emulation / GL {emu['frame_ms'] / gl['frame_ms']:.2f}")
PY
