#!/usr/bin/env bash
# `unjam solve PROBLEM.dat` and `unjam solve FILE --export-problem OUT.dat`: known
# solutions with every backend (ipopt and nlopt refuse a non-symmetric W), both residual
# measures, the impulses file, export of a packing and re-reading it, errors naming file
# and line, no output left on error.
# Usage: cli_siconos.sh UNJAM_BINARY SOURCE_DIR
source "$(dirname "$0")/harness.bash" "$@"
problems="$src/problems/siconos"
# check_impulses JSON_FILE r0 r1 ...: the impulses of a --json --forces run, to 1e-12.
check_impulses() {
  /usr/bin/python3 - "$@" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
want = [float(x) for x in sys.argv[2:]]
got = [x for pair in d["impulses"] for x in pair]
assert d["converged"] and d["format"] == "siconos", d
assert len(got) == len(want), (got, want)
assert all(abs(g - w) <= 1e-12 for g, w in zip(got, want)), (got, want)
assert d["residual"] <= 1e-12 and d["siconos_error"] <= 1e-12, d
assert d["contacts"] * 2 == d["unknowns"] == len(want)
PY
}

# Hand-written problems (solutions in problems/README.md), every backend.
for backend in nsgs newton ipopt nlopt; do
  expect_code 0 "stick $backend" "$unjam" solve "$problems/one-contact-stick.dat" --backend "$backend" --json --forces --tol 1e-14
  check_impulses "$work/out" 0.5 -0.1 || fail "one-contact-stick with $backend"
  expect_code 0 "coupled $backend" "$unjam" solve "$problems/coupled-block-slide.dat" --backend "$backend" --json --forces --tol 1e-14
  check_impulses "$work/out" 0.5555555555555556 -0.1111111111111111 || fail "coupled-block-slide with $backend"
  for storage in dense block triplet csc; do
    expect_code 0 "two contacts $storage $backend" "$unjam" solve "$problems/two-contacts-stick-$storage.dat" --backend "$backend" --json --forces --tol 1e-14
    check_impulses "$work/out" 1 -0.11428571428571428 1 0.08571428571428572 || fail "two-contacts-stick-$storage with $backend"
  done
done

# Text output: both measures; -o writes the impulses, one contact per line.
expect_code 0 "text and -o" "$unjam" solve "$problems/two-contacts-open.dat" -o "$work/r.txt"
grep -q "^residual " "$work/out" || fail "no residual line"
grep -q "^siconos error " "$work/out" || fail "no Siconos error line"
grep -q "^contacts *2 (4 unknowns)" "$work/out" || fail "contacts line"
[ "$(wc -l <"$work/r.txt")" -eq 2 ] || fail "impulses file has $(wc -l <"$work/r.txt") lines, expected 2"
/usr/bin/python3 -c 'import sys; rows=[list(map(float,l.split())) for l in open(sys.argv[1])]; assert abs(rows[0][0]-0.5)<1e-12 and rows[1]==[0.0,0.0], rows' "$work/r.txt" || fail "impulses file content"

# Not converged: reported; exit 3 with --require-converged.
expect_code 0 "no sweeps" "$unjam" solve "$problems/two-contacts-open.dat" --max-iter 0
grep -q "did not converge" "$work/err" || fail "non-convergence not reported"
expect_code 3 "--require-converged" "$unjam" solve "$problems/two-contacts-open.dat" --max-iter 0 --require-converged

# A packing's problem: exported, read back and solved to the same forces. Stack of two
# disks (mass π/4, g = 1) on a floor: normal impulses w and 2w, with and without friction.
write_stack() {  # FILE MU
  cat >"$1" <<PACK
unjam-packing 1
cell 10 10
wall 0 0 0 1
gravity 0 -1
friction $2
particles 2
5 0.5 0 0 0 0 0.5 1 0
5 1.5 0 0 0 0 0.5 1 0
end
PACK
}
for mu in 0.3 0; do
  write_stack "$work/stack.unjam" "$mu"
  expect_code 0 "export mu=$mu" "$unjam" solve "$work/stack.unjam" --export-problem "$work/stack.dat" --json
  /usr/bin/python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["exported_problem"]==sys.argv[2] and d["converged"]' "$work/out" "$work/stack.dat" || fail "export JSON mu=$mu"
  [ "$(sed -n 2p "$work/stack.dat")" = "2" ] || fail "exported problem does not have 2 contacts (mu=$mu)"
  [ "$(tail -n 1 "$work/stack.dat")" = "$mu $mu" ] || fail "exported friction coefficients: $(tail -n 1 "$work/stack.dat"), expected $mu $mu"
  expect_code 0 "solve export mu=$mu" "$unjam" solve "$work/stack.dat" --json --forces --tol 1e-13
  /usr/bin/python3 - "$work/out" <<'PY' || fail "exported stack forces mu=$mu"
import json, math, sys
d = json.load(open(sys.argv[1]))
w = math.pi / 4
normals = sorted(r[0] for r in d["impulses"])
assert d["converged"] and abs(normals[0] - w) < 1e-12 and abs(normals[1] - 2 * w) < 1e-12, d
assert all(abs(r[1]) < 1e-12 for r in d["impulses"]), d
PY
  # Re-exporting a read problem gives the same bytes (round-trip precision).
  expect_code 0 "re-export mu=$mu" "$unjam" solve "$work/stack.dat" --export-problem "$work/again.dat"
  cmp -s "$work/stack.dat" "$work/again.dat" || fail "re-export differs (mu=$mu)"
done

# A held contact cannot be posed in Siconos' problem: refused, nothing written.
write_stack "$work/held.unjam" 0.3
sed -i 's/^particles 2$/prescribed-gap 0 1 0 0 0\nparticles 2/' "$work/held.unjam"
expect_code 1 "held contact export" "$unjam" solve "$work/held.unjam" --export-problem "$work/held.dat"
grep -q "held" "$work/err" || fail "held contact not named: $(cat "$work/err")"
[ ! -e "$work/held.dat" ] || fail "an export was left behind for a held contact"

# A non-symmetric W: ipopt and nlopt refuse it (no convex program), a usage error (exit 2)
# naming the reason; nothing is written. nsgs solves it as given.
printf '2\n1\n0\n2\n2\n2 2\n2 1\n0 4\n-1 0\n1\n' >"$work/nonsym.dat"
for backend in ipopt nlopt; do
  expect_code 2 "non-symmetric W with $backend" "$unjam" solve "$work/nonsym.dat" --backend "$backend" -o "$work/never.txt"
  grep -q "not symmetric" "$work/err" || fail "non-symmetric W with $backend: reason not named: $(cat "$work/err")"
done
expect_code 0 "non-symmetric W with nsgs" "$unjam" solve "$work/nonsym.dat" --backend nsgs --tol 1e-14

# Bad problem files: exit 1, file and line named, no output left behind.
printf '2\n1\n0\n2\n2\n2 2\n2 0\nnan 4\n-1 0.4\n1\n' >"$work/nan.dat"
expect_code 1 "NaN in W" "$unjam" solve "$work/nan.dat" -o "$work/never.txt" --export-problem "$work/never.dat"
grep -q "nan.dat:8" "$work/err" || fail "NaN: file and line not named: $(cat "$work/err")"
printf '3\n1\n' >"$work/three.dat"
expect_code 1 "3D problem" "$unjam" solve "$work/three.dat"
grep -q "three.dat:1: .*dimension 3" "$work/err" || fail "dimension not named: $(cat "$work/err")"
head -n 9 "$problems/one-contact-stick.dat" >"$work/truncated.dat"
expect_code 1 "truncated" "$unjam" solve "$work/truncated.dat" -o "$work/never.txt"
grep -q "truncated.dat:9: truncated" "$work/err" || fail "truncation not named: $(cat "$work/err")"
{ cat "$problems/one-contact-stick.dat"; echo 0.5; } >"$work/extra.dat"
expect_code 1 "extra number" "$unjam" solve "$work/extra.dat"
grep -q "extra.dat:11: unexpected data" "$work/err" || fail "extra data not named: $(cat "$work/err")"
# An ill-posed W (a diagonal entry <= 0: no Delassus operator H M^-1 H^T) is refused before
# any backend can call it solved: exit 1, the file, line and contact named, nothing written.
printf '2\n2\n0\n4 4\n4 4\n-2 0 0 0\n0 -4 0 0\n0 0 -2 0\n0 0 0 -4\n-1 0 -1 0\n0.5 0.5\n' >"$work/negative-w.dat"
printf '2\n2\n0\n4 4\n4 4\n0 0 0 0\n0 0 0 0\n0 0 0 0\n0 0 0 0\n-1 0 -1 0\n0.5 0.5\n' >"$work/zero-w.dat"
sed '8s/^0 3 0 0.5$/0 0 0 0.5/' "$problems/two-contacts-stick-dense.dat" >"$work/zero-tangent.dat"
for bad in negative-w zero-w zero-tangent; do
  for backend in nsgs newton lemke; do
    expect_code 1 "$bad with $backend" "$unjam" solve "$work/$bad.dat" --backend "$backend" --json -o "$work/never.txt" --export-problem "$work/never.dat"
    grep -q "converged" "$work/out" && fail "$bad with $backend: a solution was reported: $(cat "$work/out")"
  done
done
expect_code 1 "negative W, text" "$unjam" solve "$work/negative-w.dat"
grep -q "negative-w.dat:3: contact 0: W\[0\]\[0\] (its normal diagonal entry) is -2, not positive: W is not a Delassus operator" "$work/err" || fail "negative W: file, line or contact not named: $(cat "$work/err")"
expect_code 1 "zero tangent of W" "$unjam" solve "$work/zero-tangent.dat"
grep -q "zero-tangent.dat:3: contact 0: W\[1\]\[1\] (its tangential diagonal entry) is 0" "$work/err" || fail "zero tangent of W: not named: $(cat "$work/err")"
expect_code 1 "negative W in compare" "$unjam" compare "$work/negative-w.dat" --backends nsgs --tols 1e-8
grep -q "negative-w.dat:3: contact 0" "$work/err" || fail "compare: ill-posed W not named: $(cat "$work/err")"
expect_code 1 "missing problem file" "$unjam" solve "$work/does-not-exist.dat"
expect_code 1 "unwritable impulses" "$unjam" solve "$problems/one-contact-stick.dat" -o "$work/no/such/dir/r.txt"
expect_code 1 "unwritable export" "$unjam" solve "$problems/one-contact-stick.dat" --export-problem "$work/no/such/dir/p.dat"
for f in never.txt never.dat; do [ ! -e "$work/$f" ] || fail "$f was left behind after an input error"; done
ls "$work/no" >/dev/null 2>&1 && fail "output directory was created"
ls "$work" | grep -q '\.tmp\.' && fail "a temporary file was left behind"

finish cli_siconos
