#!/usr/bin/env bash
# The GPU check's run.sh (scripts/gpu-bundle.sh copies it into the bundle; docs/gpu.md):
#   ./run.sh [--gpu auto|llvmpipe] [--gl-device N] --out OUT [more uvr gpu-check options]
# Unpacks the bundle once into UVR_GPU_UNPACK (default: $TMPDIR/uvr-gpu-UID), then runs `uvr gpu-check` on the
# bundle's Blunt Fin with only the bundle's libraries beside glibc and the GPU driver. GLVND's libEGL finds the
# driver's EGL library through the machine's own vendor files (/usr/share/glvnd/egl_vendor.d).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
unpack=${UVR_GPU_UNPACK:-${TMPDIR:-/tmp}/uvr-gpu-$(id -u)}
if [ ! -f "$unpack/MANIFEST" ] || ! cmp -s "$here/MANIFEST" "$unpack/MANIFEST"; then
  rm -rf "$unpack"
  mkdir -p "$unpack"
  while read -r f; do
    mkdir -p "$unpack/$(dirname "$f")"
    LD_LIBRARY_PATH="$here/tools" "$here/tools/zstd" -q -d --long=27 "$here/payload/$f.zst" -o "$unpack/$f"
  done <"$here/MANIFEST"
  chmod +x "$unpack/bin/uvr"
  cp "$here/MANIFEST" "$unpack/MANIFEST"  # last: a complete unpacking is one with its manifest
fi
export LD_LIBRARY_PATH="$unpack/lib"
export UVR_SHADER_DIR="$unpack/shaders"
exec "$unpack/bin/uvr" gpu-check "$unpack/data/bluntfinxyz.bin" --q "$unpack/data/bluntfinq.bin" "$@"
