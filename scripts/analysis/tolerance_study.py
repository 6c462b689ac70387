#!/usr/bin/python3
"""The cost of accuracy in the physics: F_crit and the penetration depth δ of the same
contact openings solved at a ladder of solver tolerances, per backend, against the tightest
newton result. Prints, per backend and tolerance, the largest relative change of F_crit
and δ over the openings and the time, and the loosest tolerance at which both are within
1 % (docs/accuracy-vs-time.md).
Usage: scripts/analysis/tolerance_study.py UNJAM PACKING OUT_CSV [--sample N] [--seed S]
           [--backends nsgs,newton] [--tols 1e-4,1e-6,...]
"""
import argparse, csv, json, os, subprocess, sys, tempfile

ap = argparse.ArgumentParser()
ap.add_argument("unjam"); ap.add_argument("packing"); ap.add_argument("out")
ap.add_argument("--sample", type=int, default=10); ap.add_argument("--seed", type=int, default=1)
ap.add_argument("--backends", default="nsgs,newton")
ap.add_argument("--tols", default="1e-4,1e-6,1e-8,1e-10,1e-11,1e-12")
ap.add_argument("--ref-tol", type=float, default=1e-13)
a = ap.parse_args()


def run(backend, tol):
    with tempfile.TemporaryDirectory() as d:
        cmd = [a.unjam, "perturb", a.packing, "--sample", str(a.sample), "--seed", str(a.seed), "--backend", backend,
               "--tol", f"{tol:g}", "--threads", "1", "--quiet", "--json", "-o", d]
        summary = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
        rows = list(csv.DictReader(open(os.path.join(d, "perturbations.csv"))))
    return summary, {(r["i"], r["j"]): r for r in rows}


_, ref = run("newton", a.ref_tol)
bad = [k for k, r in ref.items() if r["status"] != "ok"]
if bad:
    print(f"reference: {len(bad)} openings not ok at {a.ref_tol:g}: {bad}", file=sys.stderr)
keys = [k for k, r in ref.items() if r["status"] == "ok"]
out = []
print(f"{'backend':8} {'tol':>7} {'max dF/F':>10} {'max dδ/δ':>10} {'not ok':>6} {'seconds':>8}")
for backend in a.backends.split(","):
    loosest = None
    for tol in sorted((float(t) for t in a.tols.split(",")), reverse=True):
        summary, rows = run(backend, tol)
        rel = lambda key: max(abs(float(rows[k][key]) / float(ref[k][key]) - 1) for k in keys)
        df, dd = rel("f_crit"), rel("penetration_depth")
        not_ok = sum(rows[k]["status"] != "ok" for k in keys)
        secs = sum(float(rows[k]["seconds"]) for k in keys)
        out.append({"backend": backend, "tolerance": tol, "max_rel_fcrit": df, "max_rel_delta": dd, "not_ok": not_ok, "seconds": secs})
        print(f"{backend:8} {tol:7.0e} {df:10.2e} {dd:10.2e} {not_ok:6d} {secs:8.2f}")
        if loosest is None and df <= 0.01 and dd <= 0.01:
            loosest = tol
    print(f"{backend}: loosest tolerance with F_crit and δ within 1 %: {loosest if loosest else 'none in the ladder'}")
with open(a.out, "w", newline="") as fh:
    w = csv.DictWriter(fh, fieldnames=list(out[0]))
    w.writeheader(); w.writerows(out)
print("wrote", a.out)
