#!/usr/bin/env bash
# The repository stands alone and names the published algorithms by what they select (docs/spec.md §11):
#   bash tests/standalone.sh SOURCE_DIR UVR_PROGRAM   exits 1 when a file of the repository refers to a directory beside
#     the checkout (the parent's shared/), or when the program's help (every sub-command's) offers a choice named
#     "seed", the word the published algorithms' options no longer use;
#   bash tests/standalone.sh --self-test              shows both checks failing on a file and a help text made to fail.
set -euo pipefail
beside='\.\./'"shared"   # spelled in two pieces, so that this file does not match itself
scan_tree() {  # $1: a directory; prints the files that refer to the directory beside the checkout
  grep -rIlE "$beside" "$1" --exclude-dir='build*' --exclude-dir=.git --exclude-dir=out || true
}
scan_help() {  # stdin: help texts; prints their lines that offer "seed"
  grep -inwE 'seed' || true
}
if [ "${1:-}" = --self-test ]; then
  dir=$(mktemp -d); trap 'rm -rf "$dir"' EXIT
  printf 'data in ../%s/data\n' shared >"$dir/doc.md"
  [ -n "$(scan_tree "$dir")" ] || { echo "self-test: a reference to the shared directory went unseen"; exit 1; }
  [ -n "$(printf '  --entries TEXT  marked | seed\n' | scan_help)" ] || { echo "self-test: 'seed' went unseen"; exit 1; }
  echo "self-test: both checks fail on what they must refuse"
  exit 0
fi
src=$1 uvr=$2
status=0
found=$(scan_tree "$src")
if [ -n "$found" ]; then echo "files referring to a directory beside the checkout:"; echo "$found"; status=1; fi
help=$("$uvr" --help; for c in info render compare sweep budget bench export demo; do "$uvr" "$c" --help; done)
offered=$(printf '%s\n' "$help" | scan_help)
if [ -n "$offered" ]; then echo "help offering 'seed':"; echo "$offered"; status=1; fi
[ $status = 0 ] && echo "standalone: no reference beside the checkout, no 'seed' in the help"
exit $status
