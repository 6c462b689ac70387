#!/usr/bin/env bash
# `mpirun -np 2 unjam perturb`: the ranks share the ensemble and its records, and the
# results are those of one process; an interrupted mpirun's records resume anywhere; other
# commands and a run without -o are refused under mpirun.
# Usage: cli_perturb_mpi.sh UNJAM_BINARY SOURCE_DIR
source "$(dirname "$0")/harness.bash" "$@"
# Root in CI (../shared/DEPENDENCIES.md, trap 7); one BLAS thread per rank.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OPENBLAS_NUM_THREADS=1
mpirun=(mpirun -np 2 --oversubscribe)

pile="$src/problems/gravity-n100-mu0.5.unjam"
"$unjam" perturb "$pile" --top --threads 1 --json -o "$work/one" >"$work/one.json" 2>/dev/null || fail "one process: exit $?"
"${mpirun[@]}" "$unjam" perturb "$pile" --top --threads 1 --json -o "$work/two" >"$work/two.json" 2>"$work/two.err" || fail "mpirun -np 2: exit $?, $(tail -n 3 "$work/two.err")"
[ "$(grep -c '"complete":true' "$work/two.json")" -eq 1 ] || fail "mpirun: not one complete summary on stdout: $(head -c 300 "$work/two.json")"
# The same rows (all but the seconds) and fields as one process; one records file.
cmp -s <(cut -d, -f1-24 "$work/one/perturbations.csv") <(cut -d, -f1-24 "$work/two/perturbations.csv") || fail "mpirun: other rows than one process"
for f in profile.csv fcrit_histogram.csv field.csv stress.csv displacement.csv; do
  cmp -s "$work/one/$f" "$work/two/$f" || fail "mpirun: $f differs from one process"
done
[ "$(wc -l <"$work/two/records.jsonl")" -eq 11 ] || fail "mpirun: records.jsonl should hold the header and 10 records"
ls "$work/two" | grep -q "records.rank" && fail "mpirun: a rank's records file was left behind"

# The ranks of one mpirun share -o (above: each locks its own part, DIR/.lock for rank 0,
# DIR/.lock.rank1 for rank 1, and removes it at the end); a second run is refused by
# whichever rank's lock it meets: exit 1, the records untouched.
ls -A "$work/two" | grep -q "lock" && fail "mpirun: a lock file was left behind: $(ls -A "$work/two" | tr '\n' ' ')"
cp "$work/two/records.jsonl" "$work/two.records"
for held in .lock .lock.rank1; do
  hold_lock "$work/two/$held"
  "${mpirun[@]}" "$unjam" perturb "$pile" --top --threads 1 -o "$work/two" >/dev/null 2>"$work/held.err"; code=$?
  release_lock
  [ "$code" -eq 1 ] && grep -q "is being written by another run .*two/$held" "$work/held.err" || fail "mpirun with $held held: exit $code, $(head -c 300 "$work/held.err")"
  cmp -s "$work/two/records.jsonl" "$work/two.records" || fail "mpirun with $held held: the records changed"
done

# An mpirun stopped before its merge leaves a file per rank (rank 1's with a torn last line):
# a run on one process resumes from both and merges them.
mkdir "$work/cut"
sed -n '1p;2,5p' "$work/one/records.jsonl" >"$work/cut/records.jsonl"
{ sed -n '1p;6,8p' "$work/one/records.jsonl"; printf '{"index": 9, "torn'; } >"$work/cut/records.rank1.jsonl"
"$unjam" perturb "$pile" --top --threads 1 -o "$work/cut" >/dev/null 2>"$work/cut.err" || fail "resume of an mpirun: exit $?"
grep -q "resuming, 7 of 10 done" "$work/cut.err" || fail "resume of an mpirun: $(head -n 2 "$work/cut.err")"
cmp -s <(cut -d, -f1-24 "$work/one/perturbations.csv") <(cut -d, -f1-24 "$work/cut/perturbations.csv") || fail "resume of an mpirun: other rows"
[ ! -e "$work/cut/records.rank1.jsonl" ] || fail "resume of an mpirun: rank 1's file was not merged"
[ "$(wc -l <"$work/cut/records.jsonl")" -eq 11 ] || fail "resume of an mpirun: records.jsonl should hold 10 records"

# Refused under mpirun: a perturb run without -o, and the other commands.
"${mpirun[@]}" "$unjam" perturb "$pile" --top >/dev/null 2>"$work/noout.err"; code=$?
[ "$code" -ne 0 ] && grep -q "under mpirun, -o DIR is needed" "$work/noout.err" || fail "mpirun perturb without -o: exit $code, $(head -c 300 "$work/noout.err")"
"${mpirun[@]}" "$unjam" info "$pile" >/dev/null 2>"$work/info.err"; code=$?
[ "$code" -ne 0 ] && grep -q "only \`unjam perturb\`, \`unjam study\` and \`unjam bounds\` on contacts divide their work" "$work/info.err" || fail "mpirun info: exit $code, $(head -c 300 "$work/info.err")"

finish cli_perturb_mpi
