#!/usr/bin/env python3
"""Figures of a friction study (`unjam study`, docs/friction-study.md).

Usage: plot_study.py OUTPUT_DIR

Reads OUTPUT_DIR/summary-pressure.csv, summary-gravity.csv and runs.csv (and each run's
perturbations.csv, profile.csv, field.csv and stress.csv) and writes PNGs to
OUTPUT_DIR/figures/. Every figure comes from those files: nothing is typed in by hand.
Python 3 with matplotlib and numpy; called by `unjam study` when the build found them.
"""

import csv
import math
import os
import sys
import warnings
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_csv(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(row, key):
    try:
        value = float(row.get(key, "") or "nan")
    except ValueError:
        return math.nan
    return value


def mu_axis(ax, mus):
    """Friction on a log axis; μ = 0 drawn at a decade below the smallest positive μ."""
    ax.set_xscale("log")
    ax.set_xlabel("μ")
    positive = [m for m in mus if m > 0]
    return (min(positive) / 10 if positive else 1e-9)


def x_of(mu, zero_at):
    return mu if mu > 0 else zero_at


def errorbars(ax, rows, key, label, zero_at, **style):
    xs = [x_of(num(r, "mu"), zero_at) for r in rows]
    ys = [num(r, key) for r in rows]
    es = [num(r, key + "_error") for r in rows]
    es = [e if math.isfinite(e) else 0.0 for e in es]
    ax.errorbar(xs, ys, yerr=es, marker="o", capsize=3, label=label, **style)


def groups(rows, *keys):
    out = defaultdict(list)
    for r in rows:
        out[tuple(r[k] for k in keys)].append(r)
    for g in out.values():
        g.sort(key=lambda r: num(r, "mu"))
    return out


def save(fig, out, name, dpi=120):
    fig.tight_layout()
    fig.savefig(os.path.join(out, name), dpi=dpi)
    plt.close(fig)


def pressure_vs_mu(rows, out):
    for (n, mode), g in groups(rows, "n", "kind").items():
        zero_at = None
        fig, axes = plt.subplots(2, 4, figsize=(16, 7))
        panels = [
            ("z", [("z", "without rattlers"), ("z_with_rattlers", "with rattlers")], "z"),
            ("φ", [("packing_fraction", "φ")], "φ"),
            ("⟨F_cont⟩", [("mean_contact_force", "all contacts")], "⟨F⟩"),
            ("⟨δ⟩", [("delta", "ok openings")], "⟨δ⟩"),
            ("α", [("alpha", "averaged field")], "α"),
            ("⟨F_crit⟩ ratios", [("ratio_fcrit_freference", "ok / own F_cont"),
                                 ("ratio_fcrit_fcont_all", "ok / all contacts"),
                                 ("ratio_any_fcont_all", "any step force / all")], "ratio"),
            ("LP interval / ⟨F⟩", [("lp_position", "(F_crit − min)/(max − min)")], "position"),
        ]
        for ax, (title, series, ylabel) in zip(axes.flat, panels):
            zero_at = mu_axis(ax, [num(r, "mu") for r in g])
            for key, label in series:
                errorbars(ax, g, key, label, zero_at)
            ax.set_title(title)
            ax.set_ylabel(ylabel)
            if len(series) > 1:
                ax.legend(fontsize=8)
        ax = axes.flat[7]
        zero_at = mu_axis(ax, [num(r, "mu") for r in g])
        xs = [x_of(num(r, "mu"), zero_at) for r in g]
        ax.plot(xs, [num(r, "dynamic_share") for r in g], "o-")
        ax.set_title("share of dynamic openings")
        ax.set_ylim(-0.05, 1.05)
        fig.suptitle(f"N = {n}, {mode}")
        save(fig, out, f"pressure-n{n}-{mode}-vs-mu.png")


def run_tables(study, runs, name):
    """(run row, table rows) for every run that has the CSV `name`."""
    for r in runs:
        rows = read_csv(os.path.join(study, r["run_dir"], name))
        if rows:
            yield r, rows


def fcrit_scatter_and_distribution(study, runs, out):
    by_mu = defaultdict(list)
    for r, rows in run_tables(study, runs, "perturbations.csv"):
        if r["protocol"] != "pressure" or r["kind"] != "fixed-pressure":
            continue
        for p in rows:
            if p["status"] == "ok":
                by_mu[num(r, "mu")].append((num(p, "f_reference"), num(p, "f_crit"),
                                            num(r, "mean_contact_force")))
    if not by_mu:
        return
    mus = sorted(by_mu)
    shown = mus if len(mus) <= 4 else [mus[round(k * (len(mus) - 1) / 3)] for k in range(4)]
    fig, axes = plt.subplots(1, len(shown), figsize=(4 * len(shown), 4), squeeze=False)
    for ax, mu in zip(axes[0], shown):
        f = np.array(by_mu[mu])
        ax.plot(f[:, 0] / f[:, 2], f[:, 1] / f[:, 2], ".", alpha=0.6)
        top = max(np.nanmax(f[:, 0] / f[:, 2]), np.nanmax(f[:, 1] / f[:, 2]))
        ax.plot([0, top], [0, top], "k--", lw=0.8)
        ax.set_xlabel("F_cont / ⟨F⟩")
        ax.set_ylabel("F_crit / ⟨F⟩")
        ax.set_title(f"μ = {mu:g} ({len(f)} ok openings)")
    save(fig, out, "fcrit-vs-fcont.png")

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for mu in mus:
        f = np.array(by_mu[mu])
        if len(f) < 5:
            continue
        raw = f[:, 1] / f[:, 2]
        scaled = f[:, 1] / np.mean(f[:, 1])
        for ax, x in zip(axes, (raw, scaled)):
            density, edges = np.histogram(x, bins=15, density=True)
            centers = 0.5 * (edges[1:] + edges[:-1])
            keep = density > 0
            ax.semilogy(centers[keep], density[keep], "o-", label=f"μ = {mu:g} ({len(x)})")
    axes[0].set_xlabel("F_crit / ⟨F⟩ (all contacts)")
    axes[1].set_xlabel("F_crit / ⟨F_crit⟩")
    for ax in axes:
        ax.set_ylabel("P")
        ax.legend(fontsize=8)
    axes[1].set_title("normalised: the collapse")
    save(fig, out, "fcrit-distribution.png")


def profiles(study, runs, out):
    """⟨|Δf_n|⟩(r) and the paper's |⟨d⟩|(r) for every μ (openings at fixed pressure)."""
    series = defaultdict(list)
    for r, rows in run_tables(study, runs, "profile.csv"):
        if r["protocol"] == "pressure" and r["kind"] == "fixed-pressure":
            series[(r["n"], num(r, "mu"))].append(rows)
    if not series:
        return
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for (n, mu), tables in sorted(series.items(), key=lambda kv: (int(kv[0][0]), kv[0][1])):
        for ax, key, count in ((axes[0], "abs_force_change", "force_samples"),
                               (axes[1], "averaged_field_over_gap", "averaged_field_boxes")):
            r = np.array([num(row, "r") for row in tables[0]])
            values = np.array([[num(row, key) for row in t] for t in tables if len(t) == len(r)])
            counts = np.array([[num(row, count) for row in t] for t in tables if len(t) == len(r)])
            mean = np.where(counts.sum(0) > 0, (values * counts).sum(0) / np.maximum(counts.sum(0), 1), np.nan)
            keep = np.isfinite(mean) & (mean > 0)
            ax.loglog(r[keep], mean[keep], "o-", label=f"N = {n}, μ = {mu:g}")
    axes[0].set_title("⟨|Δf_n|⟩(r)")
    axes[1].set_title("|⟨d⟩|(r)/ξ, the averaged field")
    for ax in axes:
        ax.set_xlabel("r")
        ax.legend(fontsize=7)
    save(fig, out, "profiles.png")


def field_maps(study, runs, out):
    """The averaged displacement field and ΔP in the contact frame, and the angle of
    shearing of the stress after the perturbation, one column per μ."""
    fields = defaultdict(list)
    for r, rows in run_tables(study, runs, "field.csv"):
        if r["protocol"] == "pressure" and r["kind"] == "fixed-pressure":
            stress = read_csv(os.path.join(study, r["run_dir"], "stress.csv"))
            fields[num(r, "mu")].append((rows, stress))
    if not fields:
        return
    mus = sorted(fields)
    fig, axes = plt.subplots(3, len(mus), figsize=(4 * len(mus), 11), squeeze=False)
    for col, mu in enumerate(mus):
        rows, stress = fields[mu][0]  # grids differ between packings: the first packing's
        x = np.array([num(p, "x") for p in rows])
        y = np.array([num(p, "y") for p in rows])
        dx = np.array([num(p, "dx_over_gap") for p in rows])
        dy = np.array([num(p, "dy_over_gap") for p in rows])
        ax = axes[0][col]
        ax.quiver(x, y, dx, dy, np.hypot(dx, dy), cmap="viridis")
        ax.set_aspect("equal")
        ax.set_title(f"⟨d⟩/ξ, μ = {mu:g}")
        sx = np.array([num(p, "x") for p in stress])
        sy = np.array([num(p, "y") for p in stress])
        for row, key, title, cmap in ((1, "pressure_change", "ΔP", "coolwarm"),
                                      (2, "shear_angle_after", "θ after (deg)", "magma")):
            ax = axes[row][col]
            v = np.array([num(p, key) for p in stress])
            if key == "shear_angle_after":
                v = np.degrees(v)
            ax.set_title(f"{title}, μ = {mu:g}")
            if not np.isfinite(v).any():
                ax.text(0.5, 0.5, "no value", transform=ax.transAxes, ha="center")
                continue
            sc = ax.scatter(sx, sy, c=v, cmap=cmap, marker="s", s=30)
            fig.colorbar(sc, ax=ax, shrink=0.8)
            ax.set_aspect("equal")
    save(fig, out, "fields.png", dpi=80)  # many panels: a smaller file


def alpha_vs_n(rows, out):
    by_mu = groups([r for r in rows if r["kind"] == "fixed-pressure"], "mu")
    if not any(len({r["n"] for r in g}) > 1 for g in by_mu.values()):
        return
    fig, ax = plt.subplots(figsize=(5, 4))
    for (mu,), g in sorted(by_mu.items(), key=lambda kv: float(kv[0][0])):
        g = sorted(g, key=lambda r: int(r["n"]))
        if len(g) < 2:
            continue
        ax.errorbar([int(r["n"]) for r in g], [num(r, "alpha") for r in g],
                    yerr=[num(r, "alpha_error") for r in g], marker="o", capsize=3,
                    label=f"μ = {float(mu):g}")
    ax.set_xscale("log")
    ax.set_xlabel("N")
    ax.set_ylabel("α")
    ax.legend()
    save(fig, out, "alpha-vs-n.png")


def fixed_pressure_vs_volume(study, runs, out):
    pairs = defaultdict(dict)
    for r, rows in run_tables(study, runs, "perturbations.csv"):
        if r["protocol"] != "pressure":
            continue
        for p in rows:
            key = (r["packing"], p["i"], p["j"], p["image_x"], p["image_y"])
            pairs[(num(r, "mu"), key)][r["kind"]] = (num(p, "f_crit"), p["status"])
    by_mu = defaultdict(list)
    for (mu, key), kinds in pairs.items():
        if "fixed-pressure" in kinds and "fixed-volume" in kinds:
            by_mu[mu].append((kinds["fixed-pressure"], kinds["fixed-volume"]))
    if not by_mu:
        return
    fig, ax = plt.subplots(figsize=(5, 5))
    for mu, pts in sorted(by_mu.items()):
        both = [(a[0], b[0]) for a, b in pts if math.isfinite(a[0]) and math.isfinite(b[0])]
        if both:
            f = np.array(both)
            ax.plot(f[:, 0], f[:, 1], "o", label=f"μ = {mu:g} ({len(both)} of {len(pts)})")
    ax.set_xlabel("F_crit, fixed pressure")
    ax.set_ylabel("F_crit, fixed volume")
    ax.legend(fontsize=8)
    ax.set_title("the same contacts")
    save(fig, out, "fixed-pressure-vs-volume.png")


def gravity_vs_mu(rows, out):
    for (n, width), g in groups(rows, "n", "width").items():
        sides = groups(g, "kind")
        fig, axes = plt.subplots(2, 3, figsize=(13, 7))
        panels = [("height", "pile height"), ("z", "z without rattlers"),
                  ("f_reference", "⟨F_y⟩"), ("delta", "⟨δ⟩"),
                  ("ratio_fcrit_freference", "⟨F_crit⟩/⟨F_y⟩"), ("rattler_fcrit", "rattlers' F_crit")]
        for ax, (key, title) in zip(axes.flat, panels):
            for (side,), s in sorted(sides.items()):
                zero_at = mu_axis(ax, [num(r, "mu") for r in s])
                errorbars(ax, s, key, side, zero_at)
            ax.set_title(title)
            ax.legend(fontsize=8)
        fig.suptitle(f"piles: N = {n}, width {width}")
        save(fig, out, f"gravity-n{n}-w{width}-vs-mu.png")


def main():
    # Empty bins, all-zero fields and empty legends of small studies: drawn as gaps, not warned about.
    warnings.filterwarnings("ignore")
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    study = sys.argv[1]
    out = os.path.join(study, "figures")
    os.makedirs(out, exist_ok=True)
    pressure = read_csv(os.path.join(study, "summary-pressure.csv"))
    gravity = read_csv(os.path.join(study, "summary-gravity.csv"))
    runs = read_csv(os.path.join(study, "runs.csv"))
    if pressure:
        pressure_vs_mu(pressure, out)
        alpha_vs_n(pressure, out)
    fcrit_scatter_and_distribution(study, runs, out)
    profiles(study, runs, out)
    field_maps(study, runs, out)
    fixed_pressure_vs_volume(study, runs, out)
    if gravity:
        gravity_vs_mu(gravity, out)


if __name__ == "__main__":
    main()
