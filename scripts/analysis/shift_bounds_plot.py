#!/usr/bin/python3
"""Figure of `unjam bounds --top/--bottom` CSVs (docs/indeterminacy.md, "Particle shifts").

Usage: scripts/analysis/shift_bounds_plot.py OUT.png CSV...   (CSVs named PILE-SIDE[-...].csv)

One panel per side (top, bottom): per shift, its LP interval [min, max] of F_crit as a
vertical bar against its effective weight F_y (an unbounded min is drawn from the panel's
bottom edge), and where the CSV has them (`--compare-perturb`) the quasi-static F_crit that
`perturb` found, as dots. The line F_crit = F_y is for scale.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def load(path):
    name = os.path.basename(path).removesuffix(".csv")
    side = "top" if "-top" in name else "bottom"
    pile = name.split("-" + side)[0]
    return pile, side, list(csv.DictReader(open(path)))


def number(text):
    return float(text) if text not in ("", None) else math.nan


def main():
    out, paths = sys.argv[1], sys.argv[2:]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    panels = {"top": axes[0], "bottom": axes[1]}
    colours = {}
    for path in paths:
        pile, side, rows = load(path)
        colour = colours.setdefault(pile, f"C{len(colours)}")
        ax = panels[side]
        shift = 0.015 * (list(colours).index(pile) - 0.5)  # keep the piles' bars apart
        first = True
        for r in rows:
            fy, lo, hi = number(r["f_y"]), number(r["min"]), number(r["max"])
            if math.isnan(hi) or fy <= 0:
                continue
            x = fy * (1 + shift)
            bottom = lo if not math.isnan(lo) and lo > 0 else None
            ax.vlines(x, bottom if bottom else 1e-2, hi, colors=colour, alpha=0.5, lw=1.5,
                      label=f"{pile}: LP interval" if first else None)
            first = False
            f = number(r.get("f_crit"))
            if not math.isnan(f) and f > 0:
                ax.plot(x, f, "o", color=colour, ms=4)
    for side, ax in panels.items():
        ax.set_xscale("log")
        ax.set_yscale("log")
        lo, hi = ax.get_xlim()
        ax.plot([lo, hi], [lo, hi], "k--", lw=0.8, label="F_crit = F_y")
        ax.set_xlim(lo, hi)
        ax.set_ylim(bottom=1e-2)
        ax.set_xlabel("effective weight F_y")
        ax.set_ylabel("F_crit: LP interval (bars), perturb (dots)")
        ax.set_title(f"{side} shifts ({'pushed down' if side == 'top' else 'pushed up'})")
        ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(out, dpi=120)


if __name__ == "__main__":
    main()
