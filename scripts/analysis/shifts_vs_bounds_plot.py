#!/usr/bin/python3
"""F_crit of each shift of a pile, from one or more `unjam perturb --top|--bottom -o DIR`
runs (their DIR/perturbations.csv), against the shift's LP interval from `unjam bounds
--top|--bottom -o CSV` (matplotlib). One column per shifted particle, in the order of x;
the interval is a bar (an arrow where it is unbounded), each run's F_crit a marker:
filled where the response is quasi-static and linear (`ok`), hollow where it is
`dynamic`, `nonlinear` or unresolved.

Usage: scripts/analysis/shifts_vs_bounds_plot.py [--floor=Y] BOUNDS_CSV OUT.png TITLE LABEL=PERTURBATIONS_CSV...
  --floor=Y  cut the axis at Y: an interval that reaches below it is drawn to it with an
             arrow, as an unbounded one (on the 1600-disk pile two bottom shifts' intervals
             reach −7 000 while every F_crit is above −1)
"""
import csv
import math
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt


def number(text):
    return float(text) if text not in ("", "nan", "-nan") else math.nan


def main(bounds_path, out_path, title, *runs, cut=None):
    bounds = sorted(csv.DictReader(open(bounds_path)), key=lambda b: number(b["x"]))
    column = {int(b["particle"]): k for k, b in enumerate(bounds)}
    lows = [number(b["min"]) for b in bounds]
    if cut is not None:
        lows = [lo if lo >= cut else -math.inf for lo in lows]
    highs = [number(b["max"]) for b in bounds]
    finite = [v for v in lows + highs if math.isfinite(v)]
    span = max(finite) - min(finite) if finite else 1.0
    floor, ceiling = min(finite) - 0.1 * span, max(finite) + 0.1 * span
    if cut is not None:
        floor = min(floor, cut)
    fig, ax = plt.subplots(figsize=(max(6.0, 0.45 * len(bounds)), 4.6))
    for k, (lo, hi) in enumerate(zip(lows, highs)):
        bottom = lo if math.isfinite(lo) else floor
        top = hi if math.isfinite(hi) else ceiling
        ax.plot([k, k], [bottom, top], color="0.75", lw=6, solid_capstyle="butt", zorder=1)
        if not math.isfinite(lo):
            ax.annotate("", xy=(k, floor), xytext=(k, floor + 0.05 * span), arrowprops={"arrowstyle": "->", "color": "0.6"})
    markers = "os^Dv"
    for n, run in enumerate(runs):
        label, path = run.split("=", 1)
        xs_ok, ys_ok, xs_other, ys_other = [], [], [], []
        for row in csv.DictReader(open(path)):
            k, f = column.get(int(row["i"])), number(row["f_crit"])
            if k is None or not math.isfinite(f):
                continue
            offset = (n - (len(runs) - 1) / 2) * 0.2
            (xs_ok if row["status"] == "ok" else xs_other).append(k + offset)
            (ys_ok if row["status"] == "ok" else ys_other).append(f)
        color = f"C{n}"
        ax.plot(xs_ok, ys_ok, markers[n % len(markers)], color=color, ms=6, zorder=3,
                label=f"{label}: {len(xs_ok)} ok")
        ax.plot(xs_other, ys_other, markers[n % len(markers)], mfc="none", color=color, ms=6, zorder=3,
                label=f"{label}: {len(xs_other)} dynamic, nonlinear or unresolved")
    ax.set_xticks(range(len(bounds)))
    ax.set_xticklabels([b["particle"] for b in bounds], rotation=90, fontsize=7)
    ax.set_xlabel("shifted particle (in the order of x)")
    ax.set_ylabel("F_crit (grey: LP interval)")
    ax.set_ylim(floor, ceiling)
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.3), ncol=2)
    fig.tight_layout()
    fig.savefig(out_path, dpi=120)


if __name__ == "__main__":
    args = sys.argv[1:]
    cut = None
    if args and args[0].startswith("--floor="):
        cut = float(args.pop(0).split("=", 1)[1])
    if len(args) < 4:
        sys.exit(__doc__)
    main(*args, cut=cut)
