#!/usr/bin/env python3
"""Where a run is about to blow up, from the state tables written before it (`swarf run --state-at`).

usage: state-anomalies.py STATES_DIR OUT_PREFIX [RADIUS_M]

In the last table: the particles that stand out (fastest, most compressed or stretched against the median density,
largest contact force, largest deviatoric stress), and the hotspot, the fastest particle's position. Then for every
table: a summary line, the rows of those particles (tracked by id), written to OUT_PREFIX-tracked.csv, and the rows
within RADIUS_M (default 1e-5) of the hotspot, to OUT_PREFIX-NNNNNN.csv. Standard library only: the GPU machine
has no numpy.
"""
import csv
import math
import os
import sys


def rows(path):
    with open(path) as f:
        r = csv.reader(f)
        head = next(r)
        yield head
        yield from r


def norm(row, cols):
    return math.sqrt(sum(float(row[k]) ** 2 for k in cols))


def main():
    states, prefix = sys.argv[1], sys.argv[2]
    radius = float(sys.argv[3]) if len(sys.argv) > 3 else 1e-5
    tables = sorted(n for n in os.listdir(states) if n.startswith("state_") and n.endswith(".csv"))
    if not tables:
        sys.exit("no state tables in %s" % states)
    it = rows(os.path.join(states, tables[-1]))
    head = next(it)
    col = {c: k for k, c in enumerate(head)}
    pos = [col[c] for c in ("x", "y", "z") if c in col]
    vel = [col[c] for c in ("vx", "vy", "vz") if c in col]
    fc = [col[c] for c in ("fcx", "fcy", "fcz", "ftx", "fty", "ftz") if c in col]
    dev = [col[c] for c in ("sxx", "sxy", "sxz", "syy", "syz", "szz") if c in col]
    last = [r for r in it if col.get("tool") is None or r[col["tool"]] == "0"]
    rho = sorted(float(r[col["rho"]]) for r in last)
    rho_med = rho[len(rho) // 2]
    scores = {
        "speed": lambda r: norm(r, vel),
        "density": lambda r: abs(float(r[col["rho"]]) / rho_med - 1.0),
        "contact": lambda r: norm(r, fc),
        "deviatoric": lambda r: norm(r, dev),
    }
    picked = {}
    print("last table %s: %d particles, median density %.6g" % (tables[-1], len(last), rho_med))
    for name, f in scores.items():
        top = sorted(last, key=f, reverse=True)[:12]
        print("largest %s:" % name)
        for r in top:
            picked[r[col["id"]]] = r
            print("  id %s %s %.4g at %s, v %s, rho %s, eps_pl %s" % (
                r[col["id"]], name, f(r), [r[k] for k in pos], [r[k] for k in vel], r[col["rho"]],
                r[col["eps_pl"]] if "eps_pl" in col else "-"))
    fastest = max(last, key=scores["speed"])
    hot = [float(fastest[k]) for k in pos]
    print("hotspot (fastest particle's position): %s" % hot)
    del last
    with open(prefix + "-tracked.csv", "w", newline="") as t:
        tw = csv.writer(t)
        tw.writerow(["table"] + head)
        for name in tables:
            it = rows(os.path.join(states, name))
            next(it)
            n, vmax, near = 0, 0.0, 0
            with open("%s-%s.csv" % (prefix, name[6:-4]), "w", newline="") as g:
                w = csv.writer(g)
                w.writerow(head)
                for r in it:
                    n += 1
                    vmax = max(vmax, norm(r, vel))
                    if r[col["id"]] in picked:
                        tw.writerow([name] + r)
                    if sum((float(r[k]) - c) ** 2 for k, c in zip(pos, hot)) <= radius * radius:
                        w.writerow(r)
                        near += 1
            print("%s: %d particles, |v| max %.4g m/s, %d within %g m of the hotspot" % (name, n, vmax, near, radius))


if __name__ == "__main__":
    main()
