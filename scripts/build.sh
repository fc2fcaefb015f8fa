#!/usr/bin/env bash
# Configures and builds uvr in build/ (Release with debug info). Extra arguments go to the build tool (targets).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j "$(nproc)" -- "$@"
