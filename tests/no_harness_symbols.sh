#!/usr/bin/env bash
# Exits 1 when the program $1 defines a symbol of the GL stage harnesses (gpu/*/gl_*_harness.*, gpu/gl/gl_harness_pass.h):
# their classes are named Gl*Harness, HarnessPass, their constants kHarness*.
set -euo pipefail
[ -x "$1" ] || { echo "no program at $1" >&2; exit 2; }
found=$(nm -C --defined-only "$1" | grep -E 'Gl[A-Za-z]*Harness|HarnessPass|kHarness' || true)
if [ -n "$found" ]; then
  echo "$1 contains stage-harness symbols:"; echo "$found" | head -20
  exit 1
fi
echo "$1: no stage-harness symbol"
