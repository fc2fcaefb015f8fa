#!/usr/bin/env bash
# VICP as Moreland's dissertation gives it (--interpolation gpu, the default) beside VTK 9's projected tetrahedra, and beside its own
# variants, in one run (the performance question, "VICP on GL: where its time goes"): per round, uvr bench of
# VICP emulated and on GL (both orders; the GL driver sending the faces that make fragments, --send covered), on GL
# with the published whole stream (--send all), on GL with the exact variant (--interpolation exact), and VTK's
# vtkProjectedTetrahedraMapper.
#   bash bench/peers/vicp_vs_vtk.sh MESH [scene options...]     e.g.
#   bash bench/peers/vicp_vs_vtk.sh data/vtk-data/bluntfinxyz.bin --q data/vtk-data/bluntfinq.bin \
#     --size 512x512
# Environment: GL (osmesa | egl, default osmesa), REPEAT (default 3), ROUNDS (default 3).
# Needs Debian's python3-vtk9, python3-numpy and xvfb (apt-get install python3-vtk9 python3-numpy xvfb).
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
uvr="$here/build/bench/uvr"
gl=${GL:-osmesa}
repeat=${REPEAT:-3}
rounds=${ROUNDS:-3}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$uvr" export "$@" --out "$dir" >/dev/null
# Rounds alternate the runs, so that all see the same state of a shared machine; the ratios are taken within a round,
# and their median is the figure reported (docs/vicp.md, "The publication on GL: speed").
b() { "$uvr" bench "$@" --algos vicp --gl "$gl" --orders mpvonc,centroid --repeat "$repeat" --json; }
for r in $(seq 1 "$rounds"); do
  b "$@" --backend emu,gl > "$dir/published-$r.json"
  b "$@" --backend gl --send all > "$dir/all-$r.json"
  b "$@" --backend gl --interpolation exact > "$dir/exact-$r.json"
  mkdir -p "$dir/vtk-$r"
  xvfb-run -a /usr/bin/python3 "$here/bench/peers/vtk_peers.py" "$dir" --mappers pt --repeat "$repeat" \
    --save "$dir/vtk-$r" > "$dir/vtk-$r.json"
done
/usr/bin/python3 - "$dir" "$rounds" <<'PY'
import json, statistics, sys
d, rounds = sys.argv[1], int(sys.argv[2])
ratios = {}
def keep(name, value):
    ratios.setdefault(name, []).append(value)
for r in range(1, rounds + 1):
    runs = {k: json.load(open(f"{d}/{k}-{r}.json")) for k in ("published", "all", "exact")}
    vtk = json.load(open(f"{d}/vtk-{r}.json"))["results"][0]
    rows = {}
    for k, b in runs.items():
        for x in b["results"]:
            rows[(k if x["backend"] == "gl" else "emu-published", x["order"])] = x
    if r == 1:
        b = runs["published"]
        print(f"{b['mesh']}: {b['tetrahedra']} tetrahedra, {b['width']}x{b['height']}, {b['machine']['cpu']} "
              f"({b['machine']['threads']} threads); GL: {rows[('published', 'mpvonc')]['gl']}")
    print(f"round {r}: VTK projected tetrahedra {vtk['frame_ms']:8.1f} ms/frame")
    for (k, order), x in sorted(rows.items()):
        s = x["stages"]
        print(f"  uvr {k:8s} {order:8s} {x['frame_ms']:8.1f} ms/frame: sort {s['sort']:.1f}, project {s['project']:.1f}, "
              f"vertex and setup {s['vertex_and_setup']:.1f}, raster and fragment {s['raster_and_fragment']:.1f}, "
              f"readback {s['readback']:.1f} ms; {x['bytes_sent_per_tet']:.1f} bytes sent per tetrahedron")
    for order in ("mpvonc", "centroid"):
        published = rows[("published", order)]["frame_ms"]
        keep(f"GL published {order} / VTK PT", published / vtk["frame_ms"])
        keep(f"GL published --send all {order} / GL published", rows[("all", order)]["frame_ms"] / published)
        keep(f"GL exact {order} / GL published", rows[("exact", order)]["frame_ms"] / published)
        keep(f"emulated published {order} / GL published", rows[("emu-published", order)]["frame_ms"] / published)
print(f"median over {rounds} rounds:")
for name, v in ratios.items():
    print(f"  {name:36s} {statistics.median(v):.2f} (range {min(v):.2f}-{max(v):.2f})")
PY
