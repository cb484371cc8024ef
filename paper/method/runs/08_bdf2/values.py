#!/usr/bin/env python3
"""The values paper/method/08_bdf2.md reads from the kept BDF2 runs (run from this folder):
the wide one-cell case's height at 5 ms against the explicit run at 5e-8 s (kept in
../07_one_cell_wide_5ms/e5_exp5e-8), and the four cells' mean distance from the centreline at 50 ms
against four_cells_vs_disks' explicit run (paper/evidence/data/four_cells_vs_disks/kb1_explicit)."""
import csv
import glob
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))
H = 50e-6  # m, the wide channel's height


def rows(folder):
    r = [x for x in csv.reader(open(os.path.join(folder, "series.csv"))) if x and not x[0].startswith("#")]
    return [dict(zip(r[0], map(float, x))) for x in r[1:]]


def distance_at(folder, t):
    r = min(rows(folder), key=lambda x: abs(x["t"] - t))
    return sum(abs(r["cell%d_y" % b] - H / 2) for b in range(4)) / 4 * 1e6


ref = json.load(open(os.path.join(HERE, "../07_one_cell_wide_5ms/e5_exp5e-8/summary.json")))["cells"][0]["centroid"]
print("one cell, wide channel, 5 ms: height (um), off the explicit run at 5e-8 s (%.4f um), x1 off" % (ref[1] * 1e6))
for f in sorted(glob.glob(os.path.join(HERE, "one_cell_wide_*")), key=lambda f: -float(f.split("dt")[-1][:-2])):
    c = json.load(open(os.path.join(f, "summary.json")))["cells"][0]["centroid"]
    print("  %-34s %.4f %+.4f %+.4f" % (os.path.basename(f), c[1] * 1e6, (c[1] - ref[1]) * 1e6, (c[0] - ref[0]) * 1e6))
explicit = os.path.join(HERE, "../../../evidence/data/four_cells_vs_disks/kb1_explicit")
print("four cells: mean distance from the centreline at 50 ms (um); kb1_explicit %.4f" % distance_at(explicit, 0.05))
for f in sorted(glob.glob(os.path.join(HERE, "four_cells_*"))):
    print("  %-34s %.4f" % (os.path.basename(f), distance_at(f, 0.05)))
