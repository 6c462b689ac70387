#!/usr/bin/env bash
# `mpirun -np 2 unjam bounds`: the ranks share the contacts and their records, and the
# bounds are those of one process on as many threads, bit for bit; an mpirun stopped by
# --time-limit resumes on one process; the shifts and a run without -o are refused.
# Usage: cli_bounds_mpi.sh UNJAM_BINARY SOURCE_DIR
source "$(dirname "$0")/harness.bash" "$@"
# Root in CI (../shared/DEPENDENCIES.md, trap 7).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mpirun=(mpirun -np 2 --oversubscribe)

packing="$src/problems/pressure-n500-mu0.5.unjam"
contacts=$(seq -s, 0 3 120)  # 41 contacts
"$unjam" bounds "$packing" --contacts "$contacts" --threads 2 --json -o "$work/one.csv" >"$work/one.json" || fail "one process: exit $?"
"${mpirun[@]}" "$unjam" bounds "$packing" --contacts "$contacts" --threads 1 --json -o "$work/two.csv" >"$work/two.json" 2>"$work/two.err" \
  || fail "mpirun -np 2: exit $?, $(tail -n 3 "$work/two.err")"
cmp -s "$work/one.csv" "$work/two.csv" || fail "mpirun: other bounds than one process on two threads"
ls "$work" | grep -q "records" && fail "mpirun: records were left behind: $(ls "$work")"
/usr/bin/python3 - "$work/one.json" "$work/two.json" <<'PY' || fail "mpirun: another summary"
import json, sys
one, two = (json.loads(open(p).read().strip()) for p in sys.argv[1:])
assert two["ranks"] == 2 and two["complete"] and two["bounds_resumed"] == 0, two
for key in ("mean_width", "bounded_contacts", "no_frictionless_equilibrium", "lps_skipped", "indeterminacy_dimension"):
    assert one[key] == two[key], (key, one[key], two[key])
# The LPs' iterations are the same; rank 0's feasibility LP counts once.
assert one["lp_iterations"] == two["lp_iterations"], (one["lp_iterations"], two["lp_iterations"])
PY

# An mpirun whose time is up before any LP leaves the header in each rank's file; one
# process continues from there and merges them.
"${mpirun[@]}" "$unjam" bounds "$packing" --contacts "$contacts" --threads 1 --time-limit 0 --json -o "$work/cut.csv" \
  >"$work/cut.json" 2>"$work/cut.err" || fail "mpirun --time-limit 0: exit $?, $(tail -n 3 "$work/cut.err")"
grep -q '"complete":false' "$work/cut.json" || fail "mpirun --time-limit 0: not incomplete: $(cat "$work/cut.json")"
[ ! -e "$work/cut.csv" ] || fail "mpirun --time-limit 0 wrote a CSV"
[ -e "$work/cut.csv.records.jsonl" ] || fail "mpirun --time-limit 0: no records"
"$unjam" bounds "$packing" --contacts "$contacts" --threads 2 -o "$work/cut.csv" >/dev/null 2>"$work/cut.err" || fail "resume of an mpirun: exit $?"
cmp -s "$work/one.csv" "$work/cut.csv" || fail "resume of an mpirun: other bounds"
ls "$work" | grep -q "cut.csv.records" && fail "resume of an mpirun: records left behind"

# Each rank locks its own part (FILE.lock for rank 0, FILE.rank1.lock for rank 1) and
# removes it at the end. A second run is refused by whichever rank's lock it meets: exit 1,
# the refused rank writes nothing and the CSV stays; a rank that met no lock has solved its
# share into its own records file, which the next run takes back.
ls "$work" | grep -q "lock" && fail "mpirun: a lock file was left behind: $(ls "$work" | tr '\n' ' ')"
cp "$work/one.csv" "$work/one.before"
for held in one.csv.lock:one.csv.records.jsonl one.csv.rank1.lock:one.csv.records.rank1.jsonl; do
  lock="${held%%:*}" own="${held##*:}"
  before="$(cat "$work/$own" 2>/dev/null | md5sum)"
  hold_lock "$work/$lock"
  "${mpirun[@]}" "$unjam" bounds "$packing" --contacts "$contacts" --threads 1 -o "$work/one.csv" >/dev/null 2>"$work/held.err"; code=$?
  release_lock
  [ "$code" -eq 1 ] && grep -q "is being written by another run .*$lock" "$work/held.err" || fail "mpirun with $lock held: exit $code, $(head -c 300 "$work/held.err")"
  [ "$before" = "$(cat "$work/$own" 2>/dev/null | md5sum)" ] || fail "mpirun with $lock held: the refused rank wrote $own"
  cmp -s "$work/one.csv" "$work/one.before" || fail "mpirun with $lock held: the CSV changed"
done
"$unjam" bounds "$packing" --contacts "$contacts" --threads 2 -o "$work/one.csv" >/dev/null 2>&1 || fail "after the refused runs: exit $?"
cmp -s "$work/one.csv" "$work/one.before" || fail "after the refused runs: other bounds"
ls "$work" | grep -q "one.csv.records" && fail "after the refused runs: records left behind: $(ls "$work" | tr "\n" " ")"

# Refused under mpirun: bounds without -o, and the shifts.
"${mpirun[@]}" "$unjam" bounds "$packing" --contacts 1 >/dev/null 2>"$work/noout.err"; code=$?
[ "$code" -ne 0 ] && grep -q "under mpirun, -o FILE is needed" "$work/noout.err" || fail "mpirun bounds without -o: exit $code, $(head -c 300 "$work/noout.err")"
"${mpirun[@]}" "$unjam" bounds "$src/problems/gravity-n100-mu0.5.unjam" --top -o "$work/top.csv" >/dev/null 2>"$work/top.err"; code=$?
[ "$code" -ne 0 ] && grep -q "on contacts divide their work" "$work/top.err" || fail "mpirun bounds --top: exit $code, $(head -c 300 "$work/top.err")"

finish cli_bounds_mpi
