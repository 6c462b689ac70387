#!/usr/bin/python3
"""Contact openings against friction: one `unjam perturb -o DIR` run per packing, read
from each DIR's summary.json and perturbations.csv, written as a Markdown table (stdout)
and a figure (matplotlib): the fraction of openings that are quasi-static (`ok`), not
linear in ξ (`nonlinear`, runs with the small-gap check), dynamic or blocked,
⟨F_crit⟩/⟨F_cont⟩ over the `ok` ones, and ⟨δ⟩.

A DIR may be followed by `+RERUN.csv`: rows of `unjam perturb` runs (one per perturbation,
same packing, e.g. openings rerun one by one with `--contact K`) that replace the DIR's rows
of the same contact (i, j and periodic image). The averages are recomputed from the rows,
as `unjam perturb` computes them (quasi-static, not rattlers; the ratio's error by the
delta method, the two means being correlated).

Usage: scripts/analysis/perturb_vs_mu.py OUTPUT.png DIR[+RERUN.csv] [DIR[+RERUN.csv] ...]
"""
import csv
import json
import math
import os
import re
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt


def friction_of(packing_file):
    # summary.json names the packing as given on the command line, usually from the root.
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    path = packing_file if os.path.exists(packing_file) else os.path.join(root, packing_file)
    with open(path) as f:
        for line in f:
            if line.startswith("friction "):
                return float(line.split()[1])
    return 0.0


def contact_key(row):
    return (row["i"], row["j"], row["image_x"], row["image_y"])


def rows_with_reruns(d, rerun_csv):
    per = list(csv.DictReader(open(f"{d}/perturbations.csv")))
    if rerun_csv:
        reruns = {contact_key(r): r for r in csv.DictReader(open(rerun_csv))}
        keys = {contact_key(r) for r in per}
        missing = [k for k in reruns if k not in keys]
        if missing:
            sys.exit(f"{rerun_csv}: contacts not in {d}/perturbations.csv: {missing}")
        per = [reruns.get(contact_key(r), r) for r in per]
    return per


def quasi_static_means(per):
    """⟨F_crit⟩/⟨F_cont⟩ and ⟨δ⟩ with standard errors over quasi-static, non-rattler rows."""
    q = [r for r in per if r["status"] == "ok" and r["rattler"] == "0"]
    n = len(q)
    if n < 2:
        return None, None, None, None
    a = [float(r["f_crit"]) for r in q]
    b = [float(r["f_reference"]) for r in q]
    d = [float(r["penetration_depth"]) for r in q]
    ma, mb, md = sum(a) / n, sum(b) / n, sum(d) / n
    ratio = ma / mb
    var = lambda xs, m: sum((x - m) ** 2 for x in xs) / (n - 1)
    cov = sum((x - ma) * (y - mb) for x, y in zip(a, b)) / (n - 1)
    ratio_error = math.sqrt(max(var(a, ma) - 2 * ratio * cov + ratio ** 2 * var(b, mb), 0.0) / n) / mb
    return ratio, ratio_error, md, math.sqrt(var(d, md) / n)


def main():
    out_png, args = sys.argv[1], sys.argv[2:]
    rows = []
    for arg in args:
        d, _, rerun_csv = arg.partition("+")
        s = json.load(open(f"{d}/summary.json"))
        per = rows_with_reruns(d, rerun_csv)
        ratio, ratio_error, delta, delta_error = quasi_static_means(per)
        n = len(per)
        count = lambda status: sum(1 for p in per if p["status"] == status)
        rows.append({"packing": re.sub(r"\.unjam$", "", s["file"].split("/")[-1]), "mu": friction_of(s["file"]),
                     "n": n, "selection": s["selection"], "ok": count("ok"), "dynamic": count("dynamic"),
                     "nonlinear": count("nonlinear") if s.get("check_linearity") else None,
                     "blocked": count("blocked"), "not_converged": count("not-converged"),
                     "ratio": ratio, "ratio_error": ratio_error,
                     "delta": delta, "delta_error": delta_error, "backend": s["backend"]})
    rows.sort(key=lambda r: r["mu"])
    fmt = lambda x, e: "—" if x is None else f"{x:.3f} ± {e:.3f}"
    print("| packing | μ | openings | quasi-static | nonlinear in ξ | dynamic | blocked | not resolved | ⟨F_crit⟩/⟨F_cont⟩ (quasi-static) | ⟨δ⟩ (quasi-static) | backend |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        nonlinear = "not checked" if r["nonlinear"] is None else r["nonlinear"]
        print(f"| {r['packing']} | {r['mu']:g} | {r['n']} ({r['selection']}) | {r['ok']} | {nonlinear} | {r['dynamic']} | {r['blocked']} | "
              f"{r['not_converged']} | {fmt(r['ratio'], r['ratio_error'])} | {fmt(r['delta'], r['delta_error'])} | {r['backend']} |")

    # μ = 0 on a log axis: drawn at a tenth of the smallest positive μ and labelled.
    positive = [r["mu"] for r in rows if r["mu"] > 0]
    zero_at = min(positive) / 10 if positive else 1e-3
    x = [r["mu"] if r["mu"] > 0 else zero_at for r in rows]
    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(12, 3.6))
    for key, label, marker in (("ok", "quasi-static", "o"), ("nonlinear", "quasi-static, not linear in ξ", "D"),
                               ("dynamic", "dynamic", "x"), ("not_converged", "not resolved", "^"), ("blocked", "blocked", "s")):
        pts = [(xi, r[key] / r["n"]) for xi, r in zip(x, rows) if r[key] is not None]
        if pts:
            a1.plot([p[0] for p in pts], [p[1] for p in pts], marker + "-", label=label)
    # The LP's side (scripts/analysis/bounds_vs_mu.py): contacts that no static network lets open
    # without friction; an opening of such a contact cannot be quasi-static.
    lp_csv = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "bench", "results", "bounds-vs-mu.csv")
    if os.path.exists(lp_csv):
        lp = {r["packing"]: r for r in csv.DictReader(open(lp_csv))}
        pts = [(xi, int(lp[r["packing"]]["no_frictionless_equilibrium"]) / int(lp[r["packing"]]["contacts"]))
               for xi, r in zip(x, rows) if r["packing"] in lp]
        if pts:
            a1.plot([p[0] for p in pts], [p[1] for p in pts], "k--", lw=1, label="LP: cannot open without friction")
    a1.set_ylabel("fraction of openings"); a1.legend(fontsize=8)
    ok = [(xi, r) for xi, r in zip(x, rows) if r["ratio"] is not None]
    a2.errorbar([xi for xi, _ in ok], [r["ratio"] for _, r in ok], yerr=[r["ratio_error"] for _, r in ok], fmt="o-")
    a2.axhline(1.0, color="k", lw=0.8, ls="--")
    a2.set_ylabel("⟨F_crit⟩ / ⟨F_cont⟩ (quasi-static)")
    ok = [(xi, r) for xi, r in zip(x, rows) if r["delta"] is not None]
    a3.errorbar([xi for xi, _ in ok], [r["delta"] for _, r in ok], yerr=[r["delta_error"] for _, r in ok], fmt="o-")
    a3.set_ylabel("⟨δ⟩ (quasi-static)")
    for a in (a1, a2, a3):
        a.set_xscale("log"); a.set_xlabel("μ (μ = 0 drawn at the left end)")
    fig.tight_layout(); fig.savefig(out_png, dpi=110)
    print(f"\nwrote {out_png}", file=sys.stderr)


if __name__ == "__main__":
    main()
