#!/usr/bin/env bash
# HAVS (emulated, on GL through OSMesa or EGL, and through the paper's own ARB programs) beside VTK 9's projected
# tetrahedra on the same scene, in one run (issues 4, 5 and 24's performance goals).
#   bash bench/peers/havs_vs_vtk.sh MESH [scene options...]     e.g.
#   bash bench/peers/havs_vs_vtk.sh data/vtk-data/bluntfinxyz.bin --q data/vtk-data/bluntfinq.bin \
#        --size 512x512
# Environment: K (default 6), GL (osmesa | egl, default osmesa), REPEAT (default 5), ROUNDS (default 3).
# Needs Debian's python3-vtk9, python3-numpy and xvfb (apt-get install python3-vtk9 python3-numpy xvfb).
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
uvr="$here/build/bench/uvr"
k=${K:-6}
gl=${GL:-osmesa}
repeat=${REPEAT:-5}
rounds=${ROUNDS:-3}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$uvr" export "$@" --out "$dir" >/dev/null
# Rounds alternate uvr and VTK, so that both see the same state of a shared machine; the ratios are taken within a
# round, and their median is the figure reported (docs/gl-backend.md, "Speed").
for r in $(seq 1 "$rounds"); do
  "$uvr" bench "$@" --algos havs --backend emu,gl,arb --gl "$gl" --k "$k" --repeat "$repeat" --json > "$dir/uvr-$r.json"
  mkdir -p "$dir/vtk-$r"
  xvfb-run -a /usr/bin/python3 "$here/bench/peers/vtk_peers.py" "$dir" --mappers pt --repeat "$repeat" \
    --save "$dir/vtk-$r" > "$dir/vtk-$r.json"
done
# VTK's image measured the one way uvr measures an outside image (uvr compare --image), on its colour (8-bit RGB).
/usr/bin/python3 "$here/bench/peers/measure_images.py" --uvr "$uvr" --report "$dir/measured" \
  --image "vtk-pt=$dir/vtk-1/vtk-pt.npy" -- "$@" > "$dir/measured.json"
/usr/bin/python3 - "$dir" "$rounds" <<'PY'
import json, statistics, sys
d, rounds = sys.argv[1], int(sys.argv[2])
pt_rmse = next(r for r in json.load(open(f"{d}/measured.json"))["results"] if r["label"] == "vtk-pt")["rmse"]
gl_pt, emu_gl, arb_gl = [], [], []
for r in range(1, rounds + 1):
    u = json.load(open(f"{d}/uvr-{r}.json")); v = json.load(open(f"{d}/vtk-{r}.json"))
    emu, gl, arb = u["results"]; pt = v["results"][0]
    if r == 1:
        print(f"{u['mesh']}: {u['tetrahedra']} tetrahedra, {u['width']}x{u['height']}, k={emu['k']}, "
              f"{u['machine']['cpu']} ({u['machine']['threads']} threads); GL: {gl['gl']}; VTK {v['vtk']}")
    print(f"round {r}:")
    for x in (emu, gl, arb):
        s = x["stages"]
        print(f"  uvr HAVS {x['backend']:3s}  {x['frame_ms']:8.1f} ms/frame (median of {len(x['frame_ms_all'])}): sort "
              f"{s['sort']:.1f}, vertex+setup {s['vertex_and_setup']:.1f}, raster+fragment "
              f"{s['raster_and_fragment']:.1f}, flush {s['flush']:.1f}, readback {s['readback']:.1f} ms; "
              f"{x['tetrahedra_per_s'] / 1e6:.2f} Mtet/s")
    print(f"  VTK projected tetrahedra {pt['frame_ms']:8.1f} ms/frame (median of {len(pt['frame_ms_all'])}), RMSE "
          f"(RGB) against the reference {pt_rmse:.4f} (round 1's image)")
    gl_pt.append(gl["frame_ms"] / pt["frame_ms"]); emu_gl.append(emu["frame_ms"] / gl["frame_ms"])
    arb_gl.append(arb["frame_ms"] / gl["frame_ms"])
    print(f"  ratios: GL / VTK PT {gl_pt[-1]:.2f}, emulation / GL {emu_gl[-1]:.2f}, ARB (--entries paper) / GL "
          f"{arb_gl[-1]:.2f}")
print(f"median over {rounds} rounds: GL / VTK PT {statistics.median(gl_pt):.2f} (range {min(gl_pt):.2f}-"
      f"{max(gl_pt):.2f}), emulation / GL {statistics.median(emu_gl):.2f} (range {min(emu_gl):.2f}-{max(emu_gl):.2f}), "
      f"ARB / GL {statistics.median(arb_gl):.2f} (range {min(arb_gl):.2f}-{max(arb_gl):.2f})")
PY
