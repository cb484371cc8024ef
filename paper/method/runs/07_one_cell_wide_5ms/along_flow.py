#!/usr/bin/env python3
"""The along-flow error of the wide one-cell runs at 5 ms as the height error carried by the shear
(paper/method/07_second_order_in_time.md, "Along the flow").

A cell displaced by dx2(t) across a shear flow moves along it faster by (du/dx2) dx2, so a run whose
height differs from the reference's by dx2(t) gathers an x1 difference of about

    dx1(T) ~ integral_0^T (du/dx2)(x2_ref(t)) dx2(t) dt,   du/dx2 = 6 U(t) (H - 2 x2) / H^2,

with U(t) the reference run's mean velocity (the cell-free profile's shape; H = 50 um). This script evaluates
that integral by the trapezoidal rule on the runs' series (every 0.1 ms) and prints it beside the
measured dx1 at 5 ms. Each folder holds series.csv and summary.json of one run (the command and
code id that made it are in summary.json).

Usage: python3 along_flow.py   (from any directory; reads the folders beside this script)
"""
import csv
import os

H = 50e-6  # m, the channel's height (paper/method/scenes/one_cell_wide.toml)
HERE = os.path.dirname(os.path.abspath(__file__))
REFERENCE = "e5_exp5e-8"  # the explicit coupling at 5e-8 s
RUNS = ["e5_exp8e-8", "x_lie3.125_q3_inc", "x_lie6.25_q5_inc", "x_lie12.5_q10_inc", "x_lie25_q20_inc",
        "e5_sie3.125e-6", "e5_sie6.25e-6", "e5_sie1.25e-5", "e5_sie2.5e-5"]


def series(run):
    rows = [r for r in csv.reader(open(os.path.join(HERE, run, "series.csv"))) if r and not r[0].startswith("#")]
    return [dict(zip(rows[0], map(float, r))) for r in rows[1:]]


def main():
    ref = series(REFERENCE)
    print(f"against {REFERENCE} at 5 ms (um): dx2, dx1 measured, dx1 from the shear integral")
    for run in RUNS:
        s = series(run)
        if [a["t"] for a in s] != [a["t"] for a in ref]:
            raise SystemExit(f"{run}: its samples are not at the reference's times")
        integral = 0.0
        for k in range(1, len(ref)):
            dt = ref[k]["t"] - ref[k - 1]["t"]
            for a, b in ((ref[k - 1], s[k - 1]), (ref[k], s[k])):
                shear = 6 * a["mean_velocity"] * (H - 2 * a["cell0_y"]) / H**2
                integral += 0.5 * dt * shear * (b["cell0_y"] - a["cell0_y"])
        dx1 = s[-1]["cell0_x"] - ref[-1]["cell0_x"]
        dx2 = s[-1]["cell0_y"] - ref[-1]["cell0_y"]
        print(f"{run:20s} {dx2 * 1e6:+8.4f} {dx1 * 1e6:+8.3f} {integral * 1e6:+8.3f}")


if __name__ == "__main__":
    main()
