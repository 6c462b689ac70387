#!/usr/bin/python3
"""The displacement field of one perturbation (matplotlib): every disk drawn to scale, an
arrow per particle along its displacement d_i, coloured by log10(|d_i| / xi), the perturbed
contact marked with its normal.
Usage: scripts/figures/plot_displacement.py DISPLACEMENT_CSV OUTPUT_PNG --gap XI
           [--origin X Y --normal NX NY] [--title TEXT]
DISPLACEMENT_CSV is the displacement.csv of `unjam perturb -o DIR` (or of the main job).
"""
import argparse, csv

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.collections import PatchCollection
from matplotlib.patches import Circle
import numpy as np

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("csv"); ap.add_argument("png")
ap.add_argument("--gap", type=float, required=True, help="the perturbation size xi")
ap.add_argument("--origin", type=float, nargs=2); ap.add_argument("--normal", type=float, nargs=2)
ap.add_argument("--title", default="")
a = ap.parse_args()

rows = list(csv.DictReader(open(a.csv)))
if not rows:
    raise SystemExit(f"{a.csv}: no particles")
x, y, rad, dx, dy = (np.array([float(r[k]) for r in rows]) for k in ("x", "y", "radius", "dx", "dy"))
mag = np.hypot(dx, dy) / a.gap
moving = mag > 0

fig, ax = plt.subplots(figsize=(7.5, 7))
ax.add_collection(PatchCollection([Circle((xi, yi), ri) for xi, yi, ri in zip(x, y, rad)],
                                  facecolor="0.93", edgecolor="0.6", linewidth=0.3))
unit = np.maximum(np.hypot(dx, dy), 1e-300)
q = ax.quiver(x[moving], y[moving], (dx / unit)[moving], (dy / unit)[moving], np.log10(mag[moving]),
              cmap="viridis", scale=45, width=0.0035)
fig.colorbar(q, ax=ax, shrink=0.8, label="log$_{10}$ |d$_i$| / ξ")
if a.origin:
    ax.plot(*a.origin, "o", color="red", ms=6, label="opened contact")
    if a.normal:
        n = np.array(a.normal)
        p = np.array(a.origin)
        ax.plot(*np.transpose([p - 1.5 * n, p + 1.5 * n]), "-", color="red", lw=1.2)
    ax.legend(loc="upper right", fontsize=8)
ax.set_xlim(x.min() - 1, x.max() + 1); ax.set_ylim(y.min() - 1, y.max() + 1)
ax.set_aspect("equal"); ax.set_xlabel("x"); ax.set_ylabel("y")
ax.set_title(a.title or "displacement field (direction; colour: magnitude over ξ)", fontsize=10)
fig.tight_layout(); fig.savefig(a.png, dpi=110)
print("wrote", a.png)
