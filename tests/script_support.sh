# Sourced by the tests written in bash: a temporary directory removed on exit ($tmp), and fail MESSAGE.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
