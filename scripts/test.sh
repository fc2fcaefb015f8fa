#!/usr/bin/env bash
# README command 2: install what is missing, build everything, and run the whole test suite with ctest.
# The tests read the data sets in data/ (UVR_DATA_DIR overrides).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DUVR_DATA_DIR="${UVR_DATA_DIR:-$PWD/data}" >/dev/null
bash scripts/build.sh
cd build
ctest --output-on-failure -j "$(nproc)"
