#!/usr/bin/env bash
# scripts/gpu-bundle.sh DIR [--with-mesa]: builds DIR/uvr-gpu/, the GPU check for a machine that has a GPU driver and
# nothing else (docs/gpu.md): the `uvr` program, the shared libraries it needs beyond glibc (GLVND's libEGL among them,
# which opens the driver's), the shaders and Blunt Fin, each file compressed, with run.sh (scripts/gpu-bundle-run.sh)
# and the decompressor it unpacks them with. Mesa's OSMesa, which uvr opens only for llvmpipe, is the machine's own;
# --with-mesa adds it and its libraries (LLVM), for a machine without Mesa.
# Fails, leaving no DIR/uvr-gpu, when the bundle exceeds UVR_BUNDLE_LIMIT_MIB (default 60; 100 with --with-mesa).
# UVR_BINARY names the `uvr` to bundle (default build/bench/uvr, built by scripts/build.sh when missing);
# UVR_BUNDLE_LEVEL is zstd's level (default 19; a lower level is faster and makes a larger bundle).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dir=${1:?usage: scripts/gpu-bundle.sh DIR [--with-mesa]}
with_mesa=0
case "${2:-}" in
  "") ;;
  --with-mesa) with_mesa=1 ;;
  *) echo "gpu-bundle: unknown option '$2' (usage: scripts/gpu-bundle.sh DIR [--with-mesa])" >&2; exit 2 ;;
esac
uvr=${UVR_BINARY:-$root/build/bench/uvr}
limit_mib=${UVR_BUNDLE_LIMIT_MIB:-$((with_mesa ? 100 : 60))}
level=${UVR_BUNDLE_LEVEL:-19}
[ -x "$uvr" ] || bash "$root/scripts/build.sh"
data=${UVR_DATA_DIR:-$root/data}

# glibc's libraries and the loader: every Linux machine has them, and they must be the machine's own.
is_base() {
  case "$1" in
    linux-vdso.so.* | ld-linux*.so.* | libc.so.* | libm.so.* | libpthread.so.* | libdl.so.* | librt.so.* | \
      libresolv.so.* | libutil.so.* | libmvec.so.*) return 0 ;;
  esac
  return 1
}

# The libraries `ldd` resolves for each argument, glibc's left out, by their real files.
closure() {
  ldd "$@" | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3}' | sort -u | while read -r name path; do
    is_base "$name" || echo "$name $path"
  done
}

stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/tree/bin" "$stage/tree/lib" "$stage/tree/shaders" "$stage/tree/data" "$stage/out/tools"
# Line tables are of no use on the GPU machine.
strip --strip-debug -o "$stage/tree/bin/uvr" "$uvr"
closure "$uvr" | while read -r name path; do cp -L "$path" "$stage/tree/lib/$name"; done
if [ "$with_mesa" = 1 ]; then
  # awk reads to the end: leaving early could kill ldconfig with SIGPIPE, which pipefail makes this script's exit.
  osmesa=$(ldconfig -p | awk '$1 == "libOSMesa.so.8" && !found {print $NF; found = 1}')
  [ -n "$osmesa" ] || { echo "gpu-bundle: --with-mesa: no libOSMesa.so.8 here (Debian's libosmesa6)" >&2; exit 1; }
  cp -L "$osmesa" "$stage/tree/lib/libOSMesa.so.8"
  closure "$osmesa" | while read -r name path; do cp -L "$path" "$stage/tree/lib/$name"; done
fi
cp "$root"/shaders/* "$stage/tree/shaders/"
cp "$data/vtk-data/bluntfinxyz.bin" "$data/vtk-data/bluntfinq.bin" "$stage/tree/data/"

# The decompressor travels uncompressed, with the libraries it needs beyond glibc.
cp -L "$(command -v zstd)" "$stage/out/tools/zstd"
closure "$(command -v zstd)" | while read -r name path; do cp -L "$path" "$stage/out/tools/$name"; done

# Each file compressed on its own (run.sh needs no tar), with a window over the largest library (Embree, 43 MB), two
# files at a time.
(cd "$stage/tree" && find . -type f | sed 's|^\./||' | sort) >"$stage/out/MANIFEST"
(cd "$stage/tree" && xargs -P 2 -I{} zstd -q "-$level" --long=27 {} -o {}.zst) <"$stage/out/MANIFEST"
while read -r f; do
  mkdir -p "$stage/out/payload/$(dirname "$f")"
  mv "$stage/tree/$f.zst" "$stage/out/payload/$f.zst"
done <"$stage/out/MANIFEST"
cp "$root/scripts/gpu-bundle-run.sh" "$stage/out/run.sh"
chmod +x "$stage/out/run.sh"

size=$(du -sb "$stage/out" | cut -f1)
if [ "$size" -gt $((limit_mib * 1024 * 1024)) ]; then
  echo "gpu-bundle: the bundle is $((size / 1024 / 1024)) MiB, over its limit of $limit_mib MiB" >&2
  exit 1
fi
rm -rf "$dir/uvr-gpu"
mkdir -p "$dir"
mv "$stage/out" "$dir/uvr-gpu"
echo "gpu-bundle: $dir/uvr-gpu, $((size / 1024 / 1024)) MiB ($(wc -l <"$dir/uvr-gpu/MANIFEST") files)"
