#!/usr/bin/env python3
"""Per-grain figures of a grinding-wheel run (cases/3d/grinding-wheel-*.toml) from its forces.csv: for each grain
(tool k; k = 1 has the unsuffixed columns) the time it touched the workpiece, its peak and mean force components
while touching, its impulse ∫|F| dt, and its accumulated Usui wear ∫ Ẇ dt (Ẇ the mean wear rate of the particles it
touches, forces.csv's wear_rate_m_per_s; samples without contact add nothing) and, robust to the single-sample spikes
of that mean (one particle pressed hard against the grain), the median rate times the contact time. Then the
means over the grains that touched, over those whose pass ended before the cut-off (complete passes), and the
largest count of grains touching at once. Only samples up to the cut-off count (default: all).
Usage: wheel-wear.py forces.csv [label] [cut-off time in s]"""
import csv
import math
import sys

path = sys.argv[1]
label = sys.argv[2] if len(sys.argv) > 2 else path
cut = float(sys.argv[3]) if len(sys.argv) > 3 else math.inf
every = list(csv.DictReader(open(path)))
ends_at = float(every[-1]["time"])
rows = [r for r in every if float(r["time"]) <= cut]
t = [float(r["time"]) for r in rows]
k = 1
grains = []
while True:
    sfx = "" if k == 1 else f"_t{k}"
    if f"fx_n{sfx}" not in rows[0]:
        break
    grains.append(sfx)
    k += 1

print(f"== {label}: {len(grains)} grains, {len(rows)} samples to t = {t[-1]:.4e} s")
print("grain | contact [us] | samples | peak Fx, Fy, Fz [N] | mean Fx, Fy, Fz in contact [N] | impulse [uN s] | "
      "wear [nm] | median rate x contact time [nm]")
touching_at = [0] * len(rows)
stats = []
for g, sfx in enumerate(grains, 1):
    f = [[float(r[c + sfx]) for c in ("fx_n", "fy_n", "fz_n")] for r in rows]
    n = [float(r["contacts" + sfx]) for r in rows]
    w = [float(r["wear_rate_m_per_s" + sfx]) for r in rows]
    on = [i for i in range(len(rows)) if n[i] > 0]
    if not on:
        print(f"{g} | - | 0 | - | - | 0 | 0 | 0")
        continue
    for i in on:
        touching_at[i] += 1
    dt = [t[i] - t[i - 1] if i > 0 else t[0] for i in range(len(rows))]
    wear = sum(w[i] * dt[i] for i in on if math.isfinite(w[i]))
    impulse = sum(math.sqrt(sum(c * c for c in f[i])) * dt[i] for i in on)
    peak = [max((f[i][c] for i in on), key=abs) for c in range(3)]
    mean = [sum(f[i][c] for i in on) / len(on) for c in range(3)]
    span = (t[on[0]], t[on[-1]])
    rates = sorted(w[i] for i in on if math.isfinite(w[i]))
    robust = rates[len(rates) // 2] * sum(dt[i] for i in on) if rates else 0.0
    # A pass is complete when the grain's last contact in the whole file lies before the cut-off.
    last = max(float(r["time"]) for r in every if float(r["contacts" + sfx]) > 0)
    stats.append((wear, impulse, robust, last < min(cut, ends_at) - (t[-1] - t[-2])))
    print(f"{g} | {span[0] * 1e6:.1f}-{span[1] * 1e6:.1f} | {len(on)} | {peak[0]:.3f}, {peak[1]:.3f}, {peak[2]:.3f} | "
          f"{mean[0]:.3f}, {mean[1]:.3f}, {mean[2]:.3f} | {impulse * 1e6:.3f} | {wear * 1e9:.1f} | {robust * 1e9:.1f}")


def means(which, s):
    m = len(s)
    if m:
        print(f"{label}, {which}: {m} grains; per grain: wear {sum(x[0] for x in s) / m * 1e6:.2f} um, median-rate wear "
              f"{sum(x[2] for x in s) / m * 1e6:.2f} um, impulse {sum(x[1] for x in s) / m * 1e6:.3f} uN s")


means("every grain that touched", stats)
means("complete passes", [x for x in stats if x[3]])
print(f"{label}: {len(stats)} of {len(grains)} grains touched, at most {max(touching_at)} at once")
