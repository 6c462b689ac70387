#!/usr/bin/python3
"""Seconds per perturbation against N (matplotlib), from `unjam perturb -o DIR` runs of
packings of several sizes: one point per perturbation, coloured by who decided it (the
static LP, the rate path, the step backend) and hollow where it ended `not-converged`; the
median per N; a line ∝ N^1.5 through the smallest N's median; the target (2 s at N = 3000).

    scripts/analysis/perturb_vs_n_plot.py OUT.png N=DIR [N=DIR ...]

Reads DIR/records.jsonl; N is the number of grains of that run's packing.
"""
import json
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def records(directory):
    out = []
    with open(f"{directory}/records.jsonl") as f:
        for line in f:
            d = json.loads(line)
            if "status" in d:
                out.append(d)
    if not out:
        sys.exit(f"{directory}/records.jsonl: no perturbation records")
    return out


def decider(record):
    if record["backend"] in ("static LP", "rate"):
        return record["backend"]
    return "step backend"


def main():
    if len(sys.argv) < 3 or any("=" not in a for a in sys.argv[2:]):
        sys.exit(__doc__)
    runs = sorted((int(n), records(d)) for n, d in (a.split("=", 1) for a in sys.argv[2:]))
    colours = {"static LP": "tab:blue", "rate": "tab:green", "step backend": "tab:red"}
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    seen = set()
    for k, (n, recs) in enumerate(runs):
        for i, r in enumerate(recs):
            who = decider(r)
            failed = r["status"] == "not-converged"
            x = n * (1.0 + 0.06 * ((i % 7) - 3) / 3)  # spread the points of one N
            label = None
            if (who, failed) not in seen:
                seen.add((who, failed))
                label = who + (" (not-converged)" if failed else "")
            ax.scatter(x, max(r["seconds"], 1e-4), s=14, label=label,
                       facecolors="none" if failed else colours[who],
                       edgecolors=colours[who], linewidths=0.8)
    ns = [n for n, _ in runs]
    medians = [statistics.median(r["seconds"] for r in recs) for _, recs in runs]
    ax.plot(ns, medians, "k-o", ms=4, label="median")
    guide = [medians[0] * (n / ns[0]) ** 1.5 for n in ns]
    ax.plot(ns, guide, "k:", label="∝ N^1.5 (target growth)")
    ax.scatter([3000], [2.0], marker="*", s=90, color="gold", edgecolors="k", zorder=5,
               label="target median at N = 3000")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("N (grains)")
    ax.set_ylabel("seconds per perturbation (one core)")
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(sys.argv[1], dpi=130)


if __name__ == "__main__":
    main()
