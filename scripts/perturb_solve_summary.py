#!/usr/bin/env python3
"""One CSV row per `unjam perturb -o DIR` run: how many perturbations, how many
not-converged, which backend decided them, and the seconds per perturbation.

    scripts/perturb_solve_summary.py LABEL=DIR [LABEL=DIR ...] > bench/results/perturb-solve.csv

Reads DIR/records.jsonl (the records a run writes as it goes); the header line is skipped.
"""
import csv
import json
import statistics
import sys


def summarise(label, directory):
    records = []
    with open(f"{directory}/records.jsonl") as f:
        for line in f:
            d = json.loads(line)
            if "status" in d:
                records.append(d)
    if not records:
        sys.exit(f"{directory}/records.jsonl: no perturbation records")
    seconds = sorted(r["seconds"] for r in records)
    by = lambda name: sum(r["backend"] == name for r in records)
    return {
        "set": label,
        "perturbations": len(records),
        "not_converged": sum(r["status"] == "not-converged" for r in records),
        "ok": sum(r["status"] == "ok" for r in records),
        "dynamic": sum(r["status"] == "dynamic" for r in records),
        "nonlinear": sum(r["status"] == "nonlinear" for r in records),
        "by_static_lp": by("static LP"),
        "by_rate": by("rate"),
        "by_step_backend": len(records) - by("static LP") - by("rate"),
        "median_s": round(statistics.median(seconds), 4),
        "max_s": round(seconds[-1], 3),
    }


def main():
    if len(sys.argv) < 2 or any("=" not in a for a in sys.argv[1:]):
        sys.exit(__doc__)
    rows = [summarise(*a.split("=", 1)) for a in sys.argv[1:]]
    w = csv.DictWriter(sys.stdout, fieldnames=list(rows[0]))
    w.writeheader()
    w.writerows(rows)


if __name__ == "__main__":
    main()
