#!/usr/bin/env python3
"""Writes two-flute-mill.obj: a straight two-flute end mill's body (klippel-constitutive.md §4.8: d = 200 µm),
in µm, axis along z from z = 0 (the end face) to z = 150, every face outward. Cross-section per tooth (period 180°):
the cutting edge at radius R; the rake face, leaning 5° forward (rake −5°), down to the flute bottom at R/2; the flute (30°);
its back rising to the next tooth's relief, which falls from R - 8 µm at the heel to R at the next edge over 150°
(the clearance). The teeth lead in +φ: turning the tool positively about +z (the scene's axis after placement)
cuts with the rake faces. Straight flutes (no helix), a sharp edge (the DIXI tool's r_c = 3 µm is below Δx)."""
import math

R, L = 100.0, 150.0
RELIEF, BODY, RAKE, FLUTE = 8.0, 150.0, 5.0, 30.0
ring = []  # (r, φ in degrees), φ increasing
for k in range(2):
    t = 180.0 * k
    # The flute: rake face from the edge (R at t) down to R/2, the bottom, the back up to the next relief.
    ring.append((R, t))
    ring.append((0.5 * R, t + RAKE))
    ring.append((0.5 * R, t + FLUTE - 3.0))
    heel = t + FLUTE
    # The relief: from the heel (R - RELIEF) to just behind the next edge (R), in 10° steps.
    n = 15
    for i in range(n):
        phi = heel + BODY * i / n
        ring.append((R - RELIEF * (1.0 - i / n), phi))
pts = [(r * math.cos(math.radians(p)), r * math.sin(math.radians(p))) for r, p in ring]
n = len(pts)
out = ["# a straight two-flute end mill, d = 200 um, 150 um long, in um (two-flute-mill.py)"]
for z in (0.0, L):
    out += ["v %.6f %.6f %.6f" % (x, y, z) for x, y in pts]
out += ["v 0 0 0", "v 0 0 %.6f" % L]
c0, c1 = 2 * n + 1, 2 * n + 2
for k in range(n):
    a, b = k + 1, (k + 1) % n + 1
    out.append("f %d %d %d" % (a, b, b + n))
    out.append("f %d %d %d" % (a, b + n, a + n))
    out.append("f %d %d %d" % (c0, b, a))
    out.append("f %d %d %d" % (c1, a + n, b + n))
open("two-flute-mill.obj", "w").write("\n".join(out) + "\n")
print(n, "profile points,", 4 * n, "triangles")
