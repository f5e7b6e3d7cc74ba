#!/usr/bin/env python3
"""Energy audit of finished 2D cutting runs (docs/validation.md, "Energy audit of the cut").

For each run folder: the tool's work on the workpiece per unit depth, W = ∫ F_c dx_tool, by the trapezoid rule over
forces.csv's samples (F_c in N/mm, the tool's x offset in m; W in J/m), against energy.csv's last row: `balance`
= kinetic + elastic + plastic work + viscous dissipation (+ the cohesive work, the bonds' damping and the damage's
dissipation where the run has them). Nothing else works on the workpiece (fixed rows do no work), and the tool's
friction and contact damping can only take energy out of it, so booked/W > 1 is energy the discretisation created.
The half-sample estimates W_even, W_odd (every other sample) show the sampling error of W.

    python3 ci/energy-audit.py RUN_FOLDER...
"""
import csv
import sys


def tool_work(rows):
    return sum(0.5 * (float(a["fc_n_per_mm"]) + float(b["fc_n_per_mm"])) * 1e3 * (float(b["tool_x"]) - float(a["tool_x"]))
               for a, b in zip(rows, rows[1:]))


def main(folders):
    parts = ["kinetic", "elastic", "plastic_work", "viscous_dissipation", "cohesive_work", "bond_damping",
             "damage_dissipation"]
    for run in folders:
        rows = list(csv.DictReader(open(f"{run}/forces.csv")))
        last = list(csv.DictReader(open(f"{run}/energy.csv")))[-1]
        num = lambda k: float(last[k]) if last.get(k) not in (None, "", "NaN") else 0.0
        w = tool_work(rows)
        booked = num("balance")
        terms = ", ".join(f"{k} {num(k):.4g}" for k in parts if num(k) != 0.0)
        print(f"{run}: W {w:.4g} J/m (halves {tool_work(rows[0::2]):.4g}, {tool_work(rows[1::2]):.4g}); booked "
              f"{booked:.4g} J/m ({terms}); booked/W {booked / w:.3f}")


if __name__ == "__main__":
    main(sys.argv[1:])
