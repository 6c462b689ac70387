#!/usr/bin/env python3
"""Writes the hand-made hard cases of problems/hard/ (README.md there): small `.unjam`
scenes at rest whose contacts touch to round-off (positions computed analytically, written
with repr, the shortest decimal that reads back to the same double), and two ill-posed
Siconos problems that the reader must refuse. No stored forces: every solve starts from
zero impulses.

Usage: scripts/make_hard_cases.py [DIR]     (default problems/hard; created if missing)

Python 3 standard library only. Running it twice writes the same bytes.
"""

import math
import os
import sys

GRAVITY_DOWN = (0.0, -1.0)


def num(x):
    """A double as the shortest decimal that reads back to the same bits (repr); 0 as 0."""
    x = float(x)
    if not math.isfinite(x):
        raise ValueError("non-finite value %r" % x)
    if x == 0.0:
        return "0"
    if x == int(x) and abs(x) < 1e15:
        return str(int(x))
    return repr(x)


class Scene:
    """One `.unjam` file (docs/format.md, version 1)."""

    def __init__(self, name, about, cell, periodic="none", gravity=GRAVITY_DOWN,
                 friction=0.5):
        self.name = name
        self.about = about  # comment lines at the top of the file
        self.cell = cell
        self.periodic = periodic
        self.gravity = gravity
        self.friction = friction
        self.walls = []
        self.motions = []
        self.particles = []

    def wall(self, px, py, nx, ny):
        norm = math.hypot(nx, ny)
        if abs(norm - 1.0) > 1e-14:
            raise ValueError("%s: wall normal (%r, %r) not unit" % (self.name, nx, ny))
        self.walls.append((px, py, nx, ny))

    def disk(self, x, y, radius=0.5, density=1.0, fixed=0):
        self.particles.append((x, y, radius, density, fixed))
        return len(self.particles) - 1

    def prescribe(self, index, vx, vy, spin):
        self.motions.append((index, vx, vy, spin))

    def text(self):
        out = ["unjam-packing 1"]
        out += ["# " + line if line else "#" for line in self.about]
        out.append("cell %s %s" % (num(self.cell[0]), num(self.cell[1])))
        out.append("periodic %s" % self.periodic)
        for px, py, nx, ny in self.walls:
            out.append("wall %s %s %s %s" % (num(px), num(py), num(nx), num(ny)))
        if self.gravity is not None:
            out.append("gravity %s %s" % (num(self.gravity[0]), num(self.gravity[1])))
        out.append("friction %s" % num(self.friction))
        for index, vx, vy, spin in self.motions:
            out.append("prescribed-motion %d %s %s %s" % (index, num(vx), num(vy), num(spin)))
        out.append("seed 0")
        out.append("provenance scripts/make_hard_cases.py (problems/hard/README.md)")
        out.append("particles %d" % len(self.particles))
        out.append("# x y angle vx vy spin radius density fixed")
        for x, y, radius, density, fixed in self.particles:
            out.append("%s %s 0 0 0 0 %s %s %d" % (num(x), num(y), num(radius), num(density),
                                                  fixed))
        out.append("end")
        return "\n".join(out) + "\n"


def heavy_on_light():
    s = Scene("heavy-on-light", [
        "hard case: a disk 1e6 times heavier than the two it rests on (mass ratio 1e6).",
        "Light disks at x = -0.6, 0.6 on the floor (apart by 0.2); the heavy one at",
        "(0, 0.5 + 0.8): centre distances exactly 1 (a 3-4-5 triangle).",
    ], cell=(4, 4))
    s.wall(0, 0, 0, 1)
    s.disk(-0.6, 0.5)
    s.disk(0.6, 0.5)
    s.disk(0.0, 0.5 + math.sqrt(1.0 - 0.6 * 0.6), density=1e6)
    return s


def radius_ratio_100():
    s = Scene("radius-ratio-100", [
        "hard case: radius ratio 100 (mass ratio 1e4). A disk of radius 1 on the floor and",
        "two of radius 0.01 on the floor touching it on either side: centre distance 1.01,",
        "dx = sqrt(1.01^2 - 0.99^2) = 0.2.",
    ], cell=(4, 4))
    s.wall(0, 0, 0, 1)
    big, small = 1.0, 0.01
    dx = math.sqrt((big + small) ** 2 - (big - small) ** 2)
    s.disk(0.0, big, radius=big)
    s.disk(-dx, small, radius=small)
    s.disk(dx, small, radius=small)
    return s


def v_groove_lid():
    s = Scene("v-groove-lid", [
        "hard case: redundant contacts. A disk of radius 1 in a 90-degree V groove (two walls",
        "through the origin, inward normals (+-sin 45, cos 45)) and a lid wall touching its",
        "top (normal (0, -1)): 3 contacts on one disk.",
    ], cell=(4, 4), friction=0.3)
    c = math.sqrt(0.5)
    s.wall(0, 0, c, c)
    s.wall(0, 0, -c, c)
    y = 1.0 / c  # distance 1 from both walls: c * y = 1
    s.wall(0, y + 1.0, 0, -1)
    s.disk(0.0, y, radius=1.0)
    return s


def four_disks_square():
    s = Scene("four-disks-square", [
        "hard case: hyperstatic. Four disks of radius 0.5 in a 2x2 square between a floor",
        "(y = 0), a left wall (x = 0) and a right wall (x = 2): 4 disk-disk and 6 wall",
        "contacts, all touching.",
    ], cell=(2, 2))
    s.wall(0, 0, 0, 1)
    s.wall(0, 0, 1, 0)
    s.wall(2, 0, -1, 0)
    for y in (0.5, 1.5):
        for x in (0.5, 1.5):
            s.disk(x, y)
    return s


def column_200():
    n = 200
    s = Scene("column-200", [
        "hard case: forces carried down 200 disks. 200 disks of radius 0.5 stacked in a",
        "channel one diameter wide (side walls at x = 0 and x = 1, floor y = 0): every disk",
        "touches both side walls and its neighbours above and below.",
    ], cell=(1, n))
    s.wall(0, 0, 0, 1)
    s.wall(0, 0, 1, 0)
    s.wall(1, 0, -1, 0)
    for k in range(n):
        s.disk(0.5, 0.5 + k)
    return s


def pile_400_wide():
    n = 400
    s = Scene("pile-400-wide", [
        "hard case: a wide hexagonal pile, periodic in x (width 400), on a floor y = 0.",
        "Three rows of 400 disks of radius 0.5: x = 0.5 + k at y = 0.5, x = 1 + k (mod 400)",
        "at y = 0.5 + sqrt(3)/2, x = 0.5 + k at y = 0.5 + sqrt(3). 1200 disks.",
    ], cell=(n, 10), periodic="x")
    s.wall(0, 0, 0, 1)
    h = math.sqrt(3.0) / 2.0
    for k in range(n):
        s.disk(0.5 + k, 0.5)
    for k in range(n):
        s.disk(float((1 + k) % n), 0.5 + h)
    for k in range(n):
        s.disk(0.5 + k, 0.5 + 2.0 * h)
    return s


def wedge():
    a = math.radians(10.0)
    s = Scene("wedge", [
        "hard case: self-locking wedge. Two walls through the origin at 10 degrees on either",
        "side of the vertical (inward normals (cos 10, sin 10) and (-cos 10, sin 10)), a",
        "disk of radius 1 touching both at (0, 1/sin 10). Locks for mu >= tan 10 = 0.176.",
    ], cell=(4, 8), friction=1.0)
    s.wall(0, 0, math.cos(a), math.sin(a))
    s.wall(0, 0, -math.cos(a), math.sin(a))
    s.disk(0.0, 1.0 / math.sin(a), radius=1.0)
    return s


def near_coincident():
    e = 1e-6
    s = Scene("near-coincident", [
        "hard case: nearly parallel contacts. A floor (normal (0, 1)) and a second wall",
        "through the origin with normal (sin 1e-6, cos 1e-6); a disk of radius 0.5 at",
        "distance 0.5 from both: (0.5 tan(0.5e-6), 0.5).",
    ], cell=(2, 2))
    s.wall(0, 0, 0, 1)
    s.wall(0, 0, math.sin(e), math.cos(e))
    s.disk(0.5 * math.tan(0.5 * e), 0.5)
    return s


def gap_1e_12():
    g = 1e-12
    s = Scene("gap-1e-12", [
        "hard case: gaps of 1e-12, far below the contact-gap tolerance (1e-9). Three disks of",
        "radius 0.5 on a floor at x = 0.5, 1.5 + 1e-12, 2.5 + 2e-12, and a fourth resting",
        "on the first two (centre distance 1 to both).",
    ], cell=(4, 4))
    s.wall(0, 0, 0, 1)
    x0, x1, x2 = 0.5, 1.5 + g, 2.5 + 2 * g
    s.disk(x0, 0.5)
    s.disk(x1, 0.5)
    s.disk(x2, 0.5)
    half = 0.5 * (x1 - x0)
    s.disk(0.5 * (x0 + x1), 0.5 + math.sqrt(1.0 - half * half))
    return s


def one_particle():
    s = Scene("one-particle", [
        "degenerate case: one free disk in the middle of a box of 4 walls, no contact, no",
        "gravity.",
    ], cell=(4, 4), gravity=None)
    s.wall(0, 0, 0, 1)
    s.wall(0, 4, 0, -1)
    s.wall(0, 0, 1, 0)
    s.wall(4, 0, -1, 0)
    s.disk(2.0, 2.0)
    return s


def no_contacts():
    s = Scene("no-contacts", [
        "degenerate case: 10 disks of radius 0.5 far apart in a periodic cell, no gravity.",
    ], cell=(20, 20), periodic="xy", gravity=None)
    for k in range(10):
        s.disk(2.0 + 4.0 * (k % 5), 5.0 + 10.0 * (k // 5))
    return s


def all_fixed():
    s = Scene("all-fixed", [
        "degenerate case: 5 touching disks on a floor, all fixed: nothing can move, no",
        "unknown.",
    ], cell=(5, 2))
    s.wall(0, 0, 0, 1)
    for k in range(5):
        s.disk(0.5 + k, 0.5, fixed=1)
    return s


def blocked():
    s = Scene("blocked", [
        "ill-posed case: a disk on a floor pushed into it by prescribed-motion 0 0 -1 0: no",
        "impulse can stop it; the solve must report not converged, naming the contact.",
    ], cell=(2, 2))
    s.wall(0, 0, 0, 1)
    s.disk(1.0, 0.5)
    s.prescribe(0, 0.0, -1.0, 0.0)
    return s


SCENES = [heavy_on_light, radius_ratio_100, v_groove_lid, four_disks_square, column_200,
          pile_400_wide, wedge, near_coincident, gap_1e_12, one_particle, no_contacts,
          all_fixed, blocked]


def dense_dat(w, q, mu):
    """One-contact Siconos problem, dense storage (as problems/siconos/one-contact-stick.dat):
    W (2x2, row-major argument) written column by column."""
    lines = ["2", "1", "0", "2", "2", "2 2"]
    for j in range(2):
        lines.append("%s %s" % (num(w[0][j]), num(w[1][j])))
    lines.append("%s %s" % (num(q[0]), num(q[1])))
    lines.append(num(mu))
    return "\n".join(lines) + "\n"


DAT = {
    # W = -diag(2, 4): a negative diagonal, impossible for H M^-1 H^T.
    "ill-posed-negative-diagonal.dat": dense_dat([[-2, 0], [0, -4]], [-1, 0.4], 0.5),
    # W = 0: r = 0 would "solve" any q_n >= 0; meaningless, refused.
    "ill-posed-zero-w.dat": dense_dat([[0, 0], [0, 0]], [-1, 0.4], 0.5),
}


def write(path, text):
    with open(path, "w", encoding="utf-8", newline="\n") as f:
        f.write(text)


def main(argv):
    if len(argv) > 2 or (len(argv) == 2 and argv[1] in ("-h", "--help")):
        print(__doc__.strip())
        return 0 if len(argv) == 2 else 2
    out = argv[1] if len(argv) == 2 else "problems/hard"
    os.makedirs(out, exist_ok=True)
    for make in SCENES:
        s = make()
        path = os.path.join(out, s.name + ".unjam")
        write(path, s.text())
        print(path)
    for name, text in DAT.items():
        path = os.path.join(out, name)
        write(path, text)
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
