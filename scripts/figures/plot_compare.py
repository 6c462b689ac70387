#!/usr/bin/python3
"""Figures of an `unjam compare -o DIR` run (matplotlib):
  DIR/work-precision.png   residual reached against wall time, log-log, one panel per
                           problem, one curve per backend (a point per requested tolerance;
                           hollow markers: the backend did not reach that tolerance);
  DIR/profiles.png         Dolan–Moré performance profiles, one panel per tolerance: for
                           each backend the fraction of problems solved within a factor τ of
                           the fastest backend's time (a problem not converged costs ∞).
Usage: scripts/figures/plot_compare.py DIR   (reads DIR/compare.csv)
"""
import csv, math, sys
from collections import defaultdict

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

run = sys.argv[1]
everything = list(csv.DictReader(open(f"{run}/compare.csv")))
# A backend that refuses a problem's form (status unsupported) has no curve there; in the
# profiles it counts as not solving the problem.
rows = [r for r in everything if r["status"] != "unsupported"]
if not rows:
    raise SystemExit(f"{run}/compare.csv: no rows")
problems = list(dict.fromkeys(r["problem"] for r in rows))
backends = list(dict.fromkeys(r["backend"] for r in rows))
tolerances = sorted({float(r["tolerance"]) for r in rows}, reverse=True)
colours = {b: plt.cm.tab10(i) for i, b in enumerate(backends)}
markers = dict(zip(backends, "osD^vP*X"))

# 1. Work-precision.
cols = min(3, len(problems)); lines = math.ceil(len(problems) / cols)
fig, axes = plt.subplots(lines, cols, figsize=(4.6 * cols, 3.8 * lines), squeeze=False)
for ax, problem in zip(axes.flat, problems):
    for b in backends:
        pts = sorted((float(r["seconds"]), float(r["residual"]), r["converged"] == "true")
                     for r in rows if r["problem"] == problem and r["backend"] == b)
        pts = [p for p in pts if p[1] > 0 and p[0] > 0]
        if not pts:
            continue
        t = [p[0] for p in pts]; e = [p[1] for p in pts]
        ax.plot(t, e, "-", color=colours[b], lw=1, alpha=0.7)
        for ti, ei, ok in pts:
            ax.plot(ti, ei, markers[b], color=colours[b], mfc=colours[b] if ok else "none", ms=6)
        ax.plot([], [], markers[b] + "-", color=colours[b], label=b)
    ax.set_xscale("log"); ax.set_yscale("log")
    ax.set_xlabel("wall time (s)"); ax.set_ylabel("unjam residual reached")
    ax.set_title(problem, fontsize=9); ax.grid(True, which="major", alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8)
for ax in list(axes.flat)[len(problems):]:
    ax.axis("off")
fig.suptitle("work-precision (hollow: tolerance not reached)", fontsize=10)
fig.tight_layout(); fig.savefig(f"{run}/work-precision.png", dpi=110)

# 2. Dolan–Moré performance profiles, one panel per tolerance.
fig, axes = plt.subplots(1, len(tolerances), figsize=(4.2 * len(tolerances), 3.6), squeeze=False)
for ax, tol in zip(axes.flat, tolerances):
    cost = defaultdict(dict)
    for r in everything:
        if float(r["tolerance"]) == tol:
            # A one-contact solve can take less than the clock resolves: count it as 1 ns, so
            # that the ratios stay defined (they were a division by zero).
            cost[r["problem"]][r["backend"]] = max(float(r["seconds"]), 1e-9) if r["converged"] == "true" else math.inf
    ratios = {b: [] for b in backends}
    for problem, by_backend in cost.items():
        best = min(by_backend.values())
        for b in backends:
            c = by_backend.get(b, math.inf)
            ratios[b].append(c / best if math.isfinite(best) and math.isfinite(c) else math.inf)
    finite = [x for v in ratios.values() for x in v if math.isfinite(x)]
    top = max(2.0, 1.2 * max(finite)) if finite else 2.0
    taus = np.logspace(0, math.log10(top), 200)
    for b in backends:
        rb = np.array(ratios[b])
        ax.step(taus, [(rb <= t).mean() for t in taus], where="post", color=colours[b], label=b)
    ax.set_xscale("log"); ax.set_ylim(-0.02, 1.02)
    ax.set_xlabel("τ (time / fastest time)"); ax.set_ylabel("fraction of problems")
    ax.set_title(f"tolerance {tol:g} ({len(cost)} problems)", fontsize=9); ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
fig.suptitle("Dolan–Moré performance profiles", fontsize=10)
fig.tight_layout(); fig.savefig(f"{run}/profiles.png", dpi=110)
print("wrote", f"{run}/work-precision.png", f"{run}/profiles.png")
