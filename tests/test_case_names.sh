#!/usr/bin/env bash
# Exits 1 when a Catch test case under the directory $1 has a name that ctest cannot hand back to its program:
# - a leading "-": ctest passes each name to the test program as its filter argument, where a dash reads as an option
#   ("Unrecognised token"), so such a test fails under ctest alone;
# - a ";": test discovery reads the name as a CMake list and makes two entries of it, each matching no test case.
# With --self-test: shows that the check finds both (exits 0 when it does).
set -euo pipefail
if [ "${1:-}" = "--self-test" ]; then
  d=$(mktemp -d); trap 'rm -rf "$d"' EXIT
  printf 'TEST_CASE("--x is refused")\n{\n}\n' > "$d/dash.cpp"
  if bash "$0" "$d" > /dev/null; then echo "the check missed a leading dash" >&2; exit 1; fi
  rm "$d/dash.cpp"
  semicolon=';'  # kept out of the literal, so that this file holds no such name itself
  printf 'TEST_CASE("x is read%s y is refused", "[tag]")\n{\n}\n' "$semicolon" > "$d/semicolon.cpp"
  if bash "$0" "$d" > /dev/null; then echo "the check missed a semicolon" >&2; exit 1; fi
  echo "the check finds a leading dash and a semicolon"; exit 0
fi
[ -d "${1:-}" ] || { echo "no directory ${1:-}" >&2; exit 2; }
found=$(grep -rnE 'TEST_CASE\("(-|[^"]*;)' "$1" --include='*.cpp' || true)
if [ -n "$found" ]; then
  echo "test cases whose names start with a dash or hold a semicolon (rename them):"; echo "$found"
  exit 1
fi
echo "$1: no test case name starts with a dash or holds a semicolon"
