#!/usr/bin/env bash
# One command, one table (issues 7 and 9), on the same data, transfer function, camera and size, in one run:
#   - a mesh: uvr's reference, HAVS, and VICP in both cell orders, emulated and on GL, and VTK 9's three
#     unstructured-grid volume mappers;
#   - a regular grid (a volume): uvr's reference and ray caster (both classifications, emulated and on GL) and VTK 9's
#     GPU ray caster (vtkOpenGLGPUVolumeRayCastMapper, under Xvfb's Mesa).
# Milliseconds per frame (median), and each image's error against uvr's reference measured the same way for all, by
# `uvr compare --image` (docs/spec.md §4 on the RGB colour over black, since VTK's images are 8-bit RGB: RMSE, visible
# fraction, and the fraction of covered pixels left empty).
#   bash bench/peers/peer_table.sh MESH [scene options...]     e.g.
#   bash bench/peers/peer_table.sh data/vtk-data/bluntfinxyz.bin --q data/vtk-data/bluntfinq.bin
#   bash bench/peers/peer_table.sh data/vtk-data/neghip.slc
# Environment: K (HAVS k, default 6), GL (osmesa | egl, default osmesa), REPEAT (default 5), KEEP (a directory to keep
# every image and JSON in). Needs Debian's python3-vtk9, python3-numpy and xvfb.
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
uvr="$here/build/bench/uvr"
k=${K:-6}
gl=${GL:-osmesa}
repeat=${REPEAT:-5}
if [ -n "${KEEP:-}" ]; then dir=$KEEP; mkdir -p "$dir"; else dir=$(mktemp -d); trap 'rm -rf "$dir"' EXIT; fi
"$uvr" export "$@" --out "$dir/scene" >/dev/null
mkdir -p "$dir/vtk"
if grep -q '"kind": "volume"' "$dir/scene/scene.json"; then
  # A regular grid: uvr's ray caster (post-classified and pre-integrated, emulated and on GL) and VTK's GPU ray caster.
  "$uvr" compare "$@" --algos reference,raycast --no-cache --report "$dir/emu" --json > "$dir/emu.json"
  "$uvr" compare "$@" --algos raycast --preintegrate --report "$dir/emu" --json > "$dir/emu-preint.json"
  "$uvr" compare "$@" --algos raycast --backend gl --gl "$gl" --report "$dir/gl" --json > "$dir/gl.json"
  "$uvr" compare "$@" --algos raycast --preintegrate --backend gl --gl "$gl" --report "$dir/gl" --json \
    > "$dir/gl-preint.json"
  "$uvr" bench "$@" --algos reference,raycast --backend emu,gl --gl "$gl" --repeat "$repeat" --json > "$dir/bench.json"
  mappers=gpu
else
  "$uvr" compare "$@" --algos reference,havs,vicp --k "$k" --no-cache --report "$dir/emu" --json > "$dir/emu.json"
  "$uvr" compare "$@" --algos havs,vicp --backend gl --gl "$gl" --k "$k" --report "$dir/gl" --json > "$dir/gl.json"
  "$uvr" compare "$@" --algos vicp --order centroid --k "$k" --report "$dir/emu" --json > "$dir/emu-centroid.json"
  "$uvr" compare "$@" --algos vicp --order centroid --backend gl --gl "$gl" --report "$dir/gl" --json \
    > "$dir/gl-centroid.json"
  "$uvr" bench "$@" --algos reference,havs,vicp --backend emu,gl --gl "$gl" --k "$k" --orders mpvonc,centroid \
    --repeat "$repeat" --json > "$dir/bench.json"
  mappers=raycast,pt,zsweep
fi
xvfb-run -a /usr/bin/python3 "$here/bench/peers/vtk_peers.py" "$dir/scene" --mappers "$mappers" --repeat "$repeat" \
  --save "$dir/vtk" > "$dir/vtk.json"
/usr/bin/python3 - "$dir" "$k" "$gl" "$uvr" "$here" "$@" <<'PY'
import json, subprocess, sys
d, k, gl, uvr, here, scene = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5], sys.argv[6:]
b = json.load(open(f"{d}/bench.json"))
v = json.load(open(f"{d}/vtk.json"))

rows = []  # (name, ms/frame, label, image file)
for r in b["results"]:
    if r["algo"] == "reference":
        rows.append(("uvr reference (exact, CPU)", r["frame_ms"], "uvr-reference", f"{d}/emu/reference.npy"))
        continue
    sub = r["backend"]
    where = "emulated" if sub == "emu" else f"GL ({gl})"
    if r["algo"] == "raycast":
        pre = r["classification"] == "pre-integrated"
        label = f"raycast-{sub}-{'preint' if pre else 'post'}"
        name = f"uvr ray caster, {'pre-integrated' if pre else 'post-classified'}, step {r['step']:g}, {where}"
    elif r["algo"] == "vicp":
        label, name = f"vicp-{sub}-{r['order']}", f"uvr VICP {r['order']}, {where}"
    else:
        label, name = f"havs-{sub}-k{k}", f"uvr HAVS k={k}, {where}"
    rows.append((name, r["frame_ms"], "uvr-" + label, f"{d}/{sub}/{label}.npy"))
for r in v["results"]:
    rows.append((f"VTK {v['vtk']} {r['algo'][4:]}", r["frame_ms"], r["algo"], f"{d}/vtk/{r['algo']}.npy"))
# Every image measured the one way uvr measures an image made elsewhere (uvr compare --image), on the colour over
# black for all, since VTK's images are 8-bit RGB (bench/peers/measure_images.py).
args = ["/usr/bin/python3", f"{here}/bench/peers/measure_images.py", "--uvr", uvr, "--report", f"{d}/table",
        "--colour-only"]
for _, _, label, path in rows:
    args += ["--image", f"{label}={path}"]
measured = json.loads(subprocess.run(args + ["--", *scene], check=True, stdout=subprocess.PIPE).stdout)
by_label = {r["label"]: r for r in measured["results"]}
m = b["machine"]
elements = f"{b['tetrahedra']} tetrahedra" if "tetrahedra" in b else f"{b['voxels']} voxels"
print(f"{b['mesh']}: {elements}, {b['width']}x{b['height']}; {m['cpu']}, {m['threads']} threads; "
      f"medians of {len(b['results'][0]['frame_ms_all'])}")
print()
print("| renderer | ms/frame | RMSE (RGB) | visible fraction | covered pixels left empty |")
print("|---|---|---|---|---|")
for name, ms, label, _ in rows:
    e = by_label[label]
    print(f"| {name} | {ms:.1f} | {e['rmse']:.2e} | {e['visible_fraction']:.4f} | {e['covered_left_empty']:.4f} |")
print()
print("GL: " + next((r["gl"] for r in b["results"] if "gl" in r), "not run"))
per = f"{b['bytes_per_tet']:.0f} bytes per tetrahedron" if "bytes_per_tet" in b else \
    f"{b['bytes_per_voxel']:.0f} bytes per voxel"
print(f"peak memory of uvr bench: {b['peak_rss_mib']:.0f} MiB ({per})")
PY
