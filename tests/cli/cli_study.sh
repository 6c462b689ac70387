#!/usr/bin/env bash
# `unjam study`: a tiny study runs end to end; frictionless openings need exactly their
# contact force; every count adds up; a rerun repeats nothing and writes the same tables; a
# run whose perturbations lost their outputs is finished from its records; a second writer,
# a cached packing of other parameters and a bad configuration are refused.
# Usage: cli_study.sh UNJAM_BINARY SOURCE_DIR
source "$(dirname "$0")/harness.bash" "$@"

cat >"$work/tiny.json" <<JSON
{
  "description": "tiny",
  "output": "$work/study",
  "threads": 1,
  "pressure": {"n": 30, "mu": [0, 0.5], "seeds": [1], "openings": 4, "max_steps": 20000},
  "gravity": {"n": 12, "width": 8, "mu": [0.5], "seeds": [1]}
}
JSON
out="$work/study"

"$unjam" study "$work/tiny.json" --quiet >"$work/first.txt" 2>"$work/first.err" || fail "study: exit $?: $(head -c 400 "$work/first.err")"
for f in study.json runs.csv summary-pressure.csv summary-gravity.csv report.md; do
  [ -s "$out/$f" ] || fail "no $f"
done
/usr/bin/python3 - "$out" <<'PY' || fail "the tables"
import csv, math, sys
out = sys.argv[1]
pressure = list(csv.DictReader(open(out + "/summary-pressure.csv")))
gravity = list(csv.DictReader(open(out + "/summary-gravity.csv")))
runs = list(csv.DictReader(open(out + "/runs.csv")))
assert [r["mu"] for r in pressure] == ["0", "0.5"], pressure
assert [r["kind"] for r in gravity] == ["top", "bottom"], gravity
assert len(runs) == 4, runs
for r in pressure + gravity:
    parts = sum(int(r[k]) for k in ("ok", "dynamic", "nonlinear", "not_converged", "blocked"))
    assert parts == int(r["perturbations"]), r
for r in pressure:
    assert int(r["perturbations"]) == 4, r
# Without friction holding a contact open takes its force: F_crit = F_cont (plus the
# mechanism's inertia, below 1e-5 of it), and the LP interval is one point.
frictionless = pressure[0]
assert int(frictionless["ok"]) == 4, frictionless
assert abs(float(frictionless["ratio_fcrit_freference"]) - 1) < 1e-5, frictionless
assert abs(float(frictionless["lp_min"]) - float(frictionless["lp_max"])) < 1e-6 * float(frictionless["lp_max"]), frictionless
assert 3.5 < float(frictionless["z"]) <= 4.0 + 1e-12, frictionless
for r in pressure + gravity:
    assert 0.5 < float(r["packing_fraction"]) < 0.95, r
assert float(gravity[0]["height"]) > 0, gravity
PY
grep -q "^| 30 | 0 | fixed-pressure | 1 | 4 | 4 |" "$out/report.md" || fail "report.md: no frictionless row"
# The steps print no summary of their own: the study's stdout is its own lines.
grep -q '^{\|^perturbations \|^ensemble ' "$work/first.txt" && fail "a step's summary on stdout: $(head -c 300 "$work/first.txt")"
if grep -q "figures skipped" "$work/first.txt"; then
  echo "figures skipped by the build"
else
  ls "$out"/figures/*.png >/dev/null 2>&1 || fail "no figures: $(cat "$work/first.txt")"
fi

# A rerun finds every step done: nothing solved again, the same tables.
cp "$out/summary-pressure.csv" "$work/pressure.csv"
cp "$out/summary-gravity.csv" "$work/gravity.csv"
"$unjam" study "$work/tiny.json" >"$work/second.txt" 2>"$work/second.err" || fail "rerun: exit $?"
grep -q "^study: \(pack\|perturb\|bounds\)" "$work/second.err" && fail "the rerun repeated work: $(head -c 300 "$work/second.err")"
cmp -s "$out/summary-pressure.csv" "$work/pressure.csv" || fail "the rerun changed summary-pressure.csv"
cmp -s "$out/summary-gravity.csv" "$work/gravity.csv" || fail "the rerun changed summary-gravity.csv"
"$unjam" study "$work/tiny.json" --plan >"$work/plan.txt" || fail "--plan: exit $?"
grep -q "todo" "$work/plan.txt" && fail "--plan lists work to do after a finished study"

# A run killed after its records, before its tables: finished from the records alone.
run=$(ls -d "$out"/runs/pressure-n30-p1-mu0.5-seed1/openings-fixed-pressure)
rm "$run/summary.json" "$run/perturbations.csv"
"$unjam" study "$work/tiny.json" >/dev/null 2>"$work/third.err" || fail "resume: exit $?"
grep -q "resuming, 4 of 4 done" "$work/third.err" || fail "resume did not use the records: $(head -c 300 "$work/third.err")"
cmp -s "$out/summary-pressure.csv" "$work/pressure.csv" || fail "the resumed study changed its table"

# A time limit: no step starts after it; the tables hold the runs finished so far.
"$unjam" study "$work/tiny.json" -o "$work/later" --time-limit 0 >/dev/null 2>"$work/later.err" || fail "--time-limit 0: exit $?"
grep -q "11 steps left; the same command continues" "$work/later.err" || fail "--time-limit 0: $(head -c 300 "$work/later.err")"
[ "$(wc -l <"$work/later/runs.csv")" -eq 1 ] || fail "--time-limit 0: runs.csv should hold its header alone"
[ -e "$work/later/packings" ] && fail "--time-limit 0 made a packing"

# One writer per study.
hold_lock "$out/.study.lock"
expect_code 1 "a second writer" "$unjam" study "$work/tiny.json"
grep -q "study.lock" "$work/err" || fail "second writer: message does not name the lock: $(cat "$work/err")"
release_lock

# A cached packing made with other parameters is not taken for the study's.
packing="$out/packings/pressure-n30-p1-mu0-seed1.unjam"
sed -i 's/^provenance unjam pack \(.*\) --mu 0 /provenance unjam pack \1 --mu 0.25 /' "$packing"
expect_code 1 "a cached packing of other parameters" "$unjam" study "$work/tiny.json"
grep -q "pressure-n30-p1-mu0-seed1.unjam.*other parameters" "$work/err" || fail "cache mismatch message: $(cat "$work/err")"

# A bad configuration: file, line and key.
printf '{\n  "output": "o",\n  "pressure": {"mu": [0.5], "seeds": [1], "opennings": 4}\n}\n' >"$work/bad.json"
expect_code 1 "an unknown key" "$unjam" study "$work/bad.json"
grep -q "bad.json:3: pressure.opennings: unknown key" "$work/err" || fail "bad config message: $(cat "$work/err")"
expect_code 1 "an unknown size" "$unjam" study "$work/tiny.json" --size paper
grep -q 'no size "paper"' "$work/err" || fail "unknown size message: $(cat "$work/err")"

finish cli_study
