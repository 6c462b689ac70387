#!/usr/bin/env bash
# Regenerates the bundled packings in problems/ exactly (same parameters, same seeds, one
# thread: the same bits). Usage: scripts/make-problems.sh [BUILD_DIR] [NAME_PATTERN]
# Each packing is skipped when its file exists (delete it to remake it); a run prints its
# JSON summary to problems/logs/NAME.json.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
unjam="${1:-$root/build}/unjam"
pattern="${2:-}"
cd "$root"
mkdir -p problems/logs

pack() {  # pack NAME ARGS...: unjam pack ARGS into problems/NAME.unjam, unless it exists
  local name="$1"; shift
  [[ -z "$pattern" || "$name" == *$pattern* ]] || return 0
  [ -e "problems/$name.unjam" ] && { echo "keep problems/$name.unjam"; return 0; }
  echo "make problems/$name.unjam: unjam pack $*"
  "$unjam" pack "$@" -o "problems/$name.unjam" --json --quiet >"problems/logs/$name.json"
}
# --refine-iter 0: these bundled packings were made before certificates refined the last
# step's forces (docs/packings.md); without it they would pass earlier, elsewhere.
make() {  # make NAME ARGS...
  pack "$@" --refine-iter 0
}
# Every bundled packing was made before the time step became 0.02 (and a pile's sweeps per
# step 1000, its sweep order height): their recipes name the earlier defaults, --dt 0.01
# for the cells, --dt 0.005 and --order random (and --step-iter 500 where it was the
# default) for the piles.
cell_then=(--dt 0.01)
pile_then=(--dt 0.005 --order random)

# Homogeneous packings at constant external pressure P_ext = 1, fully periodic.
for mu in 0.5 1 10 0.1 0.01; do
  make "pressure-n500-mu$mu" --protocol pressure --n 500 --mu "$mu" --seed 1 "${cell_then[@]}"
done

# The frictionless packing is the newest: `--mu 0` picks newton steps solved to 1e-8 (the
# defaults of --backend auto and --step-tol), with which the certificates pass; loose NSGS
# steps stall at the isostatic point (docs/performance.md). Made after refinement became
# the default, it keeps it.
pack pressure-n500-mu0 --protocol pressure --n 500 --mu 0 --seed 1 "${cell_then[@]}"
# A hard case, nearly frictionless (μ = 1e-8), with today's defaults and newton steps,
# which start from the frictionless solution (docs/backends.md): NSGS steps stall as at
# μ = 0, and newton steps did not certify it before that start (docs/performance.md).
pack pressure-n500-mu1e-8 --protocol pressure --n 500 --mu 1e-8 --seed 1 --backend newton
# N = 3000 was made with 2000 NSGS sweeps per dynamics step, like the tall pile below:
# without refined certificates, 500 left no certificate passing in 15 000 steps (with
# them the defaults certify it, docs/performance.md).
make pressure-n3000-mu0.5 --protocol pressure --n 3000 --mu 0.5 --seed 1 --step-iter 2000 "${cell_then[@]}"

# Piles settled under gravity g = 1 on a rough bed, periodic in x, width 100.
# At mu = 1 the dynamics needs 2000 sweeps per step: with 500, unconverged steps leave
# the tall pile under-supported and it creeps for ever (docs/performance.md).
make gravity-n1600-mu0.1 --protocol gravity --n 1600 --mu 0.1 --width 100 --seed 1 "${pile_then[@]}" --step-iter 500
make gravity-n1600-mu1 --protocol gravity --n 1600 --mu 1 --width 100 --seed 1 --step-iter 2000 "${pile_then[@]}"

# A hard case, with today's defaults: a tall narrow pile, 200 disks 8 wide (about 37
# diameters high), mu = 0.1. Lemke's path from zero impulses cycles or ends on a ray on 3
# of its top shifts and 2 of its bottom ones; in the rate form it solves them
# (docs/backends.md, "The rate form").
pack gravity-n200-w8-mu0.1 --protocol gravity --n 200 --width 8 --mu 0.1 --seed 2

# A hard case (2026-11-26), as tall as the 1600-disk piles and a quarter as wide, μ = 1,
# with today's defaults but for the time step and sweeps of the μ = 1 pile above. One of
# its grains (206) hangs by friction between two grains above its centre, so that every
# step from rest has a member in which it falls freely; Lemke's first path ends there on
# 16 of its 17 top shifts (docs/perturbations.md, "At μ = 1").
pack gravity-n400-w25-mu1 --protocol gravity --n 400 --width 25 --mu 1 --seed 1 --dt 0.005 --step-iter 2000

# A small pile: quick to load and solve (examples, smoke tests).
make gravity-n100-mu0.5 --protocol gravity --n 100 --width 15 --mu 0.5 --seed 1 "${pile_then[@]}" --step-iter 500
