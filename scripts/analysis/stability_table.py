#!/usr/bin/env python3
"""The stability table of docs/stability.md from `unjam check ... -o DIR`'s DIR/stability.csv.

Usage: scripts/analysis/stability_table.py DIR/stability.csv [MORE.csv ...] > table.md
"""
import csv
import sys


def number(text):
    value = float(text)
    return "–" if value != value else f"{value:.1e}"


def why(row):
    """The first clause of a row's message, short enough for a table cell."""
    text = row["message"].replace("|", "/").split("; the solver")[0]
    text = text.replace("refused by the reader: ", "refused: ")
    return text if len(text) <= 70 else text[:67] + "..."


def main(paths):
    print("| case | backend | contacts | status | residual | Siconos error | equilibrium | steps | overlap growth | energy change | s | verdict | why |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    rows = [r for path in paths for r in csv.DictReader(open(path))]
    for r in rows:
        verdict = r["verdict"] if r["verdict"] != "FAILED" else "**FAILED**"
        print(f"| {r['case']} | {r['backend']} | {r['contacts']} | {r['status']} | {number(r['residual'])} | "
              f"{number(r['siconos_error'])} | {number(r['equilibrium'])} | {r['steps']} | {number(r['overlap_growth'])} | "
              f"{number(r['energy_change'])} | {float(r['seconds']):.3g} | {verdict} | {why(r)} |")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
