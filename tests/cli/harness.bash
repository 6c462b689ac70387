# Sourced by every tests/cli/*.sh (not a test itself: ctest registers *.sh only).
#   source "$(dirname "$0")/harness.bash" "$@"   # UNJAM_BINARY SOURCE_DIR
#   ... checks calling `fail MESSAGE` ...
#   finish NAME                                  # the script's exit status: 0 if none failed
# Gives $unjam, $src, a scratch directory $work removed on exit, the failure counter,
# expect_code, and hold_lock / release_lock.
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
# hold_lock FILE: another process (flock(1)) takes FILE's flock(2) lock, as a run of unjam
# takes the lock of its output, and holds it until release_lock (or $work is removed).
hold_lock() {
  rm -f "$work/.lock-taken" "$work/.lock-release"
  flock -n -o "$1" -c "touch '$work/.lock-taken'; while [ -d '$work' ] && [ ! -e '$work/.lock-release' ]; do sleep 0.05; done" \
    >/dev/null 2>&1 &
  lock_holder=$!
  local tries=0
  until [ -e "$work/.lock-taken" ]; do
    tries=$((tries + 1))
    [ "$tries" -le 200 ] || { fail "hold_lock $1: the lock was not taken"; return 1; }
    sleep 0.05
  done
}
release_lock() { touch "$work/.lock-release"; wait "$lock_holder"; }
finish() { echo "$1: $failures failures"; [ "$failures" -eq 0 ]; }
