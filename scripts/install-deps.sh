#!/usr/bin/env bash
# Installs, from Debian 12's packages, what uvr needs to build and test. Run as root; does nothing when all is there.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config git
  libembree-dev libglm-dev libosmesa6-dev libegl-dev libegl-mesa0 libtbb-dev libpng-dev zlib1g-dev
  catch2 libtet1.5-dev nlohmann-json3-dev libcli11-dev libpugixml-dev libopenexr-dev libexodusii-dev libnetcdf-dev
  libmetis-dev libopenmpi-dev openmpi-bin
  python3-dev pybind11-dev python3-numpy python3-pytest python3-matplotlib chromium
  # the sanitizer build's compiler and its runtime libraries (scripts/test-sanitize.sh); LLVM's linker (CMakeLists.txt)
  clang libclang-rt-14-dev lld
  # the offline GLSL compiler that checks the shader variants no machine here runs (tests/test_glsl_variants.cpp)
  glslang-tools
)
missing=()
for p in "${packages[@]}"; do
  [ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)" = "install ok installed" ] || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
