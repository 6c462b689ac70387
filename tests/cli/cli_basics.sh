#!/usr/bin/env bash
# Command-line behaviour: exit codes, JSON keys, errors naming file and line, no partial
# output. Usage: cli_basics.sh UNJAM_BINARY SOURCE_DIR
source "$(dirname "$0")/harness.bash" "$@"

# A small valid packing: a stack of two disks on a floor.
cat >"$work/stack.unjam" <<'PACK'
unjam-packing 1
cell 10 10
wall 0 0 0 1
gravity 0 -1
friction 0.3
particles 2
# x y angle vx vy spin radius density fixed
5 0.5 0 0 0 0 0.5 1 0
5 1.5 0 0 0 0 0.5 1 0
end
PACK

expect_code 0 "info" "$unjam" info "$work/stack.unjam"
grep -q "particles *2" "$work/out" || fail "info does not list the particles"
expect_code 0 "info --json" "$unjam" info --json "$work/stack.unjam"
/usr/bin/python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["particles"]==2' "$work/out" || fail "info --json"

expect_code 0 "solve --json" "$unjam" solve "$work/stack.unjam" --json --tol 1e-12
/usr/bin/python3 - "$work/out" <<'PY' || fail "solve --json keys or values"
import json, math, sys
d = json.load(open(sys.argv[1]))
for key in ("backend", "particles", "contacts", "iterations", "residual", "converged", "seconds"):
    assert key in d, key
assert d["backend"] == "nsgs" and d["particles"] == 2 and d["contacts"] == 2 and d["converged"]
assert d["residual"] <= 1e-12
# Mean normal force of the two contacts: (2 w + w) / 2 with w = π r² g.
assert abs(d["mean_contact_force"] - 1.5 * math.pi * 0.25) < 1e-10, d["mean_contact_force"]
PY

# Every backend by name, with its own options; the static stack sticks, so the convex
# relaxation is the exact law here.
for args in "--backend newton" "--backend ipopt" "--backend nlopt" "--backend nlopt --nlopt-algorithm ccsaq" \
            "--backend ipopt --convex-relaxation" "--backend nlopt --convex-relaxation"; do
  # shellcheck disable=SC2086
  expect_code 0 "solve $args" "$unjam" solve "$work/stack.unjam" --json --tol 1e-11 $args --require-converged
  /usr/bin/python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["backend"]==sys.argv[2] and d["converged"], d' \
    "$work/out" "$(echo $args | cut -d' ' -f2)" || fail "solve $args"
done

expect_code 0 "solve -o" "$unjam" solve "$work/stack.unjam" -o "$work/solved.unjam"
grep -q "^forces 2" "$work/solved.unjam" || fail "solve -o does not store the forces"
expect_code 0 "info on solved" "$unjam" info "$work/solved.unjam"
grep -q "coordination" "$work/out" || fail "info on a solved packing shows no coordination"

# Not converged: reported, and an error with --require-converged. (On the two-disk stack the
# pattern of a stopped NSGS already gives the exact answer; on the 200-disk column from
# zero impulses it does not.)
column="$src/problems/hard/column-200.unjam"
expect_code 0 "solve with too few iterations" "$unjam" solve "$column" --max-iter 0
grep -q "did not converge" "$work/err" || fail "non-convergence not reported"
expect_code 3 "--require-converged" "$unjam" solve "$column" --max-iter 0 --require-converged
expect_code 0 "a stopped NSGS polished" "$unjam" solve "$work/stack.unjam" --max-iter 0 --require-converged
grep -q "solved exactly on its contact pattern" "$work/out" || fail "the polish is not reported: $(cat "$work/out")"

# A prescribed motion that drives the lower disk into the floor: no impulse can stop it (both
# sides have known motions), which is reported, not solved around.
sed 's/^particles 2/prescribed-motion 0 0 -0.1 0\nparticles 2/' "$work/stack.unjam" >"$work/pushed.unjam"
expect_code 3 "solve a disk pushed into the floor" "$unjam" solve "$work/pushed.unjam" --require-converged
grep -q "particle 0 and a wall, neither of which can give way" "$work/err" || fail "the penetration is not reported: $(cat "$work/err")"

# Bad options: usage errors (2) naming the option.
expect_code 2 "unknown option" "$unjam" solve "$work/stack.unjam" --frobnicate
grep -q "frobnicate" "$work/err" || fail "unknown option not named"
expect_code 2 "unknown backend" "$unjam" solve "$work/stack.unjam" --backend simplex
grep -q "simplex" "$work/err" || fail "unknown backend not named"
expect_code 2 "bad relaxation" "$unjam" solve "$work/stack.unjam" --relaxation 3
grep -q "relaxation" "$work/err" || fail "bad relaxation not named"
expect_code 2 "unknown NLopt algorithm" "$unjam" solve "$work/stack.unjam" --backend nlopt --nlopt-algorithm bfgs
grep -q "bfgs" "$work/err" || fail "unknown NLopt algorithm not named"
expect_code 2 "bad Ipopt iteration limit" "$unjam" solve "$work/stack.unjam" --backend ipopt --ipopt-iter -1
grep -q "ipopt.max_iterations" "$work/err" || fail "bad ipopt.max_iterations not named"
expect_code 2 "a time limit of 0" "$unjam" solve "$work/stack.unjam" --max-seconds 0
grep -q -- "--max-seconds: must be > 0, got 0" "$work/err" || fail "--max-seconds 0: $(head -c 300 "$work/err")"
# A solve stopped by its time limit says so (a 1e-9 s limit is passed at the first check).
"$unjam" solve "$work/stack.unjam" --tol 1e-16 --max-seconds 1e-9 --json >"$work/out" 2>/dev/null
grep -q "time limit of 1e-09 s reached" "$work/out" || fail "--max-seconds 1e-9: $(head -c 300 "$work/out")"
expect_code 2 "unknown command" "$unjam" frobnicate

# Bad input files: exit 1, the file and the line named, no output file left behind.
sed 's/^5 1.5 0 0 0 0 0.5 1 0$/5 1.5 0 0 0 0 -0.5 1 0/' "$work/stack.unjam" >"$work/negative.unjam"
expect_code 1 "negative radius" "$unjam" solve "$work/negative.unjam" -o "$work/never.unjam"
grep -q "negative.unjam:9" "$work/err" || fail "negative radius: file and line not named: $(cat "$work/err")"
[ ! -e "$work/never.unjam" ] || fail "an output file was left behind after an input error"
sed 's/^5 1.5 0 0 0 0 0.5 1 0$/5 nan 0 0 0 0 0.5 1 0/' "$work/stack.unjam" >"$work/nan.unjam"
expect_code 1 "NaN" "$unjam" info "$work/nan.unjam"
sed 's/^5 1.5 0 0 0 0 0.5 1 0$/5 1.2 0 0 0 0 0.5 1 0/' "$work/stack.unjam" >"$work/overlap.unjam"
expect_code 1 "overlap" "$unjam" info "$work/overlap.unjam"
grep -qi "overlap" "$work/err" || fail "overlap not named"
head -n 8 "$work/stack.unjam" >"$work/truncated.unjam"
expect_code 1 "truncated" "$unjam" info "$work/truncated.unjam"
expect_code 1 "missing file" "$unjam" info "$work/does-not-exist.unjam"
# Forces that no static packing has: one contact's force line twice (it would be counted as
# two contacts), a negative normal force.
expect_code 0 "solve -o for its forces" "$unjam" solve "$work/stack.unjam" -o "$work/forces.unjam"
/usr/bin/python3 - "$work/forces.unjam" "$work/duplicate.unjam" "$work/pulling.unjam" <<'PY' || fail "making the bad force files"
import sys
lines = open(sys.argv[1]).read().splitlines()
k = next(i for i, l in enumerate(lines) if l.startswith("forces "))
n = int(lines[k].split()[1])
f = next(i for i in range(k + 1, len(lines)) if not lines[i].startswith("#"))  # the first force line
duplicate = lines[:k] + ["forces %d" % (n + 1), lines[f]] + lines[k + 1:]
open(sys.argv[2], "w").write("\n".join(duplicate) + "\n")
fields = lines[f].split()
fields[4] = "-" + fields[4]
pulling = lines[:f] + [" ".join(fields)] + lines[f + 1:]
open(sys.argv[3], "w").write("\n".join(pulling) + "\n")
PY
expect_code 1 "a duplicated force line" "$unjam" info "$work/duplicate.unjam"
grep -q "duplicate.unjam:[0-9]*: duplicate force of" "$work/err" || fail "duplicated force line: file and line not named: $(cat "$work/err")"
expect_code 1 "a negative normal force" "$unjam" solve "$work/pulling.unjam"
grep -q "pulling.unjam:[0-9]*: normal force must not be negative" "$work/err" || fail "negative normal force: file and line not named: $(cat "$work/err")"
# What solve writes, the reader takes back: ipopt from cold ends normal forces a round-off
# below zero on the default cell (-6e-13), stored as 0.
awk '/^forces/ { skip = 1 } skip && /^end/ { skip = 0 } !skip' "$src/problems/pressure-n500-mu0.5.unjam" >"$work/cold500.unjam"
expect_code 0 "solve --backend ipopt -o" "$unjam" solve "$work/cold500.unjam" --backend ipopt --tol 1e-8 -o "$work/ipopt500.unjam"
expect_code 0 "info on ipopt's forces" "$unjam" info "$work/ipopt500.unjam"
expect_code 1 "unwritable output" "$unjam" solve "$work/stack.unjam" -o "$work/no/such/dir/out.unjam"
ls "$work/no" >/dev/null 2>&1 && fail "output directory was created"

# Range errors name the rule; every command refuses a negative thread count; --version.
small="$src/problems/gravity-n100-mu0.5.unjam"
for cmd in "perturb $small --top" "bounds $small" "solve $small" "pack" "study $src/configs/none.json"; do
  expect_code 2 "$cmd --threads -1" "$unjam" $cmd --threads -1
  grep -q -- "--threads: must be >= 0, got -1" "$work/err" || fail "$cmd --threads -1: $(head -c 300 "$work/err")"
done
expect_code 2 "--sample above the contacts" "$unjam" perturb "$small" --sample 100000
grep -q -- "--sample 100000: the packing has only" "$work/err" || fail "--sample above the contacts: $(head -c 300 "$work/err")"
"$unjam" solve "$small" --json --forces >"$work/forces.json" || fail "solve --json --forces: exit $?"
/usr/bin/python3 - "$work/forces.json" <<'PY' || fail "solve --json --forces: the forces are in the JSON"
import json, sys
d = json.load(open(sys.argv[1]))
f = d["forces"]
assert len(f) == d["contacts"] and all({"i", "j", "image", "f_n", "f_t"} <= set(c) for c in f), d.keys()
PY
# An output folder the file system refuses (a path under a file) is an I/O error, exit 1,
# naming the path, not an internal error.
touch "$work/plainfile"
expect_code 1 "perturb -o under a file" "$unjam" perturb "$small" --shift-down 33 -o "$work/plainfile/out"
grep -q "plainfile/out: Not a directory" "$work/err" || fail "perturb -o under a file: $(head -c 300 "$work/err")"
"$unjam" --version | grep -q "^unjam [0-9]" || fail "--version"

finish cli_basics
