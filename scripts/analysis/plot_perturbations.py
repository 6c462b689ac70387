#!/usr/bin/python3
"""Figures of an `unjam perturb -o DIR` run (matplotlib): displacement decay d(r) with its
power-law fit, force response |Δf_n|(r), the distribution of F_crit, F_crit against F_cont,
the mean displacement field and the pressure change of the stress response in the contact
frame.
Usage: scripts/analysis/plot_perturbations.py DIR OUTPUT_PREFIX   (writes OUTPUT_PREFIX-*.png)
"""
import csv, json, math, sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

run, prefix = sys.argv[1], sys.argv[2]
summary = json.load(open(f"{run}/summary.json"))
rows = lambda name: list(csv.DictReader(open(f"{run}/{name}")))
num = lambda x: float(x) if x not in ("", "nan", "-nan") else math.nan

# 1. Radial profiles.
profile = rows("profile.csv")
r = np.array([num(p["r"]) for p in profile])
d = np.array([num(p["displacement_over_gap"]) for p in profile])
de = np.array([num(p["displacement_error"]) for p in profile])
af = np.array([num(p["averaged_field_over_gap"]) for p in profile])
afe = np.array([num(p["averaged_field_error"]) for p in profile])
f = np.array([num(p["abs_force_change"]) for p in profile])
fe = np.array([num(p["force_change_error"]) for p in profile])
fig, (a1, a2) = plt.subplots(1, 2, figsize=(9, 3.6))
# The paper's d(r): |⟨d⟩| of the averaged field, with its fit (α); beside it the mean of |d|.
a1.errorbar(r, af, yerr=afe, fmt="o", ms=4, label="|⟨d⟩| (averaged field)")
a1.errorbar(r, d, yerr=de, fmt="^", ms=3, alpha=0.6, label="⟨|d|⟩")
if summary["alpha"] is not None:
    lo, hi = summary["alpha_fit_range"]
    sel = (r >= lo) & (r <= hi) & np.isfinite(af) & (af > 0)
    c = np.exp(np.mean(np.log(af[sel]) + summary["alpha"] * np.log(r[sel])))
    rr = np.linspace(lo, hi, 50)
    a1.plot(rr, c * rr ** -summary["alpha"], "-", label=f"α = {summary['alpha']:.3f} ± {summary['alpha_error']:.3f}")
a1.legend(fontsize=7)
a1.set_xscale("log"); a1.set_yscale("log")
a1.set_xlabel("distance r from the perturbation"); a1.set_ylabel("d / ξ")
a1.set_title("displacement")
a2.errorbar(r, f, yerr=fe, fmt="s", ms=4)
a2.set_xscale("log"); a2.set_yscale("log")
a2.set_xlabel("distance r of the contact point"); a2.set_ylabel("⟨|Δf_n|⟩")
a2.set_title("force response")
fig.tight_layout(); fig.savefig(f"{prefix}-profiles.png", dpi=110)

# 2. F_crit: distribution (over its mean) and against F_cont.
per = [p for p in rows("perturbations.csv") if p["status"] == "ok" and p["rattler"] == "0"]
fc = np.array([num(p["f_crit"]) for p in per]); fr = np.array([num(p["f_reference"]) for p in per])
fig, (a1, a2) = plt.subplots(1, 2, figsize=(9, 3.6))
hist = [h for h in rows("fcrit_histogram.csv") if h["scale"] == "over_mean"]
centres = [(num(h["bin_low"]) + num(h["bin_high"])) / 2 for h in hist]
a1.semilogy(centres, [num(h["density"]) or math.nan for h in hist], "o")
if summary["fcrit_tail_scale"]:
    s = summary["fcrit_tail_scale"]; n_tail = summary["fcrit_tail_samples"]; frac = n_tail / max(1, len(fc))
    x = np.linspace(1, max(centres), 50)
    a1.plot(x, frac / s * np.exp(-(x - 1) / s), "-", label=f"tail scale {s:.2f} ± {summary['fcrit_tail_scale_error']:.2f}")
    a1.legend()
a1.set_xlabel("F_crit / ⟨F_crit⟩"); a1.set_ylabel("probability density"); a1.set_title("distribution of F_crit")
# Linear axes: a frictional packing has quasi-static openings held at zero force.
a2.plot(fr, fc, ".", ms=3, label=f"quasi-static ({len(fc)})")
top = max(fr.max(), fc.max())
# Dynamic responses (the packing yields): their F_crit is the first step of a motion, not
# a critical force; shown apart so that the two kinds are not mixed up.
dyn = [p for p in rows("perturbations.csv") if p["status"] == "dynamic" and p["rattler"] == "0"]
if dyn:
    dr = np.array([num(p["f_reference"]) for p in dyn]); dc = np.array([num(p["f_crit"]) for p in dyn])
    a2.plot(dr, dc, "x", ms=3, color="0.6", label=f"dynamic ({len(dyn)})")
    a2.legend(fontsize=8)
    top = max(top, dr.max(), dc.max())
lim = [0, top]
a2.plot(lim, lim, "k--", lw=0.8)
a2.set_xlabel(summary["reference"]); a2.set_ylabel("F_crit"); a2.set_title("F_crit against the static force")
fig.tight_layout(); fig.savefig(f"{prefix}-fcrit.png", dpi=110)

# 3. Fields in the contact frame.
field = rows("field.csv"); stress = rows("stress.csv")
fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4.4))
x = np.array([num(b["x"]) for b in field]); y = np.array([num(b["y"]) for b in field])
u = np.array([num(b["dx_over_gap"]) for b in field]); v = np.array([num(b["dy_over_gap"]) for b in field])
mag = np.hypot(u, v); keep = mag > 0
a1.quiver(x[keep], y[keep], (u / np.maximum(mag, 1e-300))[keep], (v / np.maximum(mag, 1e-300))[keep], np.log10(mag[keep]), cmap="viridis", scale=40)
a1.set_aspect("equal"); a1.set_title("⟨d⟩/ξ (direction; colour log₁₀ |⟨d⟩|/ξ)"); a1.set_xlabel("x along the normal")
sx = np.array([num(b["x"]) for b in stress]); sy = np.array([num(b["y"]) for b in stress])
dp = np.array([num(b["pressure_change"]) for b in stress])
n = int(round(math.sqrt(len(stress))))
grid = dp.reshape(n, n)
vmax = np.nanmax(np.abs(grid)) or 1
im = a2.imshow(grid, origin="lower", extent=[sx.min() - 1, sx.max() + 1, sy.min() - 1, sy.max() + 1], cmap="RdBu_r", vmin=-vmax, vmax=vmax)
fig.colorbar(im, ax=a2); a2.set_title("⟨ΔP⟩ of the stress response"); a2.set_xlabel("x along the normal")
fig.tight_layout(); fig.savefig(f"{prefix}-fields.png", dpi=110)
print("wrote", f"{prefix}-profiles.png", f"{prefix}-fcrit.png", f"{prefix}-fields.png")
