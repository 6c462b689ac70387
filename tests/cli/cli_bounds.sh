#!/usr/bin/env bash
# `unjam bounds`: the frictionless V-groove (one network: zero width, F_crit = LP max), the
# frictional one (the analytic interval), the shifts of the small pile (every quasi-static
# F_crit that perturb finds inside its LP interval), CSV and JSON, a run resumed from its
# records, and bad input.
# Usage: cli_bounds.sh UNJAM_BINARY SOURCE_DIR
source "$(dirname "$0")/harness.bash" "$@"

groove() {  # friction output
  printf 'unjam-packing 1\ncell 10 10\ngravity 0 -1\nfriction %s\nparticles 3\n3.8 1 0 0 0 0 1 1 1\n6.2 1 0 0 0 0 1 1 1\n5 2.6 0 0 0 0 1 1 0\nend\n' "$1" >"$work/bare.unjam"
  "$unjam" solve "$work/bare.unjam" --tol 1e-14 -o "$2" >/dev/null || fail "solve: exit $?"
}
groove 0 "$work/g0.unjam"
groove 0.5 "$work/g5.unjam"

"$unjam" bounds "$work/g0.unjam" --json --compare-perturb --threads 1 -o "$work/g0.csv" >"$work/g0.json" || fail "bounds g0: exit $?"
/usr/bin/python3 - "$work/g0.json" "$work/g0.csv" <<'PY' || fail "frictionless groove"
import csv, json, math, sys
d = json.load(open(sys.argv[1]))
for key in ("contacts", "rank", "indeterminacy_dimension", "mean_width", "seconds", "max_rel_diff_fcrit"):
    assert key in d, key
assert d["contacts"] == 2 and d["indeterminacy_dimension"] == 0 and d["feasible"], d
assert abs(d["mean_width"]) < 1e-12, d["mean_width"]
assert d["compared"] == 2 and d["max_rel_diff_fcrit"] < 1e-6, d
assert d["quasi_static"] == 2 and d["inside_interval"] == 2 and d["outside_interval"] == 0 and d["dynamic"] == 0, d
rows = list(csv.DictReader(open(sys.argv[2])))
assert len(rows) == 2
for r in rows:
    assert abs(float(r["max"]) - math.pi / 1.6) < 1e-10, r
    assert abs(float(r["f_crit"]) - float(r["max"])) < 1e-6, r
    assert r["inside_interval"] == "1", r
PY

# A frictional packing: contact 4 of the default packing opens quasi-statically (lemke), and
# a static opening must lie in its contact's interval [LP min, LP max without friction].
"$unjam" bounds "$src/problems/pressure-n500-mu0.5.unjam" --contacts 4 --json --compare-perturb --threads 1 \
  -o "$work/f4.csv" >"$work/f4.json" || fail "bounds --compare-perturb, frictional: exit $?"
/usr/bin/python3 - "$work/f4.json" "$work/f4.csv" <<'PY' || fail "frictional opening inside its LP interval"
import csv, json, sys
d = json.load(open(sys.argv[1]))
assert d["quasi_static"] == 1 and d["inside_interval"] == 1 and d["outside_interval"] == 0, d
(r,) = list(csv.DictReader(open(sys.argv[2])))
assert float(r["min"]) <= float(r["f_crit"]) <= float(r["max_without_friction"]) < float(r["max"]), r
PY

"$unjam" bounds "$work/g5.unjam" --json -o "$work/g5.csv" >"$work/g5.json" || fail "bounds g5: exit $?"
/usr/bin/python3 - "$work/g5.json" "$work/g5.csv" <<'PY' || fail "frictional groove"
import csv, json, math, sys
d = json.load(open(sys.argv[1]))
assert d["indeterminacy_dimension"] == 1, d
for r in csv.DictReader(open(sys.argv[2])):
    assert abs(float(r["min"]) - math.pi / 2.2) < 1e-10, r
    assert abs(float(r["max"]) - math.pi / 1.0) < 1e-10, r
    assert abs(float(r["max_without_friction"]) - math.pi / 1.6) < 1e-10, r
PY

"$unjam" bounds "$work/g5.unjam" --lp ipopt -o "$work/g5i.csv" >/dev/null || fail "--lp ipopt: exit $?"
/usr/bin/python3 - "$work/g5i.csv" <<'PY' || fail "ipopt bounds of the frictional groove"
import csv, math, sys
for r in csv.DictReader(open(sys.argv[1])):
    assert abs(float(r["min"]) - math.pi / 2.2) < 1e-6, r
    assert abs(float(r["max"]) - math.pi / 1.0) < 1e-6, r
PY

"$unjam" bounds "$work/g5.unjam" --contacts 1 --json >"$work/one.json" || fail "--contacts 1: exit $?"
grep -q '"contacts":1' "$work/one.json" || fail "--contacts 1 did not select one contact"

# Particle shifts of the bundled small pile: every quasi-static answer of `perturb` (ok, or
# nonlinear with its answers at ξ and 10ξ) lies in the shift's LP interval.
for side in top bottom; do
  "$unjam" bounds "$src/problems/gravity-n100-mu0.5.unjam" --$side --compare-perturb --threads 1 --json \
    -o "$work/shift-$side.csv" >"$work/shift-$side.json" || fail "bounds --$side: exit $?"
  /usr/bin/python3 - "$work/shift-$side.json" "$work/shift-$side.csv" "$side" <<'PY' || fail "--$side shifts inside their LP intervals"
import csv, json, math, sys
d = json.load(open(sys.argv[1]))
assert d["shifts"] == 10 and d["side"] == sys.argv[3] and d["feasible"], d
for key in ("bounded", "no_lower_bound", "no_upper_bound", "mean_max", "mean_fy", "seconds"):
    assert key in d, key
quasi = d["quasi_static"] + d["nonlinear"]
assert quasi >= 4 and d["inside_interval"] == quasi and d["outside_interval"] == 0, d
rows = list(csv.DictReader(open(sys.argv[2])))
assert len(rows) == 10
for r in rows:
    assert r["status_max"] == "optimal", r  # no shift of this pile is blocked
    if r["inside_interval"] == "1":
        lo = float(r["min"]) if r["min"] else -math.inf
        assert lo - 1e-6 <= float(r["f_crit"]) <= float(r["max"]) + 1e-6, r
    if sys.argv[3] == "top":
        assert float(r["direction_y"]) == -1 and float(r["min"]) <= float(r["f_static"]) <= float(r["max"]), r
PY
done
# The disk in the frictional groove: lifted, it leaves both supports, and no network resists
# (a rattler whatever the solver); pushed down, the supports can resist any push.
printf 'unjam-packing 1\ncell 10 10\nperiodic x\ngravity 0 -1\nfriction 0.5\nparticles 3\n3.8 1 0 0 0 0 1 1 1\n6.2 1 0 0 0 0 1 1 1\n5 2.6 0 0 0 0 1 1 0\nend\n' >"$work/barep.unjam"
"$unjam" solve "$work/barep.unjam" --tol 1e-14 -o "$work/gp.unjam" >/dev/null || fail "solve, periodic groove: exit $?"
"$unjam" bounds "$work/gp.unjam" --bottom --json >"$work/g5b.json" || fail "bounds --bottom, groove: exit $?"
"$unjam" bounds "$work/gp.unjam" --top --json >"$work/g5t.json" || fail "bounds --top, groove: exit $?"
/usr/bin/python3 - "$work/g5b.json" "$work/g5t.json" <<'PY' || fail "shift bounds of the groove"
import json, sys
b, t = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
assert b["shifts"] == 1 and b["bounded"] == 1 and b["need_no_force"] == 1 and b["mean_max"] == 0, b
assert t["shifts"] == 1 and t["no_upper_bound"] == 1 and t["need_no_force"] == 0, t
PY
# One shift alone: the same row as its --top row.
"$unjam" bounds "$src/problems/gravity-n100-mu0.5.unjam" --top -o "$work/top.csv" >/dev/null || fail "bounds --top, small pile: exit $?"
particle=$(awk -F, 'NR == 2 { print $1 }' "$work/top.csv")
"$unjam" bounds "$src/problems/gravity-n100-mu0.5.unjam" --shift-down "$particle" --json -o "$work/one.csv" >"$work/one.json" \
  || fail "bounds --shift-down $particle: exit $?"
[ "$(sed -n 2p "$work/top.csv")" = "$(sed -n 2p "$work/one.csv")" ] || fail "--shift-down $particle differs from its --top row"
grep -q '"side":"down"' "$work/one.json" || fail "bounds --shift-down: side not named: $(cat "$work/one.json")"
expect_code 2 "--shift-down of a fixed particle" "$unjam" bounds "$src/problems/gravity-n100-mu0.5.unjam" --shift-down 0
grep -q -- "--shift-down 0: particle 0 is fixed" "$work/err" || fail "the error does not name the option: $(cat "$work/err")"
expect_code 2 "--shift-up with --top" "$unjam" bounds "$src/problems/gravity-n100-mu0.5.unjam" --shift-up 92 --top
expect_code 2 "--top on a packing without gravity" "$unjam" bounds "$src/problems/pressure-n500-mu0.5.unjam" --top
expect_code 2 "--top with --contacts" "$unjam" bounds "$src/problems/gravity-n100-mu0.5.unjam" --top --contacts 1
expect_code 2 "--top with --bottom" "$unjam" bounds "$src/problems/gravity-n100-mu0.5.unjam" --top --bottom
expect_code 2 "--top with --lp ipopt" "$unjam" bounds "$src/problems/gravity-n100-mu0.5.unjam" --top --lp ipopt

# Long runs: --time-limit 0 obtains no bound and writes no CSV, only the records' header;
# a rerun takes back what the records hold (here a hand-made max of contact 0, and a torn
# last line as a kill leaves) and solves the rest, writes the CSV and removes the records.
"$unjam" bounds "$work/g5.unjam" --time-limit 0 --json -o "$work/long.csv" >"$work/long.json" 2>"$work/err" || fail "--time-limit 0: exit $?"
[ ! -e "$work/long.csv" ] || fail "--time-limit 0 wrote a CSV"
grep -q '"complete":false' "$work/long.json" || fail "--time-limit 0 did not say incomplete: $(cat "$work/long.json")"
grep -q "the same command continues" "$work/err" || fail "--time-limit 0 did not say how to continue: $(cat "$work/err")"
[ "$(wc -l <"$work/long.csv.records.jsonl")" -eq 1 ] || fail "--time-limit 0 recorded bounds"
printf '{"contact":0,"kind":"max","status":"optimal","value":1234.5,"iterations":7,"shortcut":false}\n{"contact":1,"ki' >>"$work/long.csv.records.jsonl"
"$unjam" bounds "$work/g5.unjam" --json -o "$work/long.csv" >"$work/long.json" 2>"$work/err" || fail "bounds resumed: exit $?"
[ ! -e "$work/long.csv.records.jsonl" ] || fail "the records outlived the CSV"
/usr/bin/python3 - "$work/long.json" "$work/long.csv" <<'PY' || fail "bounds resumed from the records"
import csv, json, math, sys
d = json.load(open(sys.argv[1]))
assert d["complete"] and d["bounds_resumed"] == 1 and d["lp_iterations_resumed"] == 7, d
rows = {r["contact"]: r for r in csv.DictReader(open(sys.argv[2]))}
assert float(rows["0"]["max"]) == 1234.5, rows["0"]        # taken from the records, not solved
assert abs(float(rows["1"]["max"]) - math.pi) < 1e-10, rows["1"]
assert abs(float(rows["0"]["min"]) - math.pi / 2.2) < 1e-10, rows["0"]
PY
"$unjam" bounds "$work/g5.unjam" --time-limit 0 -o "$work/long.csv" >/dev/null 2>&1 || fail "--time-limit 0 again: exit $?"
expect_code 2 "records of other parameters" "$unjam" bounds "$work/g5.unjam" --gap-tol 1e-8 -o "$work/long.csv"
grep -q "other parameters (gap_tolerance)" "$work/err" || fail "the error does not name the parameter: $(cat "$work/err")"
rm -f "$work/long.csv"
printf 'not json\n{"contact":0}\n' >>"$work/long.csv.records.jsonl"
expect_code 1 "a bad line in the records" "$unjam" bounds "$work/g5.unjam" -o "$work/long.csv"
grep -q "long.csv.records.jsonl:2" "$work/err" || fail "the error does not name the file and line: $(cat "$work/err")"
[ ! -e "$work/long.csv" ] || fail "bad records left a CSV"
expect_code 2 "--time-limit without -o" "$unjam" bounds "$work/g5.unjam" --time-limit 5
expect_code 2 "--time-limit with --top" "$unjam" bounds "$src/problems/gravity-n100-mu0.5.unjam" --top --time-limit 5 -o "$work/t.csv"
expect_code 2 "--time-limit -1" "$unjam" bounds "$work/g5.unjam" --time-limit -1 -o "$work/neg.csv"
[ ! -e "$work/neg.csv.records.jsonl" ] || fail "--time-limit -1 left records"

check() {  # expected-exit description args...
  local want="$1" what="$2"; shift 2
  "$unjam" bounds "$@" -o "$work/bad.csv" >/dev/null 2>"$work/err"; local code=$?
  [ "$code" -eq "$want" ] || fail "$what: exit $code, expected $want"
  [ -s "$work/err" ] || fail "$what: no error message"
  [ ! -e "$work/bad.csv" ] || { fail "$what: left a CSV"; rm -f "$work/bad.csv"; }
  [ ! -e "$work/bad.csv.records.jsonl" ] || { fail "$what: left records"; rm -f "$work/bad.csv.records.jsonl"; }
}
check 2 "--contacts x" "$work/g5.unjam" --contacts x
check 2 "--contacts 9" "$work/g5.unjam" --contacts 9
check 2 "--contacts 1,1 (listed twice)" "$work/g5.unjam" --contacts 1,1
check 2 "--lp simplex" "$work/g5.unjam" --lp simplex
check 2 "--mode bogus" "$work/g5.unjam" --mode bogus
check 1 "missing file" "$work/none.unjam"

# One run per output: while another process holds FILE.lock, a run is refused (exit 1,
# naming the lock) and writes neither FILE nor its records; once it is released, the run
# goes, and removes its lock at the end. The shifts lock FILE too.
hold_lock "$work/locked.csv.lock"
"$unjam" bounds "$work/g5.unjam" --threads 1 -o "$work/locked.csv" >/dev/null 2>"$work/held.err"; code=$?
"$unjam" bounds "$src/problems/gravity-n100-mu0.5.unjam" --top --threads 1 -o "$work/locked.csv" >/dev/null 2>"$work/held-top.err"; top_code=$?
release_lock
[ "$code" -eq 1 ] && grep -q "locked.csv is being written by another run .*locked.csv.lock" "$work/held.err" || fail "bounds on a locked output: exit $code, $(cat "$work/held.err")"
[ "$top_code" -eq 1 ] && grep -q "locked.csv.lock" "$work/held-top.err" || fail "bounds --top on a locked output: exit $top_code, $(cat "$work/held-top.err")"
ls "$work" | grep -q "^locked.csv$\|^locked.csv.records" && fail "bounds on a locked output wrote: $(ls "$work")"
"$unjam" bounds "$work/g5.unjam" --threads 1 -o "$work/locked.csv" >/dev/null 2>&1 || fail "bounds once the lock is released: exit $?"
[ -s "$work/locked.csv" ] && [ ! -e "$work/locked.csv.lock" ] || fail "bounds once the lock is released: $(ls "$work")"

finish cli_bounds
