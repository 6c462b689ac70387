#!/usr/bin/env python3
"""The stability table of docs/stability.md from `unjam check ... -o DIR`'s DIR/stability.csv.

Usage: scripts/stability_table.py DIR/stability.csv > table.md
"""
import csv
import sys


def number(text):
    value = float(text)
    return "–" if value != value else f"{value:.1e}"


def main(path):
    print("| case | backend | contacts | status | residual | Siconos error | equilibrium | steps | overlap growth | energy change | s | verdict |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in csv.DictReader(open(path)):
        verdict = r["verdict"] if r["verdict"] != "FAILED" else "**FAILED**"
        print(f"| {r['case']} | {r['backend']} | {r['contacts']} | {r['status']} | {number(r['residual'])} | "
              f"{number(r['siconos_error'])} | {number(r['equilibrium'])} | {r['steps']} | {number(r['overlap_growth'])} | "
              f"{number(r['energy_change'])} | {float(r['seconds']):.3g} | {verdict} |")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
