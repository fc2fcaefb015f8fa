#!/usr/bin/env bash
# The frames of every algorithm on every backend, rendered by two builds of uvr and compared byte for byte: for changes
# that must not change a single bit (a rename, a refactoring). Prints one line per frame and exits non-zero when any
# frame differs or fails.
#   bash bench/frames_identical.sh BEFORE_UVR AFTER_UVR
# Environment: BEFORE_SHADERS / AFTER_SHADERS (each build's shaders/ directory, when it is not the one it was built
# with), UVR_DATA_DIR (the data sets, default data/), SIZE (default 256x256).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
before=$1 after=$2
data="${UVR_DATA_DIR:-$root/data}/vtk-data"
size=${SIZE:-256x256}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
bf=("$data/bluntfinxyz.bin" --q "$data/bluntfinq.bin")
frames=(
  "reference-bluntfin|${bf[*]} --algo reference"
  "reference-neghip|$data/neghip.slc --algo reference"
  "havs-emu|${bf[*]} --algo havs --k 6"
  "havs-gl|${bf[*]} --algo havs --k 6 --backend gl"
  "havs-arb|${bf[*]} --algo havs --backend arb"
  "havs-emu-exact|builtin:torus --algo havs --interpolation exact --k 8"
  "vicp-emu|${bf[*]} --algo vicp"
  "vicp-gl|${bf[*]} --algo vicp --backend gl"
  "vicp-gl-exact|builtin:torus --algo vicp --backend gl --interpolation exact --order centroid"
  "raycast-emu|$data/neghip.slc --algo raycast"
  "raycast-gl|$data/neghip.slc --algo raycast --backend gl"
  "raycast-gl-preintegrated|$data/neghip.slc --algo raycast --backend gl --preintegrate"
)
status=0
for f in "${frames[@]}"; do
  name=${f%%|*}
  read -r -a args <<<"${f#*|}"
  ok=1
  UVR_SHADER_DIR="${BEFORE_SHADERS:-}" "$before" render "${args[@]}" --size "$size" --no-cache --out "$dir/$name-before.npy" \
    >/dev/null 2>"$dir/err" || ok=0
  UVR_SHADER_DIR="${AFTER_SHADERS:-}" "$after" render "${args[@]}" --size "$size" --no-cache --out "$dir/$name-after.npy" \
    >/dev/null 2>>"$dir/err" || ok=0
  if [ $ok = 0 ]; then
    echo "FAILED    $name: $(tail -1 "$dir/err")"; status=1
  elif cmp -s "$dir/$name-before.npy" "$dir/$name-after.npy"; then
    echo "identical $name"
  else
    echo "DIFFERENT $name"; status=1
  fi
done
exit $status
