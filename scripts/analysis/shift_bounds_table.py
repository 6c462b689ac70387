#!/usr/bin/python3
"""Markdown table of `unjam bounds --top/--bottom` CSVs (docs/indeterminacy.md, "Particle shifts").

Usage: scripts/analysis/shift_bounds_table.py CSV...   (one CSV per pile and side, named PILE-SIDE.csv)

Per CSV: shifts, bounded (min and max optimal), without upper / lower bound, and over the
bounded shifts the means with standard errors of F_y, of the stored network's F_crit, of the
LP min and max, and of max / F_y per shift. With a `perturbation_status` column
(`--compare-perturb`), also where each quasi-static F_crit sits in its interval
((F_crit - min) / (max - min), 0 = min, 1 = max).
"""
import csv
import math
import os
import sys


def mean_se(values):
    if not values:
        return "—"
    m = sum(values) / len(values)
    if len(values) < 2:
        return f"{m:.3g}"
    var = sum((v - m) ** 2 for v in values) / (len(values) - 1)
    return f"{m:.3g} ± {math.sqrt(var / len(values)):.2g}"


def row(path):
    rows = list(csv.DictReader(open(path)))
    bounded = [r for r in rows if r["status_min"] == "optimal" and r["status_max"] == "optimal"]
    no_upper = sum(r["status_max"] == "unbounded" for r in rows)
    no_lower = sum(r["status_min"] == "unbounded" for r in rows)
    col = lambda name: [float(r[name]) for r in bounded]
    ratio = [float(r["max"]) / float(r["f_y"]) for r in bounded if float(r["f_y"]) > 0]
    where = []
    if rows and "perturbation_status" in rows[0]:
        for r in bounded:
            if r["f_crit"] and float(r["max"]) > float(r["min"]):
                where.append((float(r["f_crit"]) - float(r["min"])) / (float(r["max"]) - float(r["min"])))
    name = os.path.basename(path).removesuffix(".csv")
    cells = [name, str(len(rows)), str(len(bounded)), str(no_upper), str(no_lower), mean_se(col("f_y")),
             mean_se(col("f_static")), mean_se(col("min")), mean_se(col("max")), mean_se(ratio),
             mean_se(where) + (f" ({len(where)})" if where else "")]
    return "| " + " | ".join(cells) + " |"


print("| pile, side | shifts | bounded | no upper bound | no lower bound | ⟨F_y⟩ | ⟨F_crit of the stored network⟩ "
      "| ⟨LP min⟩ | ⟨LP max⟩ | ⟨max / F_y⟩ | quasi-static F_crit in the interval (count) |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for path in sys.argv[1:]:
    print(row(path))
