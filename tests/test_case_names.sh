#!/usr/bin/env bash
# Exits 1 when a Catch test case under the directory $1 has a name that starts with "-": ctest passes each name to the
# test program as its filter argument, where a leading dash reads as an option ("Unrecognised token"), so such a test
# fails under ctest alone. With --self-test: shows that the check finds such a name (exits 0 when it does).
set -euo pipefail
if [ "${1:-}" = "--self-test" ]; then
  d=$(mktemp -d); trap 'rm -rf "$d"' EXIT
  printf 'TEST_CASE("--x is refused")\n{\n}\n' > "$d/t.cpp"
  if bash "$0" "$d" > /dev/null; then echo "the check missed a leading dash" >&2; exit 1; fi
  echo "the check finds a leading dash"; exit 0
fi
[ -d "${1:-}" ] || { echo "no directory ${1:-}" >&2; exit 2; }
found=$(grep -rnE 'TEST_CASE\("-' "$1" --include='*.cpp' || true)
if [ -n "$found" ]; then
  echo "test cases whose names start with a dash (rename them):"; echo "$found"
  exit 1
fi
echo "$1: no test case name starts with a dash"
