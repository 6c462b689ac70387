#!/usr/bin/env bash
# `unjam` without a command: the main job on the default packing, on a small sample. The
# table and its CSV agree, a quasi-static F_crit lies inside its LP interval, the figure is
# a PNG, and main-job options are refused beside a command.
# Usage: cli_main_job.sh UNJAM_BINARY SOURCE_DIR
source "$(dirname "$0")/harness.bash" "$@"

cd "$work"
"$unjam" --sample 3 --seed 4 --threads 1 --out "$work/mj" >"$work/out.txt" || fail "main job: exit $?"
grep -q "static solve.*(converged)" "$work/out.txt" || fail "no static solve line"
grep -q "LP bounds" "$work/out.txt" || fail "no LP line"
[ "$(grep -c -E '^ +[0-9]+-[0-9]+ ' "$work/out.txt")" = 3 ] || fail "table has not 3 rows"
head -c 8 "$work/mj/displacement.png" | od -An -c | grep -q "P   N   G" || fail "displacement.png is not a PNG"
[ -s "$work/mj/response.vtk" ] || fail "no response.vtk"
/usr/bin/python3 - "$work/mj/main-job.csv" <<'PY' || fail "main-job.csv"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 3, len(rows)
for r in rows:
    assert r["status"] in ("ok", "dynamic", "nonlinear", "blocked", "not-converged"), r
    assert r["lp_min"] != "" and r["lp_max"] != "", r
    lo, hi, fc = float(r["lp_min"]), float(r["lp_max"]), float(r["f_crit"])
    assert lo <= float(r["f_cont"]) * (1 + 1e-9) + 1e-9 and float(r["f_cont"]) <= hi * (1 + 1e-9) + 1e-9, r
    if r["status"] == "ok":  # a static opening is one admissible network
        assert lo - 1e-6 <= fc <= hi + 1e-6, r
print(sum(r["status"] == "ok" for r in rows), "quasi-static")
PY
[ ! -e "$work/unjam-main-job" ] || fail "wrote into the working directory despite --out"

"$unjam" --sample 0 >/dev/null 2>"$work/err.txt"; rc=$?
[ $rc = 2 ] || fail "--sample 0: exit $rc"
"$unjam" --sample 2 info "$2/problems/gravity-n100-mu0.5.unjam" >/dev/null 2>"$work/err.txt"; rc=$?
[ $rc = 2 ] && grep -q "main job" "$work/err.txt" || fail "main-job option beside a command: exit $rc"

finish cli_main_job
