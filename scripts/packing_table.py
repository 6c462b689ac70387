#!/usr/bin/python3
"""Packing fraction and coordination number vs friction of the bundled packings.

Reads every problems/pressure-n500-mu*.unjam through `unjam info --json`, writes the table
into docs/packings.md (between the <!-- table --> markers) and the figure
docs/figures/packings-phi-z.png.
Usage: /usr/bin/python3 scripts/packing_table.py [BUILD_DIR]
"""
import glob
import json
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
unjam = os.path.join(sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build"), "unjam")

rows = []
for path in sorted(glob.glob(os.path.join(root, "problems", "pressure-n500-mu*.unjam"))):
    info = json.loads(subprocess.run([unjam, "info", "--json", path], check=True,
                                     capture_output=True, text=True).stdout)
    mu = float(os.path.basename(path)[len("pressure-n500-mu"):-len(".unjam")])
    rows.append((mu, info["packing_fraction"], info["coordination"], info["rattlers"],
                 info["particles"], os.path.basename(path)))
rows.sort()
if not rows:
    sys.exit("no problems/pressure-n500-mu*.unjam found: run scripts/make-problems.sh first")

table = ["| μ | packing fraction φ | coordination z (rattlers excluded) | rattlers | N | file |",
         "|---|---|---|---|---|---|"]
for mu, phi, z, rattlers, n, name in rows:
    table.append(f"| {mu:g} | {phi:.4f} | {z:.3f} | {rattlers} | {n} | `{name}` |")
page = os.path.join(root, "docs", "packings.md")
text = open(page).read()
head, rest = text.split("<!-- table -->\n", 1)
tail = rest.split("<!-- /table -->", 1)[1]
with open(page, "w") as out:
    out.write(head + "<!-- table -->\n" + "\n".join(table) + "\n<!-- /table -->" + tail)

# μ = 0 sits at the left edge of a log axis: plot it at μ = 1e-3 and say so.
mus = [mu if mu > 0 else 1e-3 for mu, *_ in rows]
fig, (left, right) = plt.subplots(1, 2, figsize=(9, 3.6))
left.semilogx(mus, [r[1] for r in rows], "o-")
left.set_xlabel("friction μ (μ = 0 drawn at 1e-3)")
left.set_ylabel("packing fraction φ")
right.semilogx(mus, [r[2] for r in rows], "s-", color="C1")
right.axhline(4.0, color="gray", lw=0.8, ls="--")
right.axhline(3.0, color="gray", lw=0.8, ls="--")
right.set_xlabel("friction μ (μ = 0 drawn at 1e-3)")
right.set_ylabel("coordination z")
fig.suptitle("Jammed packings at constant pressure, N = 500 (bundled)")
fig.tight_layout()
fig.savefig(os.path.join(root, "docs", "figures", "packings-phi-z.png"), dpi=120)
print(f"{len(rows)} packings: docs/packings.md, docs/figures/packings-phi-z.png")
