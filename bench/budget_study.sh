#!/usr/bin/env bash
# The error-budget study of docs/budget.md: `uvr budget` for HAVS (k = 2, 6, 16), VICP (MPVONC and the
# centroid order) and the ray caster (two steps) on the data sets of data/, then the interpolation factor against the image
# size, then one table of every number (OUT/study.md). Finished budgets are kept and not redone.
#   bash bench/budget_study.sh                       # every view (VIEWS), SIZE 512x512, SIZES "512 1024 2048 4096"
#   VIEWS="0,0" SIZES="512 1024 2048" bash bench/budget_study.sh     # a smaller subset
# Environment: OUT (default budget-study), SIZE, VIEWS (azimuth,elevation list), SIZES (square image sides).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
uvr="$here/build/bench/uvr"
data="$here/data/vtk-data"
out=${OUT:-budget-study}
size=${SIZE:-512x512}
views=${VIEWS:-"0,0 120,30 240,-30"}
sizes=${SIZES:-"512 1024 2048 4096"}
mkdir -p "$out"
declare -A meshes=(
  [bluntfin]="$data/bluntfinxyz.bin --q $data/bluntfinq.bin"
  [post]="$data/postxyz.bin --q $data/postq.bin --field StagnationEnergy"
  [torus]="builtin:torus"
)
run() {  # NAME ARGS...: one budget into OUT/NAME, unless done
  local name=$1; shift
  [ -s "$out/$name/budget.json" ] && return 0
  echo "budget $name" >&2
  "$uvr" budget "$@" --report "$out/$name" > /dev/null || echo "budget $name: the baseline check failed" >&2
}
for m in bluntfin post torus; do
  for v in $views; do
    tag="$m-${v/,/_}"
    for k in 2 6 16; do run "havs-k$k-$tag" ${meshes[$m]} --view "$v" --size "$size" --algo havs --k "$k"; done
    for o in mpvonc centroid; do run "vicp-$o-$tag" ${meshes[$m]} --view "$v" --size "$size" --algo vicp --order "$o"; done
  done
done
for vol in neghip.slc hydrogen.vti; do
  for step in 0.5 1; do run "raycast-step$step-${vol%.*}" "$data/$vol" --size "$size" --algo raycast --step "$step"; done
done
# The interpolation factor against the image size: the baseline with the paper's interpolation (HAVS) or the paper's
# interpolation and the rasterizer's coverage (VICP: its varyings exist only on the rasterizer's fragments), against
# the reference, on Blunt Fin from the first view.
v=${views%% *}
for n in $sizes; do
  for a in havs vicp; do
    d="$out/size-$a-$n"
    [ -s "$d/metrics.json" ] && continue
    echo "interpolation factor $a ${n}x$n" >&2
    cov=exact; [ "$a" = vicp ] && cov=gpu
    "$uvr" compare ${meshes[bluntfin]} --view "$v" --size "${n}x$n" --algos "$a" --k all --segment exact \
      --coverage "$cov" --threshold 1 --interpolation gpu --report "$d" > /dev/null
  done
done
/usr/bin/python3 - "$out" <<'PY'
import glob, json, os, sys
out = sys.argv[1]
lines = ["| run | baseline RMSE | " + " | ".join(["factor", "RMSE", "largest"]) + " |", "|---|---|---|---|---|"]
rows = []
for f in sorted(glob.glob(f"{out}/*/budget.json")):
    b = json.load(open(f))
    name = os.path.basename(os.path.dirname(f))
    def cell(r):  # RMSE, and the fraction of visibly wrong pixels when there are any
        v = r["visible_fraction"]
        return f"{r['rmse']:.1e}" + (f" ({100 * v:.1f} %)" if v > 0 else "")
    facs = "; ".join(f"{n} {cell(b['factors'][n])}" for n in b["factor_order"])
    rows.append(f"| {name} | {b['baseline']['max_abs']:.1e}{'' if b['baseline_ok'] else ' (not ok)'} | {facs} | "
                f"{cell(b['total'])} | {b['total']['max_abs']:.2e} |")
print("| budget | baseline largest error | factors: RMSE (visibly wrong pixels) | total | total largest |")
print("|---|---|---|---|---|")
print("\n".join(rows))
print()
print("| image size | HAVS interpolation factor RMSE | largest | VICP interpolation factor RMSE | largest |")
print("|---|---|---|---|---|")
sizes = sorted({int(d.split("-")[-1]) for d in glob.glob(f"{out}/size-*-*")})
for n in sizes:
    cells = []
    for a in ("havs", "vicp"):
        p = f"{out}/size-{a}-{n}/metrics.json"
        if not os.path.exists(p):
            cells += ["", ""]
            continue
        r = [x for x in json.load(open(p))["results"] if x["algo"] == a][0]
        cells += [f"{r['rmse']:.2e}", f"{r['max_abs']:.2e}"]
    print(f"| {n} x {n} | " + " | ".join(cells) + " |")
PY
