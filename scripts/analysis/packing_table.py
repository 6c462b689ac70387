#!/usr/bin/python3
"""Packing fraction and coordination number vs friction of the bundled packings.

Reads every problems/*.unjam through `unjam info --json` (and problems/logs/NAME.json for
steps and seconds), writes two tables into docs/packings.md (between the <!-- table --> and
<!-- all --> markers: the N = 500 pressure series vs mu, and every bundled packing) and the
figure docs/figures/packings-phi-z.png.
Usage: /usr/bin/python3 scripts/analysis/packing_table.py [BUILD_DIR]
"""
import glob
import json
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
unjam = os.path.join(sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build"), "unjam")

def info(path):
    return json.loads(subprocess.run([unjam, "info", "--json", path], check=True,
                                     capture_output=True, text=True).stdout)


def log(path):
    name = os.path.join(root, "problems", "logs", os.path.basename(path)[:-len(".unjam")] + ".json")
    return json.load(open(name)) if os.path.exists(name) else {}


def friction(d):
    """μ from `unjam info`'s effects line ("friction mu=0.5, ..."); absent means 0."""
    effects = d["effects"]
    return effects.split("mu=")[1].split(",")[0].split()[0] if "mu=" in effects else "0"


def replace_between(text, marker, lines):
    head, rest = text.split(f"<!-- {marker} -->\n", 1)
    tail = rest.split(f"<!-- /{marker} -->", 1)[1]
    return head + f"<!-- {marker} -->\n" + "\n".join(lines) + f"\n<!-- /{marker} -->" + tail


everything = []
for path in sorted(glob.glob(os.path.join(root, "problems", "*.unjam"))):
    d, run = info(path), log(path)
    everything.append((os.path.basename(path), d, run))
if not everything:
    sys.exit("no problems/*.unjam found: run scripts/make-problems.sh first")

rows = []
piles = []
for name, d, _ in everything:
    mu = float(friction(d))
    row = (mu, d["packing_fraction"], d["coordination"], d["rattlers"], d["particles"] - d["fixed"], name)
    if name.startswith("pressure-n500-mu"):
        rows.append(row)
    elif name.startswith("gravity-n1600"):
        piles.append(row)
rows.sort()
piles.sort()

table = ["| μ | packing fraction φ | coordination z (rattlers excluded) | rattlers | N | file |",
         "|---|---|---|---|---|---|"]
for mu, phi, z, rattlers, n, name in rows:
    table.append(f"| {mu:g} | {phi:.4f} | {z:.3f} | {rattlers} | {n} | `{name}` |")
full = ["| file | protocol | N free | μ | φ | z | rattlers | steps | static checks | seconds |",
        "|---|---|---|---|---|---|---|---|---|---|"]
for name, d, run in everything:
    mu = friction(d)
    full.append(f"| `{name}` | {run.get('protocol', '?')} | {d['particles'] - d['fixed']} | {mu} | "
                f"{d['packing_fraction']:.4f} | {d['coordination']:.3f} | {d['rattlers']} | "
                f"{run.get('steps', '?')} | {run.get('static_checks', '?')} | {run.get('seconds', float('nan')):.0f} |")
page = os.path.join(root, "docs", "packings.md")
text = replace_between(open(page).read(), "table", table)
text = replace_between(text, "all", full)
open(page, "w").write(text)

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
if piles:
    left.semilogx([p[0] for p in piles], [p[1] for p in piles], "D", color="C2", label="pile under gravity, N = 1600")
    right.semilogx([p[0] for p in piles], [p[2] for p in piles], "D", color="C2", label="pile under gravity, N = 1600")
    left.plot([], [], "o-", color="C0", label="constant pressure, N = 500")
    left.legend(fontsize=8)
fig.suptitle("Bundled jammed packings: constant pressure (N = 500) and piles under gravity")
fig.tight_layout()
fig.savefig(os.path.join(root, "docs", "figures", "packings-phi-z.png"), dpi=120)
print(f"{len(everything)} packings: docs/packings.md, docs/figures/packings-phi-z.png")
