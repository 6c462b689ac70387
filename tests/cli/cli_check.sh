#!/usr/bin/env bash
# `unjam check`: the hard-case catalogue (problems/hard) on the fast backends, a short run:
# every row solved or honestly reported; the ill-posed W files refused; the CSV written;
# exit 5 when a row fails, 0 otherwise.
# Usage: cli_check.sh UNJAM_BINARY SOURCE_DIR
source "$(dirname "$0")/harness.bash" "$@"
hard="$src/problems/hard"

cases=()
for f in all-fixed blocked four-disks-square gap-1e-12 heavy-on-light no-contacts one-particle radius-ratio-100 \
  v-groove-lid wedge; do cases+=("$hard/$f.unjam"); done
"$unjam" check "${cases[@]}" "$hard"/ill-posed-*.dat "$src/problems/siconos/collection/FrictionContactProblem00031.dat" \
  --backends nsgs,newton,lemke --steps 20 --quiet --json -o "$work/c" >"$work/c.json"
rc=$?
/usr/bin/python3 - "$work/c.json" "$work/c/stability.csv" "$rc" <<'PY' || fail "check results"
import csv, json, sys
d = json.load(open(sys.argv[1]))
rows = list(csv.DictReader(open(sys.argv[2])))
assert len(rows) == len(d["rows"]) == 11 * 3 + 2, len(rows)
by = {(r["case"], r["backend"]): r for r in rows}
for name in ("ill-posed-negative-diagonal.dat", "ill-posed-zero-w.dat"):
    r = by[(name, "-")]
    assert r["verdict"] == "reported" and "refused by the reader" in r["message"] and "not positive" in r["message"], r
for b in ("nsgs", "newton", "lemke"):
    assert by[("blocked.unjam", b)]["verdict"] == "reported", by[("blocked.unjam", b)]
    for name in ("all-fixed.unjam", "no-contacts.unjam", "one-particle.unjam", "radius-ratio-100.unjam", "four-disks-square.unjam",
                 "FrictionContactProblem00031.dat"):
        assert by[(name, b)]["verdict"] == "solved", by[(name, b)]
for r in rows:
    if r["status"] == "converged" and r["verdict"] != "FAILED":
        assert float(r["residual"]) <= 1e-10, r
    if r["backend"] != "-":
        assert r["finite"] == "true" and r["reproducible"] == "true", r
# newton's answer on the 1e6 mass ratio (1e-4 off at 8e-11) is solved exactly on its pattern.
r = by[("heavy-on-light.unjam", "newton")]
assert r["verdict"] == "solved" and float(r["equilibrium"]) <= 1e-12, r
failed = [r for r in rows if r["verdict"] == "FAILED"]
assert d["failed"] == bool(failed) and int(sys.argv[3]) == (5 if failed else 0), (d["failed"], sys.argv[3])
PY

# A case list with only sound rows exits 0; a missing path or an empty folder is an input error.
"$unjam" check "$hard/one-particle.unjam" --backends nsgs --steps 5 --quiet >/dev/null || fail "one-particle: exit $?"
expect_code 1 "a missing case" "$unjam" check "$work/missing.unjam" --quiet
mkdir -p "$work/empty"
expect_code 1 "a folder without cases" "$unjam" check "$work/empty" --quiet
expect_code 2 "an unknown backend" "$unjam" check "$hard/one-particle.unjam" --backends nosuch --quiet
mkdir -p "$work/held"
hold_lock "$work/held/.lock"
expect_code 1 "a held output" "$unjam" check "$hard/one-particle.unjam" --backends nsgs -o "$work/held" --quiet
release_lock
[ ! -e "$work/held/stability.csv" ] || fail "a held output was written"
# A killed `check -o DIR` keeps the rows it recorded; the same command takes them back and
# runs only the rest; the records go once stability.csv holds every row.
resume=("$unjam" check "$hard/one-particle.unjam" "$hard/column-200.unjam" --backends nsgs
  --steps 1000000 --max-step-seconds 3 -o "$work/resume")
"${resume[@]}" --quiet &
pid=$!
for _ in $(seq 300); do
  [ "$(wc -l <"$work/resume/stability.records.jsonl" 2>/dev/null || echo 0)" -ge 2 ] && break
  sleep 0.1
done
kill -9 "$pid"
wait "$pid" 2>/dev/null
[ "$(wc -l <"$work/resume/stability.records.jsonl")" -eq 2 ] || fail "check: one row recorded before the kill"
[ ! -e "$work/resume/stability.csv" ] || fail "check: a table written before the end"
expect_code 2 "a resume with other options" "${resume[@]/1000000/5}" --quiet
[ "$(wc -l <"$work/resume/stability.records.jsonl")" -eq 2 ] || fail "check: records kept on a refusal"
"${resume[@]}" >/dev/null 2>"$work/resume.err" || fail "check resumed: exit $?"
grep -q "resuming: 1 rows" "$work/resume.err" || fail "check resumed: $(cat "$work/resume.err")"
[ "$(grep -c nsgs "$work/resume/stability.csv")" -eq 2 ] || fail "check resumed: rows $(cat "$work/resume/stability.csv")"
[ ! -e "$work/resume/stability.records.jsonl" ] || fail "check resumed: records left behind"
# Near-coincident contacts: nsgs converges to 1e-12 with the weight on the tilted wall; the
# answer `unjam solve` gives, solved on its corrected pattern, has it on the floor (wall 0).
"$unjam" solve "$hard/near-coincident.unjam" --json --forces >"$work/nc.json" 2>"$work/warn" ||
  fail "solve near-coincident: exit $?"
[ ! -s "$work/warn" ] || fail "solve near-coincident: unexpected stderr: $(cat "$work/warn")"
/usr/bin/python3 - "$work/nc.json" <<'PY' || fail "near-coincident forces"
import json, math, sys
d = json.load(open(sys.argv[1]))
f = {c["j"]: c["f_n"] for c in d["forces"]}
assert abs(f[-1] - math.pi / 4) < 1e-14 and abs(f[-2]) < 1e-14, f
PY
"$unjam" solve "$hard/v-groove-lid.unjam" >/dev/null 2>"$work/nowarn" || fail "solve v-groove-lid: exit $?"
[ ! -s "$work/nowarn" ] || fail "solve v-groove-lid: unexpected stderr: $(cat "$work/nowarn")"

finish cli_check
