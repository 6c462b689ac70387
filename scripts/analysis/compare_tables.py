#!/usr/bin/env python3
"""The tables of docs/accuracy-vs-time.md from the CSV of `unjam compare -o DIR`.

    scripts/analysis/compare_tables.py DIR/compare.csv

Prints two markdown tables, seconds per run by backend: the static solves from cold (at
1e-4, 1e-8 and 1e-12) and the openings (at 1e-8, 1e-10 and 1e-12). The fastest run that
reached the tolerance is bold; `!` marks a run that missed it, with the residual it reached
and its seconds in brackets.
"""
import csv
import sys

BACKENDS = ["nsgs", "newton", "ipopt", "nlopt"]
STATIC_TOLS = ["0.0001", "1e-08", "1e-12"]
OPENING_TOLS = ["1e-08", "1e-10", "1e-12"]


def cell(row):
    if row is None:
        return "–"
    seconds = float(row["seconds"])
    if row["converged"] == "true":
        return f"{seconds:.2f}"
    return f"! {float(row['residual']):.1e} ({seconds:.2f})"


def table(rows, problems, tols):
    lines = ["| problem | tolerance | " + " | ".join(BACKENDS) + " |",
             "|---|---|" + "---|" * len(BACKENDS)]
    for problem in problems:
        for n, tol in enumerate(tols):
            runs = {b: rows.get((problem, b, tol)) for b in BACKENDS}
            reached = [float(r["seconds"]) for r in runs.values()
                       if r is not None and r["converged"] == "true"]
            best = min(reached) if reached else None
            cells = []
            for b in BACKENDS:
                text = cell(runs[b])
                r = runs[b]
                if r is not None and r["converged"] == "true" and float(r["seconds"]) == best:
                    text = f"**{text}**"
                cells.append(text)
            name = problem if n == 0 else ""
            lines.append(f"| {name} | {float(tol):.0e} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    with open(sys.argv[1], newline="") as f:
        data = list(csv.DictReader(f))
    rows = {(r["problem"], r["backend"], r["tolerance"]): r for r in data}
    problems = list(dict.fromkeys(r["problem"] for r in data))
    static = [p for p in problems if p.endswith(" static")]
    openings = [p for p in problems if " opening " in p]
    print("Static forces from cold (seconds):\n")
    print(table(rows, static, STATIC_TOLS))
    print("\nContact openings (seconds per opening):\n")
    print(table(rows, openings, OPENING_TOLS))


if __name__ == "__main__":
    main()
