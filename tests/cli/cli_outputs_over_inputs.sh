#!/usr/bin/env bash
# An output that names an input file (also as ./P, through a symbolic link, or as a file an
# output directory would hold) is refused before any work: exit 2 naming the option, the
# input left as it was, nothing written.
# Usage: cli_outputs_over_inputs.sh UNJAM_BINARY SOURCE_DIR
source "$(dirname "$0")/harness.bash" "$@"

printf 'unjam-packing 1\ncell 10 10\ngravity 0 -1\nparticles 3\n3.8 1 0 0 0 0 1 1 1\n6.2 1 0 0 0 0 1 1 1\n5 2.6 0 0 0 0 1 1 0\nend\n' >"$work/bare.unjam"
"$unjam" solve "$work/bare.unjam" --tol 1e-14 -o "$work/vg.unjam" >/dev/null || fail "solve: exit $?"
cp "$src/problems/siconos/one-contact-stick.dat" "$work/p.dat"
ln -s vg.unjam "$work/link.unjam"
mkdir "$work/cmp" && cp "$work/vg.unjam" "$work/cmp/summary.json"
mkdir "$work/pert" && cp "$work/vg.unjam" "$work/pert/summary.json"
for f in vg.unjam p.dat cmp/summary.json pert/summary.json; do cp "$work/$f" "$work/$f.orig"; done

# The files of the scratch directories but the harness's own (out, err).
files() { ls -A "$work" "$work/cmp" "$work/pert" | grep -vx 'out\|err'; }
# refused OPTION INPUT DESCRIPTION COMMAND...: exit 2, the option named, INPUT unchanged, and
# the directories hold no file they did not hold before.
refused() {
  local option="$1" input="$2" what="$3"; shift 3
  local before; before="$(files)"
  expect_code 2 "$what" "$@"
  grep -q -- "$option .*which it would overwrite\|$option .*would overwrite the input file\|$option and" "$work/err" || fail "$what: the option is not named: $(cat "$work/err")"
  cmp -s "$work/$input" "$work/$input.orig" || fail "$what: the input $input was changed"
  [ "$before" = "$(files)" ] || fail "$what: files were written"
}
cd "$work" || exit 1
refused -o vg.unjam "solve P -o P" "$unjam" solve vg.unjam -o vg.unjam
refused -o vg.unjam "solve P -o ./P" "$unjam" solve vg.unjam -o ./vg.unjam
refused -o vg.unjam "solve ./P -o P through a link" "$unjam" solve ./vg.unjam -o "$work/link.unjam"
refused --export-problem vg.unjam "solve P --export-problem P" "$unjam" solve vg.unjam --export-problem "$work/vg.unjam"
refused -o p.dat "solve X.dat -o X.dat" "$unjam" solve p.dat -o ./p.dat
refused --export-problem p.dat "solve X.dat --export-problem X.dat" "$unjam" solve p.dat --export-problem p.dat
refused -o p.dat "solve -o and --export-problem one file" "$unjam" solve vg.unjam -o p.dat --export-problem ./p.dat
refused -o vg.unjam "bounds P -o P" "$unjam" bounds vg.unjam -o ./vg.unjam
refused -o vg.unjam "bounds P --shift-up -o P" "$unjam" bounds vg.unjam --shift-up 2 -o vg.unjam
refused -o vg.unjam "perturb P -o P" "$unjam" perturb vg.unjam --all -o vg.unjam
refused -o pert/summary.json "perturb DIR/summary.json -o DIR" "$unjam" perturb pert/summary.json --all -o ./pert
refused -o cmp/summary.json "compare DIR/summary.json -o DIR" "$unjam" compare vg.unjam cmp/summary.json --backends nsgs -o cmp
refused -o vg.unjam "compare P -o P" "$unjam" compare vg.unjam --backends nsgs -o vg.unjam
# pack: the checkpoint is removed once the packing is written, so it cannot be the output.
expect_code 2 "pack --checkpoint OUT -o OUT" "$unjam" pack --protocol gravity --n 4 --width 8 -o pile.unjam --checkpoint ./pile.unjam
grep -q -- "--checkpoint ./pile.unjam is the output file" "$work/err" || fail "pack: --checkpoint not named: $(cat "$work/err")"
[ ! -e pile.unjam ] || fail "pack --checkpoint OUT -o OUT wrote pile.unjam"

# Other names are outputs as before.
expect_code 0 "solve -o another file" "$unjam" solve vg.unjam -o solved.unjam --export-problem vg.dat
[ -s solved.unjam ] && [ -s vg.dat ] || fail "solve -o another file: no outputs"

finish cli_outputs_over_inputs
