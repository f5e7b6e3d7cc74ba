#!/usr/bin/env python3
"""Writes grinding-wheel-{a,b,c}.toml: a segment of a grinding wheel with diamond grains in Pinto's patterns A, B and C
grinding Ti6Al4V, with blanking (roethlin-solver.md §7.10, "Full grinding wheel", thesis §7.6.3; issue 24).

The thesis' printed kinematics disagree with each other (the digest's [D] note: a 0.5 mm wheel, a tool feed of
1.8 m/s, one revolution while traversing L = 2 r, about 54 000 rpm and a cutting speed of about 280 m/s). They are
rebuilt here from the wheel, the pattern and the feed, keeping the feed and "one revolution per L = 2 r":

- wheel diameter 0.5 mm (r = 250 µm, the thesis' 5 mm scaled 1/10), axis along z;
- feed v_w = 1.8 m/s along +x; one revolution per 2 r of feed: n = 60 v_w/(2 r) = 216 000 rpm, so the grains'
  peripheral speed is v_s = 2π r n/60 = π v_w = 5.65 m/s (not 280 m/s, and not the printed 54 000 rpm);
- the wheel turns positively about +z: a grain at the bottom moves along +x, with the feed, and sweeps the engaged
  arc ahead of the wheel's centre upwards: up-grinding; relative to the workpiece a grain moves at v_s + v_w at the
  bottom;
- the pattern (Tab. 7.10, Pinto 2008) scaled by the wheel's 1/10: grains λ = Δx/10 apart along the circumference
  (rounded to a whole number per turn: A 8, B 16, C 31), lanes Δz/10 = 50 µm apart in z, lane j shifted by
  j Δz/(10 tan α) along the circumference, and each grain of a lane shifted Δz2/10 in z from the one before (a helix);
- the grain: the single-grain scene's diamond (cases/3d/tools/diamond-grain.k) at 1/20 of the file's µm, its flat
  face (about 15 µm across) outward, its longer side along the cutting direction;
- the depth of cut d = 10 µm (65 % of the flat face's 15 µm edge, the thesis' rule), the workpiece D = 3 d = 30 µm high,
  100 µm wide (two lanes), 400 µm long, Δx = 2.5 µm (d/4: the thesis' n_seed = 4);
- half a revolution (139 µs, 250 µm of feed), the wheel's centre from 80 µm before the workpiece's left face;
- the active box: from 50 µm behind the wheel's centre to 190 µm ahead of it (the engaged arc reaches
  √(2 r d) ≈ 71 µm ahead, and a front 120 µm ahead of that stands off as the single grain's had to), moving with
  the feed;
- Usui wear on every grain (Ψ 7.8e-9 1/Pa, ξ 2500 K, the thesis' constants), μ = 0.35, adiabatic, AV and XSPH,
  CFL 0.3 (the 3D cutting scenes' value).

Only the grains whose path meets the workpiece within the run are written (a tool that never meets it is refused).
The uncut chip of a grain, cutting what the grain before it in its lane left, is at most about
2 (λ v_w/v_s) √(d/(2 r)): 17.7, 8.8 and 4.6 µm for A, B and C, i.e. 7, 3.5 and 1.8 particle spacings.
forces.csv: the first grain's columns, then fx_n_tk … wear_rate_m_per_s_tk for grain k (the order of the
[[tool]] tables, each named in its comment)."""
import math

R = 250e-6  # wheel radius [m]
FEED = 1.8  # v_w [m/s]
RPM = 60.0 * FEED / (2.0 * R)
DEPTH, HEIGHT, WIDTH, LENGTH, DX = 10e-6, 30e-6, 100e-6, 400e-6, 2.5e-6
END = 0.5 * (2.0 * R) / FEED  # half a revolution: one revolution per 2r of feed
X0 = -80e-6  # the wheel's centre at t = 0
SCALE = 5e-8  # file µm -> m, 1/20
# The bottom face's centre of the grain turned -90° about x (tool frame, m): x 1.31-17.48, z -6.62-7.18 µm, y 33.5 µm.
G0 = (9.397e-6, 33.5e-6, 0.279e-6)
PATTERNS = {  # Tab. 7.10: Δx [m], Δz [m], Δz2 [m], α, at the thesis' wheel; scaled by 1/10 below
    "a": (2.0e-3, 0.5e-3, 3.2e-6, math.pi / 3),
    "b": (1.0e-3, 0.5e-3, 1.6e-6, math.pi / 3),
    "c": (0.5e-3, 0.5e-3, 0.8e-6, math.pi / 3),
}


def quat_mul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return (w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2)


def axis_angle(theta):
    """The grain's placement R_z(θ)·R_x(−90°) as one axis and angle (degrees)."""
    qx = (math.cos(-math.pi / 4), math.sin(-math.pi / 4), 0.0, 0.0)
    qz = (math.cos(theta / 2), 0.0, 0.0, math.sin(theta / 2))
    w, x, y, z = quat_mul(qz, qx)
    s = math.sqrt(x * x + y * y + z * z)
    return (x / s, y / s, z / s), math.degrees(2.0 * math.atan2(s, w))


def rz(theta, v):
    c, s = math.cos(theta), math.sin(theta)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1], v[2])


def meets(theta0, z):
    """Whether the grain's flat face, turning with the wheel from θ0 (from the bottom), dips a spacing below the
    workpiece's top inside it before the end (sampled every 0.02 µs: 0.15 µm of the grain's travel)."""
    omega = 2.0 * math.pi * RPM / 60.0
    if abs(z) > WIDTH / 2 + 20e-6:
        return False
    for k in range(int(END / 2e-8) + 1):
        t = k * 2e-8
        th = theta0 + omega * t
        cx = X0 + FEED * t
        x, y = cx + R * math.sin(th), HEIGHT - DEPTH + R * (1.0 - math.cos(th))
        # The face a spacing below the top, within the workpiece's length: it holds particles then.
        if y < HEIGHT - DX and 0.0 < x < LENGTH:
            return True
    return False


def grains(p):
    dx, dz, dz2, alpha = p[0] / 10, p[1] / 10, p[2] / 10, p[3]
    n = round(2.0 * math.pi * R / dx)
    out = []
    for j, zl in enumerate((-dz / 2, dz / 2)):
        shift = j * dz / math.tan(alpha) / R
        for i in range(n):
            theta = (2.0 * math.pi * i / n + shift) % (2.0 * math.pi)
            z = zl + i * dz2
            if meets(theta, z):
                out.append((j, i, theta, z))
    return n, out


def tool(j, i, theta, z):
    centre = (X0, HEIGHT - DEPTH + R, z)
    rel = rz(theta, (-G0[0], -R - G0[1], -G0[2]))
    pos = tuple(centre[k] + rel[k] for k in range(3))
    axis, angle = axis_angle(theta)
    c = tuple(centre[k] - pos[k] for k in range(3))
    f = lambda v: "[%.6e, %.6e, %.6e]" % v
    return f"""# lane {j}, grain {i}: {math.degrees(theta):.2f}° from the bottom at t = 0, z = {z * 1e6:.2f} µm
[[tool]]
mesh = {{ file = "tools/diamond-grain.k", scale = {SCALE}, axis = {f(axis)}, angle = {angle:.6f} }}
position = {f(pos)}
velocity = [{FEED}, 0.0, 0.0]
rotation = {{ axis = [0.0, 0.0, 1.0], centre = {f(c)}, rpm = {RPM:.1f} }}
friction = 0.35
usui = {{ psi = 7.8e-9, xi = 2500.0 }}
"""


for name, p in PATTERNS.items():
    n, gs = grains(p)
    head = f"""# Grinding wheel segment, pattern {name.upper()} (generated by grinding-wheel.py: the kinematics, the pattern and the
# choices are in its docstring; roethlin-solver.md §7.10, thesis §7.6.3; issue 24). Wheel d = 0.5 mm at
# {RPM:.0f} rpm (v_s = {2 * math.pi * R * RPM / 60:.2f} m/s), feed {FEED} m/s along +x, up-grinding, d = 10 µm; {n} grains per
# turn in each of two lanes, {len(gs)} of which meet the workpiece in the half revolution run. Ti6Al4V, Δx = 2.5 µm,
# blanking. Röthlin (Tab. 7.11): the mean accumulated Usui wear per grain falls from A to B to C.

name = "grinding-wheel-{name}"
dim = 3

[discretisation]
dx = {DX}
h_over_dx = 1.7

[material]
name = "Ti6Al4V-V0060-DE-mu035"

[physics]
plasticity = true
plastic_heating = true
initial_temperature = 300.0

[[body]]
name = "workpiece"
shape = "box"
min = [0.0, 0.0, {-WIDTH / 2:.6e}]
max = [{LENGTH:.6e}, {HEIGHT:.6e}, {WIDTH / 2:.6e}]

[[boundary]]
kind = "fixed"
body = "workpiece"
min = [-1.0, -1.0, -1.0]
max = [1.0, {DX:.6e}, 1.0]

# The active box moves with the feed (the grains' translation): 50 µm behind the wheel's centre to 190 µm ahead.
[blanking]
min = [{X0 - 50e-6:.6e}, -1.0, -1.0]
max = [{X0 + 190e-6:.6e}, 1.0, 1.0]

[stabilisation]
artificial_viscosity = {{ alpha = 1.0, beta = 1.0, eta = 0.1 }}
xsph = {{ epsilon = 0.5 }}

[time]
end = {END:.6e}
cfl = 0.3

[output]
every = {END / 40:.6e}

"""
    with open(f"grinding-wheel-{name}.toml", "w") as out:
        out.write(head + "\n".join(tool(*g) for g in gs))
    print(name, n, "per turn,", len(gs), "grains meet the workpiece")
