#!/usr/bin/env bash
# `unjam pack`: a small pile settles, is static, and is reproduced bit for bit from its
# seed; re-solving the saved pile gives back its forces; checkpoints resume; a frictionless
# cell, given newton steps by default, jams exactly isostatic.
# Usage: cli_pack.sh UNJAM_BINARY SOURCE_DIR
source "$(dirname "$0")/harness.bash" "$@"

"$unjam" pack --protocol gravity --n 12 --width 8 --mu 0.5 --seed 3 -o "$work/a.unjam" --json --quiet >"$work/a.json" || fail "pack a: exit $?"
"$unjam" pack --protocol gravity --n 12 --width 8 --mu 0.5 --seed 3 -o "$work/b.unjam" --json --quiet >"$work/b.json" || fail "pack b: exit $?"
cmp -s <(grep -v '^provenance' "$work/a.unjam") <(grep -v '^provenance' "$work/b.unjam") || fail "same seed, different packings"
/usr/bin/python3 - "$work/a.json" <<'PY' || fail "pack --json"
import json, sys
d = json.load(open(sys.argv[1]))
for key in ("particles", "contacts", "packing_fraction", "coordination", "rattlers", "steps", "seconds"):
    assert key in d, key
assert d["jammed"] and d["static_solve"]["converged"], d
assert d["equilibrium_residual"] < 1e-8, d["equilibrium_residual"]
assert d["max_overlap"] < 1e-6, d["max_overlap"]
PY

# The defaults resolved and recorded: Δt = 0.02 T₀ (T₀ = 1 for a pile, 1/√P_ext for a cell),
# 1000 sweeps per step for a pile and 500 for a cell, sweeps by height for a pile and in a
# random order for a cell, and the loose step tolerance 1e-4, tightened as (0.02 T₀/Δt)²
# above the default step.
"$unjam" pack --protocol pressure --n 10 --pressure 4 --max-steps 1 --checkpoint-every 0 -o "$work/p4.unjam" --json --quiet >"$work/p4.json" 2>/dev/null
"$unjam" pack --protocol gravity --n 10 --width 8 --dt 0.04 --max-steps 1 --checkpoint-every 0 -o "$work/dt.unjam" --json --quiet >"$work/dt.json" 2>/dev/null
/usr/bin/python3 - "$work/a.json" "$work/p4.json" "$work/dt.json" <<'PY' || fail "the defaults of dt, step_iter and step_tol"
import json, sys
pile, cell, coarse = (json.load(open(f))["parameters"] for f in sys.argv[1:])
assert (pile["dt"], pile["step_iter"], pile["step_tol"], pile["order"]) == (0.02, 1000, 1e-4, "height"), pile
assert (cell["dt"], cell["step_iter"], cell["step_tol"]) == (0.01, 500, 1e-4), cell
assert "order" not in cell, cell  # random, the cells' default: absent as in files made before the option
assert coarse["dt"] == 0.04 and abs(coarse["step_tol"] - 2.5e-5) < 1e-18, coarse
PY

# Units: with Δt = 0.02 T₀ and T₀ = 1/√P_ext, a cell at P_ext = 4 or 1/4 is the cell at
# P_ext = 1 seen on another clock. Powers of two scale exactly in binary, so the positions
# must agree bit for bit and every force scale by P_ext exactly.
for p in 1 4 0.25; do
  "$unjam" pack --protocol pressure --n 30 --mu 0.5 --pressure $p --checkpoint-every 0 -o "$work/u$p.unjam" --json --quiet >/dev/null || fail "pack --pressure $p: exit $?"
done
/usr/bin/python3 - "$work/u1.unjam" "$work/u4.unjam" "$work/u0.25.unjam" <<'PY' || fail "the packing does not scale with P_ext"
import sys
def read(path):
    lines = [l for l in open(path).read().split("\n") if l and not l.startswith("#")]
    block = lambda key: (lambda i: [list(map(float, l.split())) for l in lines[i + 1:i + 1 + int(lines[i].split()[1])]])(
        next(i for i, l in enumerate(lines) if l.startswith(key + " ")))
    return next(l for l in lines if l.startswith("cell ")), block("particles"), block("forces")
(cell, disks, forces), *others = (read(p) for p in sys.argv[1:])
for (c, d, f), scale in zip(others, (4.0, 0.25)):
    assert c == cell and [x[:3] for x in d] == [x[:3] for x in disks], "positions differ"
    assert len(f) == len(forces) and all(g[4:6] == [scale * h[4], scale * h[5]] for g, h in zip(f, forces)), scale
PY

# The saved pile re-solved: static, its own forces, no iteration needed beyond the check.
"$unjam" solve "$work/a.unjam" --json --tol 1e-10 -o "$work/resolved.unjam" >"$work/solve.json" || fail "solve: exit $?"
/usr/bin/python3 - "$work/solve.json" "$work/a.unjam" "$work/resolved.unjam" <<'PY' || fail "re-solve changed the forces"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["converged"] and d["equilibrium_residual"] < 1e-8 and d["max_end_speed"] < 1e-9, d
def forces(path):
    lines = open(path).read().split("\n")
    start = next(i for i, l in enumerate(lines) if l.startswith("forces "))
    out = {}
    for l in lines[start + 1:]:
        if l == "end": break
        if l.startswith("#") or not l.strip(): continue
        f = l.split()
        out[tuple(f[:4])] = (float(f[4]), float(f[5]))
    return out
a, b = forces(sys.argv[2]), forces(sys.argv[3])
assert a.keys() == b.keys(), (len(a), len(b))
scale = sum(v[0] for v in a.values()) / len(a)
worst = max(max(abs(a[k][0] - b[k][0]), abs(a[k][1] - b[k][1])) for k in a) / scale
assert worst < 1e-8, worst
PY

# Checkpoints: a run stopped at --max-steps resumes from its checkpoint and ends bit for bit
# as an uninterrupted run; a checkpoint of other parameters is refused.
args=(pack --protocol gravity --n 12 --width 8 --seed 3 --quiet --checkpoint-every 10)
"$unjam" "${args[@]}" --mu 0.5 -o "$work/r.unjam" --max-steps 35 --json >"$work/r.json" 2>/dev/null; code=$?
[ "$code" -eq 3 ] || fail "--max-steps 35: exit $code, expected 3 (not static yet)"
# No static state, so no static forces: null, not zero contacts and every particle a rattler.
python3 - "$work/r.json" <<'PY' || fail "the JSON of a run not proven static"
import json, sys
d = json.load(open(sys.argv[1]))
assert not d["jammed"] and d["output"] is None and d["steps"] == 35, d
for key in ("contacts", "coordination", "rattlers", "pressure", "static_solve", "equilibrium_residual"):
    assert d[key] is None, (key, d[key])
assert d["packing_fraction"] > 0, d
PY
[ -e "$work/r.unjam.checkpoint" ] || fail "no checkpoint left by the interrupted run"
[ ! -e "$work/r.unjam" ] || fail "a packing not proven static was written"
"$unjam" "${args[@]}" --mu 0.5 -o "$work/r.unjam" >/dev/null 2>"$work/resume.err" || fail "resume: exit $?"
grep -q "resuming from" "$work/resume.err" || fail "the rerun did not say it resumed"
cmp -s "$work/a.unjam" "$work/r.unjam" || fail "resumed run differs from the uninterrupted one"
[ ! -e "$work/r.unjam.checkpoint" ] || fail "checkpoint left after a finished run"
"$unjam" "${args[@]}" --mu 0.6 -o "$work/m.unjam" --max-steps 15 >/dev/null 2>&1
"$unjam" "${args[@]}" --mu 0.5 -o "$work/m.unjam" >/dev/null 2>"$work/m.err"; code=$?
[ "$code" -eq 2 ] || fail "checkpoint with other parameters: exit $code, expected 2"
grep -q "mu 0.6" "$work/m.err" || fail "the error does not name the differing parameter: $(cat "$work/m.err")"

# The sweep order: other orders make other packings, but as static, as reproducible, and
# recorded with their parameters; `random` (the cells' default, and the piles' before
# height became theirs) is recorded by its absence, as in files made before the option;
# `--order height` is a pile's default spelled out; an unknown order is refused.
for order in local random; do
  for run in 1 2; do
    "$unjam" pack --protocol gravity --n 12 --width 8 --mu 0.5 --seed 3 --order $order -o "$work/$order$run.unjam" --json --quiet >"$work/$order$run.json" || fail "pack --order $order: exit $?"
  done
  cmp -s "$work/${order}1.unjam" "$work/${order}2.unjam" || fail "--order $order: same seed, different packings"
  /usr/bin/python3 - "$work/${order}1.json" "$order" "$work/${order}1.unjam" <<'PY' || fail "pack --order $order: summary or provenance"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["jammed"] and d["static_solve"]["converged"] and d["equilibrium_residual"] < 1e-8, d
provenance = next(l for l in open(sys.argv[3]) if l.startswith("provenance"))
if sys.argv[2] == "random":
    assert "order" not in d["parameters"] and "--order" not in provenance, (d["parameters"], provenance)
else:
    assert d["parameters"]["order"] == sys.argv[2] and "--order " + sys.argv[2] in provenance, (d["parameters"], provenance)
PY
done
"$unjam" pack --protocol gravity --n 12 --width 8 --mu 0.5 --seed 3 --order height -o "$work/height.unjam" --quiet >/dev/null || fail "pack --order height: exit $?"
cmp -s "$work/a.unjam" "$work/height.unjam" || fail "--order height is not the pile's default"
cmp -s <(grep -v '^provenance' "$work/a.unjam") <(grep -v '^provenance' "$work/random1.unjam") && fail "--order random made the same pile as height"
"$unjam" pack --protocol gravity --n 12 --order zigzag -o "$work/z.unjam" 2>"$work/err"; code=$?
[ "$code" -eq 2 ] || fail "--order zigzag: exit $code, expected 2"
grep -q -- "--order" "$work/err" || fail "the error does not name --order: $(cat "$work/err")"
[ ! -e "$work/z.unjam" ] || fail "--order zigzag left a file"

# Threads: recorded when not 1 (so that the provenance remakes the packing), one thread
# recorded by its absence; a negative count is refused, naming the option. (This pile is
# below the 1 000 contacts from which NSGS splits its sweeps: the threads' own arithmetic
# is tested in tests/solvers/nsgs_test.cpp.)
"$unjam" pack --protocol gravity --n 12 --width 8 --mu 0.5 --seed 3 --threads 2 -o "$work/t2.unjam" --quiet >/dev/null || fail "pack --threads 2: exit $?"
grep -q '^provenance.*--threads 2' "$work/t2.unjam" || fail "--threads 2 not in the provenance: $(grep provenance "$work/t2.unjam")"
grep -q '^provenance.*--threads' "$work/a.unjam" && fail "one thread recorded: $(grep provenance "$work/a.unjam")"
cmp -s <(grep -v '^provenance' "$work/a.unjam") <(grep -v '^provenance' "$work/t2.unjam") || fail "--threads 2 changed a pile below 1 000 contacts"
expect_code 2 "--threads -1" "$unjam" pack --protocol gravity --n 12 --threads -1 -o "$work/tn.unjam"
grep -q -- "--threads" "$work/err" || fail "the error does not name --threads: $(cat "$work/err")"

# The certificate's options: a wider closure gap and the LP fallback are recorded (the LP
# as a bare flag, so that the provenance line stays a command that remakes the packing),
# and the recorded command remakes the same pile; a closure gap out of range is refused.
"$unjam" pack --protocol gravity --n 12 --width 8 --mu 0.5 --seed 3 --closure-gap 1e-5 --certificate-lp -o "$work/lp.unjam" --json --quiet >"$work/lp.json" || fail "pack --certificate-lp: exit $?"
grep '^provenance' "$work/lp.unjam" | grep -q -- '--certificate-lp --' && grep -q '^provenance.*--closure-gap 1e-05 ' "$work/lp.unjam" || fail "certificate options not in the provenance: $(grep provenance "$work/lp.unjam")"
read -r -a remake <<<"$(sed -n 's/^provenance unjam \(.*\) (unjam .*/\1/p' "$work/lp.unjam")"
"$unjam" "${remake[@]}" -o "$work/lp2.unjam" --quiet || fail "the provenance command failed: ${remake[*]}"
cmp -s "$work/lp.unjam" "$work/lp2.unjam" || fail "the provenance command made another pile"
expect_code 2 "--closure-gap 0" "$unjam" pack --protocol gravity --n 12 --closure-gap 0 -o "$work/cg.unjam"
grep -q -- "--closure-gap" "$work/err" || fail "the error does not name --closure-gap: $(cat "$work/err")"
[ ! -e "$work/cg.unjam" ] || fail "--closure-gap 0 left a file"

# --backend auto: frictionless cells get newton steps at 1e-8 and jam exactly isostatic
# (N_c = 2(N' - 1) + 1 under a pressure bath); with friction the steps stay NSGS at 1e-4.
"$unjam" pack --protocol pressure --n 30 --mu 0 --seed 1 -o "$work/f.unjam" --json --quiet >"$work/f.json" || fail "pack --mu 0: exit $?"
/usr/bin/python3 - "$work/f.json" "$work/a.json" <<'PY' || fail "pack --backend auto"
import json, sys
d = json.load(open(sys.argv[1]))
p = d["parameters"]
assert p["backend"] == "newton" and p["step_tol"] == 1e-8, p
assert d["jammed"] and d["equilibrium_residual"] < 1e-8, d
assert d["contacts"] == 2 * (d["particles"] - d["rattlers"] - 1) + 1, d
p = json.load(open(sys.argv[2]))["parameters"]
assert "backend" not in p and p["step_tol"] == 1e-4, p
PY
grep -q '^provenance.*--backend newton.*--step-tol 1e-08' "$work/f.unjam" || fail "resolved backend not in the provenance: $(grep provenance "$work/f.unjam")"
# Nearly frictionless cells (mu <= 1e-4) get newton steps too, and jam like frictionless
# ones: every step starts from its frictionless solution (docs/backends.md).
"$unjam" pack --protocol pressure --n 30 --mu 1e-8 --seed 1 -o "$work/t.unjam" --json --quiet >"$work/t.json" || fail "pack --mu 1e-8: exit $?"
/usr/bin/python3 - "$work/t.json" <<'PY' || fail "pack --mu 1e-8 with --backend auto"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["parameters"]["backend"] == "newton" and d["parameters"]["step_tol"] == 1e-8, d["parameters"]
assert d["jammed"] and d["equilibrium_residual"] < 1e-8, d
PY

"$unjam" pack --protocol gravity --n 0 -o "$work/c.unjam" 2>"$work/err"; code=$?
[ "$code" -eq 2 ] || fail "--n 0: exit $code, expected 2"
[ ! -e "$work/c.unjam" ] || fail "--n 0 left a file"

# One run per checkpoint: while another process holds OUTPUT.checkpoint.lock, pack is
# refused (exit 1, naming the lock) and writes nothing.
hold_lock "$work/held.unjam.checkpoint.lock"
"$unjam" pack --protocol gravity --n 4 --width 8 -o "$work/held.unjam" --quiet >/dev/null 2>"$work/held.err"; code=$?
release_lock
[ "$code" -eq 1 ] && grep -q "held.unjam.checkpoint is being written by another run .*held.unjam.checkpoint.lock" "$work/held.err" || fail "pack on a locked checkpoint: exit $code, $(cat "$work/held.err")"
ls "$work" | grep -q "^held.unjam$\|^held.unjam.checkpoint$" && fail "pack on a locked checkpoint wrote: $(ls "$work")"

# A malformed checkpoint is an input error naming the file (exit 1), never ignored, and it
# stays as it was.
printf 'garbage\n' >"$work/bad.checkpoint"
"$unjam" pack --protocol pressure --n 10 --checkpoint "$work/bad.checkpoint" -o "$work/bad.unjam" >/dev/null 2>"$work/bad.err"; code=$?
[ "$code" -eq 1 ] && grep -q "bad.checkpoint: not a checkpoint" "$work/bad.err" || fail "malformed checkpoint: exit $code, $(head -c 300 "$work/bad.err")"
[ "$(cat "$work/bad.checkpoint")" = garbage ] || fail "malformed checkpoint was overwritten"
[ ! -e "$work/bad.unjam" ] || fail "malformed checkpoint: a packing was written"

finish cli_pack
