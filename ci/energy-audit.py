#!/usr/bin/env python3
"""Energy audit of finished 2D cutting runs (docs/validation.md, "Energy audit of the cut").

For each run folder: the tool's work on the workpiece per unit depth, W = ∫ F_c dx_tool, by the trapezoid rule over
forces.csv's samples (F_c in N/mm, the tool's x offset in m; W in J/m), against the change of energy.csv's
`balance` = kinetic + elastic + plastic work + viscous dissipation (+ the cohesive work, the bonds' damping and the
damage's dissipation where the run has them). The half-sample estimates (every other sample) show the sampling
error. Runs whose forces.csv has the power columns (`tool_power_w`, `friction_power_w`, `normal_power_w`; swarf
writes them since the audit entered summary.json) also get the friction's and the penalty's works and W_p, the work
the particles received, W − W_friction − W_normal: booked/W_p is 1 where the solver conserves energy.

    python3 ci/energy-audit.py RUN_FOLDER...
"""
import csv
import sys


def trapezoid(rows, key, x=None):
    """∫ key d(x) over the rows (x: a column; None: time, from (t = 0, 0) as swarf's summary does)."""
    if x is None:
        rows = [{"time": "0", key: "0"}] + rows
        x = "time"
    return sum(0.5 * (float(a[key]) + float(b[key])) * (float(b[x]) - float(a[x])) for a, b in zip(rows, rows[1:]))


def main(folders):
    parts = ["kinetic", "elastic", "plastic_work", "viscous_dissipation", "cohesive_work", "bond_damping",
             "damage_dissipation"]
    for run in folders:
        rows = list(csv.DictReader(open(f"{run}/forces.csv")))
        energy = list(csv.DictReader(open(f"{run}/energy.csv")))
        first, last = energy[0], energy[-1]
        num = lambda row, k: float(row[k]) if row.get(k) not in (None, "", "NaN", "nan") else 0.0
        w = lambda r: 1e3 * trapezoid(r, "fc_n_per_mm", "tool_x")
        booked = num(last, "balance") - num(first, "balance")
        terms = ", ".join(f"{k} {num(last, k):.4g}" for k in parts if num(last, k) != 0.0)
        print(f"{run}: W {w(rows):.4g} J/m (halves {w(rows[0::2]):.4g}, {w(rows[1::2]):.4g}); booked "
              f"{booked:.4g} J/m ({terms}); booked/W {booked / w(rows):.3f}")
        if rows and "tool_power_w" in rows[0]:
            works = {k: [trapezoid(r, f"{k}_power_w") for r in (rows, rows[0::2], rows[1::2])]
                     for k in ("tool", "friction", "normal")}
            wp = [works["tool"][i] - works["friction"][i] - works["normal"][i] for i in range(3)]
            listed = "; ".join(f"{k} {v[0]:.4g} (halves {v[1]:.4g}, {v[2]:.4g})" for k, v in works.items())
            print(f"  powers integrated: {listed}; received W_p {wp[0]:.4g} (halves {wp[1]:.4g}, {wp[2]:.4g}); "
                  f"booked/W_p {booked / wp[0]:.3f} (halves {booked / wp[1]:.3f}, {booked / wp[2]:.3f})")


if __name__ == "__main__":
    main(sys.argv[1:])
