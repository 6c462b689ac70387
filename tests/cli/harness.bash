# Sourced by every tests/cli/*.sh (not a test itself: ctest registers *.sh only).
#   source "$(dirname "$0")/harness.bash" "$@"   # UNJAM_BINARY SOURCE_DIR
#   ... checks calling `fail MESSAGE` ...
#   finish NAME                                  # the script's exit status: 0 if none failed
# Gives $unjam, $src, a scratch directory $work removed on exit, the failure counter and
# expect_code.
set -u
unjam="$1"
src="${2:-}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
# expect_code CODE DESCRIPTION COMMAND...: the command exits with CODE (stdout and stderr
# kept in $work/out and $work/err for later checks).
expect_code() {
  local want="$1" what="$2"; shift 2
  "$@" >"$work/out" 2>"$work/err"
  local got=$?
  [ "$got" -eq "$want" ] || fail "$what: exit $got, expected $want; stderr: $(head -c 300 "$work/err")"
}
finish() { echo "$1: $failures failures"; [ "$failures" -eq 0 ]; }
