#!/usr/bin/env bash
# Time to a jammed packing vs N, at constant pressure, for μ = 0.1 and μ = 1 (issue 3's
# measure). Long: hours on one core at N = 8000. Sizes in the outer loop, so that an
# interrupted run has both μ up to some N. Results are appended to
# bench/results/packing-vs-n.csv as they come (a rerun skips rows already there), and the
# growth exponent of the cost is fitted at the end. STEP_ITER (default 500) caps the NSGS
# sweeps per dynamics step; large frictional cells need 2000 (docs/performance.md).
# REFINE_ITER (default 30000, unjam's) caps the static solve that refines a failed
# certificate's forces; the rows measured before that existed have 0. Each run checkpoints
# into bench/results/work/ (git-ignored), so an interrupted run resumes there. ORDER=local
# runs `unjam pack --order local` (cheaper sweeps on large cells) into
# bench/results/packing-vs-n-local.csv instead.
# MUS (default "0.1 1") lists the friction coefficients. DT (default 0.02, unjam's) is the
# time step; rows at another DT go to their own file, packing-vs-n-dtDT.csv (the rows of
# packing-vs-n.csv and packing-vs-n-local.csv were measured at 0.01, the default before
# 2026-11-25). MAX_STEPS (default unjam's) gives up on a run that creeps. LP=1 adds
# `--certificate-lp --closure-gap 1e-4` (what certifies the creeping N = 4000, mu = 1 cell)
# and writes to a file of its own, packing-vs-n...-lp.csv. THREADS (default 1) runs
# `unjam pack --threads THREADS` (NSGS on several threads; another packing per count) into
# packing-vs-n...-tTHREADS.csv.
# Usage: [STEP_ITER=2000] [REFINE_ITER=N] [ORDER=local] [MUS="0.1"] [DT=0.01] [MAX_STEPS=N]
#        [LP=1] [THREADS=2] scripts/bench-packing.sh [BUILD_DIR] [N ...]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
unjam="${1:-$root/build}/unjam"
shift || true
[ $# -gt 0 ] && sizes=("$@") || sizes=(500 1000 2000 4000 8000)
order="${ORDER:-random}"
dt="${DT:-0.02}"
suffix=""
[ "$order" = random ] || suffix="-$order"
[ "$dt" = 0.01 ] || suffix="$suffix-dt$dt"
certificate=()
[ "${LP:-0}" = 1 ] && { certificate=(--certificate-lp --closure-gap 1e-4); suffix="$suffix-lp"; }
threads="${THREADS:-1}"
[ "$threads" = 1 ] || suffix="$suffix-t$threads"
out="$root/bench/results/packing-vs-n$suffix.csv"
mkdir -p "$(dirname "$out")"
[ -e "$out" ] || echo "n,mu,seconds,steps,static_checks,packing_fraction,coordination,jammed,step_iter,refine_iter" >"$out"
step_iter="${STEP_ITER:-500}"
refine_iter="${REFINE_ITER:-30000}"
work="$root/bench/results/work"
mkdir -p "$work"
for n in "${sizes[@]}"; do
  for mu in ${MUS:-0.1 1}; do
    grep -q "^$n,$mu," "$out" && continue
    run="$work/n$n-mu$mu-s$step_iter-r$refine_iter$suffix"
    "$unjam" pack --protocol pressure --n "$n" --mu "$mu" --seed 1 --step-iter "$step_iter" --dt "$dt" \
      --refine-iter "$refine_iter" --order "$order" --max-steps "${MAX_STEPS:-1000000}" "${certificate[@]}" --threads "$threads" \
      -o "$run.unjam" --json --quiet >"$run.json" || true
    /usr/bin/python3 - "$run.json" "$n" "$mu" "$step_iter" "$refine_iter" >>"$out" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
z = "nan" if d["coordination"] is None else f"{d['coordination']:.4f}"  # null: not certified
print(f"{sys.argv[2]},{sys.argv[3]},{d['seconds']:.2f},{d['steps']},{d['static_checks']},"
      f"{d['packing_fraction']:.5f},{z},{str(d['jammed']).lower()},{sys.argv[4]},{sys.argv[5]}")
PY
    tail -n 1 "$out"
  done
done
/usr/bin/python3 - "$out" <<'PY'
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for mu in sorted({r["mu"] for r in rows}):
    pts = [(math.log(int(r["n"])), math.log(float(r["seconds"]))) for r in rows if r["mu"] == mu and r["jammed"] == "true"]
    if len(pts) < 2:
        continue
    mx = sum(x for x, _ in pts) / len(pts); my = sum(y for _, y in pts) / len(pts)
    slope = sum((x - mx) * (y - my) for x, y in pts) / sum((x - mx) ** 2 for x, _ in pts)
    print(f"mu = {mu}: cost grows like N^{slope:.2f} over {len(pts)} sizes")
PY
