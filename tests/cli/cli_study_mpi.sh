#!/usr/bin/env bash
# `mpirun -np 2 unjam study`: the ranks divide the steps (packings first) and the tables are
# those of one process; a rerun under mpirun finds every step done.
# Usage: cli_study_mpi.sh UNJAM_BINARY SOURCE_DIR
source "$(dirname "$0")/harness.bash" "$@"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OPENBLAS_NUM_THREADS=1
mpirun=(mpirun -np 2 --oversubscribe)

cat >"$work/tiny.json" <<JSON
{"threads": 1,
 "pressure": {"n": 30, "mu": [0, 0.5], "seeds": [1, 2], "openings": 4},
 "gravity": {"n": 12, "width": 8, "mu": [0.5], "seeds": [1]}}
JSON
"$unjam" study "$work/tiny.json" -o "$work/one" --quiet >/dev/null 2>"$work/one.err" || fail "one process: exit $?"
"${mpirun[@]}" "$unjam" study "$work/tiny.json" -o "$work/two" --quiet >"$work/two.out" 2>"$work/two.err" || fail "mpirun -np 2: exit $?, $(tail -n 3 "$work/two.err")"
[ "$(grep -c "^study $work/two:" "$work/two.out")" -eq 1 ] || fail "mpirun: not one report line: $(cat "$work/two.out")"
/usr/bin/python3 - "$work/one" "$work/two" <<'PY' || fail "mpirun: other tables than one process"
import csv, sys
def table(folder, name):
    rows = list(csv.DictReader(open(f"{folder}/{name}")))
    for r in rows:
        r.pop("seconds")  # wall time, not a result
    return rows
for name in ("runs.csv", "summary-pressure.csv", "summary-gravity.csv"):
    assert table(sys.argv[1], name) == table(sys.argv[2], name), name
PY
ls -A "$work/two" | grep -q "lock" && fail "mpirun: the study's lock was left behind"
"${mpirun[@]}" "$unjam" study "$work/tiny.json" -o "$work/two" >/dev/null 2>"$work/again.err" || fail "mpirun rerun: exit $?"
grep -q "study\[rank [01]\]: \(pack\|perturb\|bounds\)" "$work/again.err" && fail "mpirun rerun repeated work: $(head -c 300 "$work/again.err")"

finish cli_study_mpi
