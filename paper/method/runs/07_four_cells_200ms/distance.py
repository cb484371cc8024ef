#!/usr/bin/env python3
"""The four cells' mean distance from the centreline (um) of four_cells_vs_disks runs over the last
millisecond of the run (the mean of the samples at t >= t_end - 1 ms, as the experiment's rows
read it), from each run's series.csv (paper/method/07_second_order_in_time.md, "Four cells to
200 ms"). The kept series are thinned:
the first sample of each millisecond, the two around 50 ms and every sample of the last millisecond.

Usage: python3 distance.py FOLDER...   (each holding a run's series.csv; here: python3 distance.py */)
"""
import csv
import os
import sys

H = 50e-6  # m, the wide channel's height


def series(folder):
    rows = [r for r in csv.reader(open(os.path.join(folder, "series.csv"))) if r and not r[0].startswith("#")]
    return [dict(zip(rows[0], map(float, r))) for r in rows[1:]]


def distance(row):
    return sum(abs(row["cell%d_y" % b] - H / 2) for b in range(4)) / 4


def last_ms(rows):
    t_end = rows[-1]["t"]
    window = [distance(r) for r in rows if r["t"] >= t_end - 1e-3 - 1e-12]
    return sum(window) / len(window)


print("%-40s %10s %12s" % ("run", "t_end_ms", "last_ms_um"))
for folder in sys.argv[1:]:
    rows = series(folder)
    print("%-40s %10.3f %12.4f" % (os.path.basename(folder.rstrip("/")), rows[-1]["t"] * 1e3, last_ms(rows) * 1e6))
