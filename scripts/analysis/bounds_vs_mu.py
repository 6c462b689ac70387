#!/usr/bin/env python3
"""Admissible-force interval width vs friction for the bundled packings (issue 5's measure).

Runs `unjam bounds --json` on each bundled packing, writes bench/results/bounds-vs-mu.csv,
the figure docs/figures/bounds-width-vs-mu.png (matplotlib) and the table between the
<!-- bounds-table --> markers of docs/indeterminacy.md.
Usage: scripts/analysis/bounds_vs_mu.py [BUILD_DIR]
"""
import csv, json, os, re, subprocess, sys

root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
unjam = os.path.join(sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build"), "unjam")
packings = ["pressure-n500-mu0", "pressure-n500-mu0.01", "pressure-n500-mu0.1", "pressure-n500-mu0.5",
            "pressure-n500-mu1", "pressure-n500-mu10", "gravity-n100-mu0.5"]
# Rows already measured are kept (the N=500 runs take minutes each): delete the CSV to redo.
results = os.path.join(root, "bench", "results", "bounds-vs-mu.csv")
done = {}
if os.path.exists(results):
    for r in csv.DictReader(open(results)):
        done[r["packing"]] = {k: (r[k] if k == "packing" else int(r[k]) if r[k].isdigit() else float(r[k])) for k in r}


def write_rows(rows):  # as we go, keeping the measured rows not yet reached
    with open(results, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)


rows = []
for name in packings:
    if name in done:
        rows.append(done[name])
        continue
    path = os.path.join(root, "problems", name + ".unjam")
    out = subprocess.run([unjam, "bounds", path, "--json"], capture_output=True, text=True)
    d = json.loads(out.stdout)
    mu = float(re.search(r"mu([0-9.]+)$", name).group(1))
    rows.append({"packing": name, "mu": mu, "contacts": d["contacts"], "indeterminacy": d["indeterminacy_dimension"],
                 "mean_width": d["mean_width"] if d["mean_width"] is not None else float("nan"), "mean_fcont": d["mean_fcont"],
                 "relative_width": d["mean_width"] / d["mean_fcont"] if d["mean_width"] is not None and d["mean_fcont"] else float("nan"),
                 "unbounded": d["unbounded_or_failed"], "no_frictionless_equilibrium": d["no_frictionless_equilibrium"],
                 "seconds": d["seconds"]})
    print(rows[-1], flush=True)
    write_rows(rows + [done[n] for n in packings if n in done and n not in {r["packing"] for r in rows}])
write_rows(rows)

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
pressure = [r for r in rows if r["packing"].startswith("pressure") and r["mu"] > 0]
fig, ax = plt.subplots(figsize=(5, 3.6))
ax.loglog([r["mu"] for r in pressure], [r["relative_width"] for r in pressure], "o-", label="pressure, N=500")
pile = [r for r in rows if r["packing"].startswith("gravity")]
ax.loglog([r["mu"] for r in pile], [r["relative_width"] for r in pile], "s", label="gravity pile, N=100")
ax.set_xlabel("friction coefficient μ")
ax.set_ylabel("⟨max − min⟩ / ⟨F_cont⟩")
ax.set_title("Width of the admissible normal-force interval")
ax.legend()
fig.tight_layout()
fig.savefig(os.path.join(root, "docs", "figures", "bounds-width-vs-mu.png"), dpi=120)

table = ["| packing | μ | contacts | indeterminacy | ⟨width⟩ | ⟨F_cont⟩ | ⟨width⟩/⟨F_cont⟩ | unbounded | no frictionless equilibrium |",
         "|---|---|---|---|---|---|---|---|---|"]
for r in rows:
    table.append(f"| {r['packing']} | {r['mu']:g} | {int(r['contacts'])} | {int(r['indeterminacy'])} | {r['mean_width']:.4g} | "
                 f"{r['mean_fcont']:.4g} | {r['relative_width']:.3g} | {int(r['unbounded'])} | {int(r['no_frictionless_equilibrium'])} |")
doc = os.path.join(root, "docs", "indeterminacy.md")
text = open(doc).read()
text = re.sub(r"<!-- bounds-table -->.*<!-- /bounds-table -->", "<!-- bounds-table -->\n" + "\n".join(table) + "\n<!-- /bounds-table -->", text, flags=re.S)
open(doc, "w").write(text)
