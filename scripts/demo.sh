#!/usr/bin/env bash
# README command 1: install what is missing, build, and run `uvr demo`.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh uvr
./build/bench/uvr demo "$@"
