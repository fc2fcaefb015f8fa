#!/usr/bin/env bash
# The GPU bundle (scripts/gpu-bundle.sh, docs/gpu.md) as the GPU machine gets it: it builds within its size, every
# library the unpacked `uvr` needs beyond glibc resolves inside it, run.sh's llvmpipe check passes in an environment
# holding nothing but the bundle (with --with-mesa, Mesa included), the check's error measures are uvr compare's, --gpu auto without a GPU falls back to
# llvmpipe and says so, and a bad --gl-device is refused with EGL's devices listed.
# Usage: tests/gpu_bundle.sh REPOSITORY UVR_BINARY
set -euo pipefail
repo=$1
uvr=$2
# shellcheck source=tests/script_support.sh
source "$(dirname "$0")/script_support.sh"
data=${UVR_DATA_DIR:-$repo/data}/vtk-data

# A size limit the bundle cannot meet: refused, nothing left behind.
if UVR_BINARY=$uvr UVR_BUNDLE_LEVEL=1 UVR_BUNDLE_LIMIT_MIB=1 bash "$repo/scripts/gpu-bundle.sh" "$tmp/small" 2>"$tmp/err"; then
  fail "a 1 MiB limit was not refused"
fi
grep -q "over its limit of 1 MiB" "$tmp/err" || fail "no clear message for the size limit: $(cat "$tmp/err")"
[ ! -e "$tmp/small/uvr-gpu" ] || fail "a refused bundle was left behind"

# The bundle at a fast level, which makes it larger than the default level does: within the limit here is within it
# there.
UVR_BINARY=$uvr UVR_BUNDLE_LEVEL=3 bash "$repo/scripts/gpu-bundle.sh" "$tmp/b" >/dev/null
bundle=$tmp/b/uvr-gpu
run() { env -i PATH=/usr/bin:/bin HOME="$tmp" UVR_GPU_UNPACK="$tmp/unpacked" "$@"; }
quick=(--sizes 32 --grid 3 --warmup 0 --repeat 1)

run bash "$bundle/run.sh" --gpu llvmpipe "${quick[@]}" --out "$tmp/check" >"$tmp/out" 2>&1 || fail "run.sh --gpu llvmpipe: $(cat "$tmp/out")"
[ -s "$tmp/check/gpu-check.json" ] && [ -s "$tmp/check/index.html" ] || fail "no gpu-check.json or index.html"

# Every library FILE loads, with LIB as the library path, is in LIB or glibc's.
inside_only() {
  LD_LIBRARY_PATH=$2 ldd "$1" >"$tmp/ldd"
  ! grep -q "not found" "$tmp/ldd" || fail "a library of $1 is missing: $(grep 'not found' "$tmp/ldd")"
  outside=$(awk '$2 == "=>" {print $1, $3}' "$tmp/ldd" | grep -v " $2/" |
    grep -Ev '^(libc|libm|libpthread|libdl|librt|libresolv|libutil|libmvec)\.so' || true)
  [ -z "$outside" ] || fail "libraries of $1 resolved outside the bundle: $outside"
}
inside_only "$tmp/unpacked/bin/uvr" "$tmp/unpacked/lib"
# (grep without -q reads every name: -q could stop ls with SIGPIPE, whose status pipefail would turn into a pass.)
[ -z "$(ls "$tmp/unpacked/lib" | grep -E "^lib(OSMesa|LLVM)" || true)" ] || fail "the bundle carries Mesa without --with-mesa"

# --with-mesa: OSMesa and LLVM inside, and the llvmpipe run loads them from there (the library path comes first).
UVR_BINARY=$uvr UVR_BUNDLE_LEVEL=1 bash "$repo/scripts/gpu-bundle.sh" "$tmp/m" --with-mesa >/dev/null
run UVR_GPU_UNPACK="$tmp/unpacked-mesa" bash "$tmp/m/uvr-gpu/run.sh" --gpu llvmpipe "${quick[@]}" \
  --out "$tmp/mesa-check" >"$tmp/out" 2>&1 || fail "--with-mesa, run.sh --gpu llvmpipe: $(cat "$tmp/out")"
inside_only "$tmp/unpacked-mesa/lib/libOSMesa.so.8" "$tmp/unpacked-mesa/lib"

# The check's measures are uvr compare's on the same scene and options.
"$uvr" compare "$data/bluntfinxyz.bin" --q "$data/bluntfinq.bin" --algos reference,havs,vicp --backend gl \
  --size 32x32 --report "$tmp/compare" --json >"$tmp/compare.json"
python3 - "$tmp/check/gpu-check.json" "$tmp/compare.json" <<'PY' || fail "the check's measures differ from uvr compare's"
import json, sys
check = json.load(open(sys.argv[1]))
compare = json.load(open(sys.argv[2]))
ours = {r["label"]: r for r in check["runs"] if r["scene"] == "bluntfinxyz"}
theirs = {r["label"]: r for r in compare["results"]}
for label in ("havs-gl-k6", "vicp-gl-mpvonc"):
    for m in ("rmse", "max_abs", "psnr", "visible_fraction"):
        if ours[label][m] != theirs[label][m]:
            sys.exit(f"{label} {m}: gpu-check {ours[label][m]}, compare {theirs[label][m]}")
PY

# No GPU (EGL offers no device here): --gpu auto falls back to llvmpipe and says so.
run __EGL_VENDOR_LIBRARY_DIRS=/nonexistent bash "$bundle/run.sh" "${quick[@]}" --out "$tmp/auto" >"$tmp/out" 2>&1 ||
  fail "run.sh --gpu auto: $(cat "$tmp/out")"
grep -q "no hardware GPU through EGL" "$tmp/out" && grep -q "llvmpipe through OSMesa" "$tmp/out" ||
  fail "--gpu auto did not say it fell back: $(head -3 "$tmp/out")"
grep -q '"platform": "osmesa"' "$tmp/auto/gpu-check.json" || fail "--gpu auto's JSON does not name OSMesa"

# A device EGL does not have: refused, the devices listed.
if run bash "$bundle/run.sh" --gl-device 9 "${quick[@]}" --out "$tmp/bad" >"$tmp/out" 2>&1; then
  fail "--gl-device 9 was not refused"
fi
grep -q -- "--gl-device 9: no such EGL device (EGL" "$tmp/out" || fail "no list of devices: $(cat "$tmp/out")"
echo "gpu bundle: $(du -sh "$bundle" | cut -f1) at level 3, every check passed"
