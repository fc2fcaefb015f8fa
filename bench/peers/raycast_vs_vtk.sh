#!/usr/bin/env bash
# The ray caster (Krüger and Westermann's passes, emulated and on GL; and GL with --interpolation exact, the full-screen pass) beside
# VTK 9's GPU ray caster on the same volume, in one run (the performance goal).
#   bash bench/peers/raycast_vs_vtk.sh VOLUME [scene options...]     e.g.
#   bash bench/peers/raycast_vs_vtk.sh data/vtk-data/neghip.slc --size 512x512
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
# Rounds alternate uvr and VTK, so that both see the same state of a shared machine; the ratios are taken within a
# round, and their median is the figure reported (docs/raycast.md, "Speed").
for r in $(seq 1 "$rounds"); do
  "$uvr" bench "$@" --algos raycast --backend emu,gl --gl "$gl" --repeat "$repeat" --json > "$dir/published-$r.json"
  "$uvr" bench "$@" --algos raycast --backend gl --gl "$gl" --interpolation exact --repeat "$repeat" --json \
    > "$dir/exact-$r.json"
  mkdir -p "$dir/vtk-$r"
  xvfb-run -a /usr/bin/python3 "$here/bench/peers/vtk_peers.py" "$dir" --mappers gpu --repeat "$repeat" \
    --save "$dir/vtk-$r" > "$dir/vtk-$r.json"
done
/usr/bin/python3 - "$dir" "$rounds" <<'PY'
import json, statistics, sys
d, rounds = sys.argv[1], int(sys.argv[2])
ratios = {}
def keep(name, value):
    ratios.setdefault(name, []).append(value)
for r in range(1, rounds + 1):
    published = json.load(open(f"{d}/published-{r}.json")); exact = json.load(open(f"{d}/exact-{r}.json"))
    vtk = json.load(open(f"{d}/vtk-{r}.json"))["results"][0]
    rows = {(x["backend"], x["classification"], x["interpolation"]): x for x in published["results"] + exact["results"]}
    if r == 1:
        g = rows[("gl", "post", "gpu")]
        print(f"{published['mesh']}: {published['width']}x{published['height']}, step {g['step']}, {published['machine']['cpu']} "
              f"({published['machine']['threads']} threads); GL: {g['gl']}; VTK GPU ray caster {vtk['frame_ms']:.1f} ms")
    print(f"round {r}: VTK GPU ray cast {vtk['frame_ms']:8.1f} ms/frame")
    for (backend, cls, interp), x in sorted(rows.items()):
        s = x["stages"]
        print(f"  uvr {backend:3s} {cls:14s} {interp:5s} {x['frame_ms']:8.1f} ms/frame: setup {s['setup']:.1f}, march "
              f"{s['march']:.1f}, readback {s['readback']:.1f} ms; {x['rays']} rays, {x['samples'] / 1e6:.2f} M samples")
    for cls in ("post", "pre-integrated"):
        keep(f"GL published {cls} / VTK", rows[("gl", cls, "gpu")]["frame_ms"] / vtk["frame_ms"])
        keep(f"GL exact {cls} / GL published", rows[("gl", cls, "exact")]["frame_ms"] / rows[("gl", cls, "gpu")]["frame_ms"])
        keep(f"emulated published {cls} / GL published", rows[("emu", cls, "gpu")]["frame_ms"] / rows[("gl", cls, "gpu")]["frame_ms"])
print(f"median over {rounds} rounds:")
for name, v in ratios.items():
    print(f"  {name:34s} {statistics.median(v):.2f} (range {min(v):.2f}-{max(v):.2f})")
PY
