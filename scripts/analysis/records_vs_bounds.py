#!/usr/bin/python3
"""The finished shifts of a (possibly unfinished) `unjam perturb --top|--bottom -o DIR` run
beside their LP intervals from `unjam bounds --top|--bottom -o CSV` on the same pile.

Reads the run's records (DIR/records.jsonl, docs/format.md), which grow one line per
finished perturbation, so that a long ensemble (the 1600-disk piles: 15–60 minutes per
shift) can be looked at while it runs or after it was stopped; rerunning the same
`perturb` command resumes it. RECORDS may be the run folder itself (its records.jsonl),
e.g. out/ensembles/NAME of scripts/long-ensembles.sh.

Prints per status the count, ⟨F_crit⟩/⟨F_y⟩ over the quasi-static (`ok`) shifts with its
standard error (F_y the shifted particle's effective weight, the records' f_reference;
rattlers, bottom grains that need no force to lift, are left out as perturb leaves them
out of its averages),
and where each quasi-static F_crit sits in its LP interval ((F_crit − min)/(max − min);
inside means within 1e-6 of it, which covers F_crit's O(ξ) inertial part on these piles).
With a third argument, writes the joined rows as CSV.

Usage: scripts/analysis/records_vs_bounds.py RECORDS BOUNDS_CSV [JOINED_CSV]
"""
import csv
import json
import math
import os
import statistics
import sys
from collections import Counter


def records(path):
    # As perturb reads them (ReadRecords): whole lines only, so the text after the last
    # newline, a line torn by an interruption, is not a record; line 1 is the header.
    if os.path.isdir(path):
        path = os.path.join(path, "records.jsonl")
    text = open(path).read()
    lines = text.split("\n")[:-1]
    return [json.loads(line) for line in lines[1:]]


def standard_error(values):
    return statistics.stdev(values) / math.sqrt(len(values)) if len(values) > 1 else math.nan


def main(records_path, bounds_path, joined_path=None):
    bounds = {int(r["particle"]): r for r in csv.DictReader(open(bounds_path))}
    rows = []
    for rec in records(records_path):
        particle = rec["target"]["i"]
        b = bounds.get(particle)
        if b is None:
            sys.exit(f"{bounds_path}: no row for particle {particle} (another pile or side?)")
        # An empty bound is an unbounded LP (status_min/status_max say so).
        lo = float(b["min"]) if b["min"] else -math.inf
        hi = float(b["max"]) if b["max"] else math.inf
        # An unresolved step's F_crit is no answer (docs/perturbations.md): nan here.
        resolved = rec["f_crit"] is not None and rec["status"] != "not-converged"
        f = rec["f_crit"] if resolved else math.nan
        inside = lo - 1e-6 <= f <= hi + 1e-6 if math.isfinite(f) else False
        where = (f - lo) / (hi - lo) if hi > lo and math.isfinite(f) and math.isfinite(hi - lo) else math.nan
        rows.append({"index": rec["index"], "particle": particle, "status": rec["status"], "f_crit": f,
                     "fcrit_10xi": rec.get("fcrit_10xi"), "f_y": rec["f_reference"], "lp_min": lo, "lp_max": hi,
                     "rattler": bool(rec.get("rattler", False)), "inside": inside, "position": where, "delta": rec["penetration_depth"],
                     "iterations": rec["iterations"], "residual": rec["residual"], "seconds": rec["seconds"]})
    rows.sort(key=lambda r: r["index"])
    print(f"{len(rows)} shifts finished: " + ", ".join(f"{n} {s}" for s, n in sorted(Counter(r['status'] for r in rows).items())))
    ok = [r for r in rows if r["status"] == "ok"]
    used = [r for r in ok if not r["rattler"]]
    if used:
        m_f = statistics.mean(r["f_crit"] for r in used)
        m_y = statistics.mean(r["f_y"] for r in used)
        ratios = [r["f_crit"] / r["f_y"] for r in used]
        ratio, se = statistics.mean(ratios), standard_error(ratios)
        spread = f" ± {se:.2g}" if len(used) > 1 else " (one shift: no error)"
        rattlers = len(ok) - len(used)
        left_out = f" ({rattlers} rattler{'s' if rattlers > 1 else ''} left out)" if rattlers else ""
        print(f"ok: <F_crit>/<F_y> = {m_f / m_y:.3g}; per shift F_crit/F_y = {ratio:.3g}{spread}{left_out}")
    if ok:
        positions = [r["position"] for r in ok if math.isfinite(r["position"])]
        print(f"ok: {sum(r['inside'] for r in ok)} of {len(ok)} inside their LP interval, at "
              f"{min(positions):.3f}–{max(positions):.3f} of its width")
    for r in rows:
        print(f"  {r['particle']:5d} {r['status'] + (' rattler' if r['rattler'] else ''):14s} F_crit {r['f_crit']:.6g}  F_y {r['f_y']:.4g}  "
              f"LP [{r['lp_min']:.4g}, {r['lp_max']:.4g}] at {r['position']:.3f}  {r['iterations']} pivots  {r['seconds']:.0f} s")
    if joined_path:
        with open(joined_path, "w", newline="") as out:
            w = csv.DictWriter(out, fieldnames=list(rows[0].keys()) if rows else ["index"])
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    main(*sys.argv[1:])
