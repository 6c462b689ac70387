#!/usr/bin/env python3
"""One CSV row per `unjam perturb -o DIR` run: how many perturbations, how many
not-converged, which backend decided them, and the seconds per perturbation.

    scripts/analysis/perturb_solve_summary.py LABEL=DIR [LABEL=DIR ...] > bench/results/perturb-solve.csv

With --path-ends DIR: a Markdown table of how the rate path ended (the `rate path:` account
in each record's message) against the perturbation's final status and who decided it.

    scripts/analysis/perturb_solve_summary.py --path-ends DIR

Reads DIR/records.jsonl (the records a run writes as it goes); the header line is skipped.
"""
import collections
import csv
import json
import re
import statistics
import sys


def read_records(directory):
    records = []
    with open(f"{directory}/records.jsonl") as f:
        for line in f:
            d = json.loads(line)
            if "status" in d:
                records.append(d)
    if not records:
        sys.exit(f"{directory}/records.jsonl: no perturbation records")
    return records


PATH_END = re.compile(r"rate path: ([a-z-]+) after \d+ events, (\d+) turns(, at zero load)?")


def path_end(record):
    """The path's end as the table groups it, or None where no path ran (the static LP)."""
    m = PATH_END.search(json.dumps(record))
    if m is None:
        return None
    end, turns = m.group(1), int(m.group(2))
    if end == "collapse":
        return "collapse after folds (t turns back)" if turns > 0 else "collapse, no fold"
    if end == "cycle" and m.group(3):
        return "loop at zero load (cycle, t = 0 but at first order)"
    if end in ("cycle", "back"):
        return "back to the start (cycle or t ≤ 0)"
    return end


def path_ends(directory):
    counts = collections.defaultdict(collections.Counter)
    for r in read_records(directory):
        end = path_end(r)
        if end is not None:
            who = "rate" if r["backend"] == "rate" else r["backend"]
            counts[end][f'{r["status"]} ({who})'] += 1
    print("| path end | perturbations | final status (who decided) |")
    print("|---|---|---|")
    for end, by in sorted(counts.items(), key=lambda kv: -sum(kv[1].values())):
        cells = " / ".join(f"{n} {what}" for what, n in by.most_common())
        print(f"| {end} | {sum(by.values())} | {cells} |")


def summarise(label, directory):
    records = read_records(directory)
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
    if len(sys.argv) == 3 and sys.argv[1] == "--path-ends":
        path_ends(sys.argv[2])
        return
    if len(sys.argv) < 2 or any("=" not in a for a in sys.argv[1:]):
        sys.exit(__doc__)
    rows = [summarise(*a.split("=", 1)) for a in sys.argv[1:]]
    w = csv.DictWriter(sys.stdout, fieldnames=list(rows[0]))
    w.writeheader()
    w.writerows(rows)


if __name__ == "__main__":
    main()
