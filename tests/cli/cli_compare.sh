#!/usr/bin/env bash
# `unjam compare`: runs per (problem, backend, tolerance), residuals honest (converged means
# at or below the tolerance), unique solutions found by every backend, figures written, bad
# options refused.
# Usage: cli_compare.sh UNJAM_BINARY SOURCE_DIR
source "$(dirname "$0")/harness.bash" "$@"

"$unjam" compare "$src/problems/siconos/one-contact-slide.dat" "$src/problems/siconos/two-contacts-open.dat" \
  "$src/problems/gravity-n100-mu0.5.unjam" --openings 1 --backends nsgs,newton --tols 1e-6,1e-10 \
  --quiet --json -o "$work/c" >"$work/c.json" || fail "compare: exit $?"
/usr/bin/python3 - "$work/c.json" "$work/c/compare.csv" <<'PY' || fail "compare results"
import csv, json, sys
d = json.load(open(sys.argv[1]))
assert d["problems"] == 4 and d["runs"] == 4 * 2 * 2, d
rows = list(csv.DictReader(open(sys.argv[2])))
assert len(rows) == 16, len(rows)
for r in rows:
    if r["converged"] == "true":
        assert float(r["residual"]) <= float(r["tolerance"]), r
    else:
        assert float(r["residual"]) > float(r["tolerance"]), r
# Unique solutions (hand-worked .dat problems): every backend lands on the reference.
for r in rows:
    if r["problem"] in ("one-contact-slide", "two-contacts-open"):
        assert r["converged"] == "true" and float(r["force_distance"]) < 1e-9, r
assert {r["problem"] for r in rows} >= {"gravity-n100-mu0.5 static"}, {r["problem"] for r in rows}
PY
for png in work-precision profiles; do
  head -c 8 "$work/c/$png.png" | od -An -c | grep -q "P   N   G" || fail "$png.png is not a PNG"
done

"$unjam" compare "$src/problems/siconos/one-contact-slide.dat" --tols 1e-6,0 >/dev/null 2>"$work/err"; rc=$?
[ $rc = 2 ] && grep -q -- "--tols" "$work/err" || fail "zero tolerance: exit $rc"
"$unjam" compare "$src/problems/siconos/one-contact-slide.dat" --backends nsgs,bogus >/dev/null 2>"$work/err"; rc=$?
[ $rc = 2 ] && grep -q "bogus" "$work/err" || fail "unknown backend: exit $rc"
"$unjam" compare "$work/missing.dat" -o "$work/m" >/dev/null 2>"$work/err"; rc=$?
[ $rc = 1 ] && [ ! -e "$work/m/compare.csv" ] || fail "missing file: exit $rc"

# The output is claimed before any solve: another run's lock, or a path that cannot be a
# directory, is refused at once, with nothing written.
mkdir -p "$work/held"
hold_lock "$work/held/.lock"
expect_code 1 "compare over a held output" "$unjam" compare "$src/problems/gravity-n100-mu0.5.unjam" --openings 3 -o "$work/held"
grep -q "held" "$work/err" || fail "held output: message names no output: $(cat "$work/err")"
[ ! -e "$work/held/compare.csv" ] || fail "held output: compare.csv written"
grep -q "compare gravity" "$work/err" && fail "held output: solved before refusing"
release_lock
touch "$work/plainfile"
expect_code 1 "compare into a file's subdirectory" "$unjam" compare "$src/problems/siconos/one-contact-slide.dat" -o "$work/plainfile/c"
grep -q "plainfile" "$work/err" || fail "unwritable output: message names no path: $(cat "$work/err")"

finish cli_compare
