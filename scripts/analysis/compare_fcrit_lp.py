#!/usr/bin/python3
"""Simulated critical forces beside the admissible-force LPs, contact by contact.

Joins the rows of an `unjam perturb -o DIR` run (openings) with an `unjam bounds -o CSV`
run on the same packing by (i, j, image), classifies every opening by what the LP says
about holding the contact without friction (infeasible, only at zero force, positive) and
by what the simulation did (quasi-static or dynamic), and checks the quasi-static F_crit
against the interval [LP min, LP max without friction] that a static opening must lie in,
to 1e-6 of the mean force plus the row's `inertial_force` (F_crit's O(ξ) inertial part,
docs/perturbations.md; as `unjam bounds --compare-perturb` allows for it).
Prints a Markdown table and a few summary lines; with a third argument, also writes the
joined rows as CSV.

Usage: scripts/analysis/compare_fcrit_lp.py PERTURB_DIR BOUNDS_CSV [JOINED_CSV]
"""
import csv
import math
import statistics
import sys


def number(text):
    return float(text) if text not in ("", "nan", "-nan") else math.nan


def key(row):
    i, j = int(row["i"]), int(row["j"])
    image = (int(row["image_x"]), int(row["image_y"]))
    # The same contact may be listed as (i, j, image) or (j, i, -image).
    return (i, j, image) if i < j else (j, i, (-image[0], -image[1]))


def lp_class(bound, scale):
    without = number(bound["max_without_friction"])
    if bound["status_without_friction"] == "infeasible":
        return "infeasible"
    if math.isnan(without):
        return bound["status_without_friction"] or "unknown"
    return "zero" if without <= 1e-9 * scale else "positive"


def main():
    perturb_dir, bounds_csv = sys.argv[1], sys.argv[2]
    openings = [r for r in csv.DictReader(open(f"{perturb_dir}/perturbations.csv")) if r["kind"] == "opening"]
    bounds = {key(b): b for b in csv.DictReader(open(bounds_csv))}
    scale = statistics.mean(number(b["f_cont"]) for b in bounds.values())
    joined, missing = [], 0
    for r in openings:
        b = bounds.get(key(r))
        if b is None:
            missing += 1
            continue
        joined.append({"i": r["i"], "j": r["j"], "image_x": r["image_x"], "image_y": r["image_y"],
                       "f_cont": r["f_reference"], "f_crit": r["f_crit"], "status": r["status"],
                       "delta": r["penetration_depth"], "lp_min": b["min"], "lp_max": b["max"],
                       "lp_max_without_friction": b["max_without_friction"], "lp_class": lp_class(b, scale),
                       "inertial_force": r.get("inertial_force", "0"), "fcrit_10xi": r.get("fcrit_10xi", "nan")})
    classes = ["infeasible", "zero", "positive"]
    kinds = [("dynamic", "dynamic"), ("quasi-static", "ok"), ("quasi-static, not linear in ξ", "nonlinear"),
             ("not resolved", "not-converged")]
    print(f"{len(openings)} openings, {len(joined)} matched to an LP row, {missing} without one")
    print()
    print("| LP max without friction | " + " | ".join(k for k, _ in kinds) + " |")
    print("|---|" + "---|" * len(kinds))
    for c in classes + sorted({r["lp_class"] for r in joined} - set(classes)):
        counts = [sum(1 for r in joined if r["lp_class"] == c and r["status"] == s) for _, s in kinds]
        print(f"| {c} | " + " | ".join(str(n) for n in counts) + " |")
    static = [r for r in joined if r["status"] == "ok"]
    tol = 1e-6 * scale
    # The inertial part grows with the gap: gap_scale 10 for F_crit at 10ξ.
    slack = lambda r, gap_scale=1: tol + gap_scale * number(r["inertial_force"] or "0")
    within = lambda r, f, gap_scale=1: (r["lp_class"] in ("zero", "positive") and
                                        number(r["lp_min"]) - slack(r, gap_scale) <= f <=
                                        number(r["lp_max_without_friction"]) + slack(r, gap_scale))
    inside = [r for r in static if within(r, number(r["f_crit"]))]
    print()
    print(f"quasi-static F_crit inside [LP min, LP max without friction] (to 1e-6 of <F_cont> plus its inertial part): "
          f"{len(inside)} of {len(static)}")
    # The small-gap check's rejects: two members of the step's solution family, at ξ and 10ξ.
    nonlinear = [r for r in joined if r["status"] == "nonlinear"]
    if nonlinear:
        both = [r for r in nonlinear if within(r, number(r["f_crit"])) and within(r, number(r["fcrit_10xi"]), 10)]
        print(f"nonlinear openings with F_crit at ξ and at 10ξ both inside it: {len(both)} of {len(nonlinear)}")
    spans = [(number(r["f_crit"]) - number(r["lp_min"])) /
             (number(r["lp_max_without_friction"]) - number(r["lp_min"]))
             for r in inside if number(r["lp_max_without_friction"]) - number(r["lp_min"]) > tol]
    if spans:
        print(f"where inside it (0 = LP min, 1 = LP max without friction): mean {statistics.mean(spans):.3f}, "
              f"median {statistics.median(spans):.3f}, over {len(spans)} intervals of positive width")
    rel = [abs(number(r["f_crit"]) - number(r["lp_max_without_friction"])) / number(r["lp_max_without_friction"])
           for r in static if r["lp_class"] == "positive"]
    if rel:
        print(f"|F_crit - LP max without friction| / LP max without friction: mean {statistics.mean(rel):.3f}, "
              f"max {max(rel):.3f}")
    if len(sys.argv) > 3:
        with open(sys.argv[3], "w", newline="") as out:
            writer = csv.DictWriter(out, fieldnames=list(joined[0].keys()))
            writer.writeheader()
            writer.writerows(joined)


if __name__ == "__main__":
    main()
