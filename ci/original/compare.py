#!/usr/bin/env python3
"""Compares swarf with the original 2D GPU code (iwf-inspire/mfree_iwf-ul_cut_gpu, run by ci/original/run-original.sh).
Standard library only. docs/original-code.md describes the files; in short:

  states   per-field differences of the particle state after given steps (default: every step both sides have):
           compare.py states --orig original-dumps.tar.gz --swarf DIR [--steps 1,10,100,3000] [--json out.json]
  forces   means and standard deviations of F_c and F_f over a window of cut distance, in N/mm:
           compare.py forces --orig original-cut.tar.gz [--swarf runs/reference-cut/forces.csv] [--window 0.50,0.69]
  selftest builds small synthetic inputs and checks both commands (no GPU, no files needed)

--orig takes the .tar.gz that run-original.sh writes (join split parts first: cat X.tar.gz.part* > X.tar.gz), or a
folder holding its contents, or (forces) a forces.csv.

The original runs the reference cut in "bomb units" (g, cm, µs; stress in Mbar = 1e11 Pa): this script converts
its numbers to SI. swarf's side is SI.

swarf's state files (what `states` expects in --swarf DIR): one CSV per step, named state_NNNNNN.csv (NNNNNN =
steps completed, zero-padded to 6), with a header row; columns in any order, extra columns ignored, SI units:
  x0, y0            initial position [m] (the key: particles are matched by their initial position)
  x, y [m]; vx, vy [m/s]; rho [kg/m^3]; sxx, sxy, syy, szz [Pa] (the deviatoric stress S, szz out of plane);
  T [K]; eps_pl [-]; fcx, fcy, ftx, fty [N per m of depth] (the contact normal and friction force on the
  particle, the f_c and f_t of the next step's momentum balance)
  tool (optional, default 0): 1 for the tool's thermal-only particles, which are compared only with --tool
Any of the field columns may be missing (that field is then skipped). Initial positions are aligned by
subtracting each side's smallest workpiece x0 and y0 (the original's workpiece starts at (0.05 mm, 0.3 mm), swarf's
reference-cut at (0, 0)), or by --offset DX,DY [m] (swarf = original + offset), then matched to within a quarter
of the particle spacing. Both runs must use the same time step: the original's is in meta.json (dt, µs; 1.44734 ns
for the reference cut, from its own formula 0.5 h/(c0 + √v_tool)); run swarf with --set time.dt=<that in s>.
The tool first touches the workpiece at step 7737: before that both codes hold the workpiece at rest, and the
state comparison is only meaningful with swarf's tool placed as the original's (docs/original-code.md).
"""

import argparse
import csv
import io
import json
import math
import os
import statistics
import sys
import tarfile
import tempfile

# Code units of the reference cut -> SI.
CM = 1e-2  # m
US = 1e-6  # s
TO_SI = {
    "x0": CM, "y0": CM, "x": CM, "y": CM,
    "vx": CM / US, "vy": CM / US,                       # cm/µs = 1e4 m/s
    "rho": 1e3,                                          # g/cm³ -> kg/m³
    "p": 1e11, "sxx": 1e11, "sxy": 1e11, "syy": 1e11, "szz": 1e11,  # Mbar -> Pa
    "T": 1.0, "eps_pl": 1.0, "eps_pl_dot": 1.0 / US,
    # force per unit depth: g·cm/µs² per cm of depth = 1e7 N / 1e-2 m = 1e9 N/m
    "fcx": 1e9, "fcy": 1e9, "ftx": 1e9, "fty": 1e9,
    "h": CM,
}
FORCE_TO_N_PER_MM = 1e6  # g·cm/µs² per cm of depth -> N per mm of depth
FIELDS = ["x", "y", "vx", "vy", "rho", "sxx", "sxy", "syy", "szz", "T", "eps_pl", "fcx", "fcy", "ftx", "fty"]
# The scale of a field's difference: its largest change from the step-0 value (displacement, density change,
# temperature rise), or its largest magnitude for fields that start at zero.
CHANGE_FROM = {"x": "x0", "y": "y0"}


class Source:
    """A folder, a .tar.gz, or a single file, read by base name."""

    def __init__(self, path):
        self.path = path
        self.tar = None
        if os.path.isfile(path) and (path.endswith(".tar.gz") or path.endswith(".tgz")):
            self.tar = tarfile.open(path)
            self.members = {os.path.basename(m.name): m for m in self.tar.getmembers() if m.isfile()}

    def has(self, name):
        if self.tar:
            return name in self.members
        if os.path.isdir(self.path):
            return any(name in files for _, _, files in os.walk(self.path))
        return os.path.basename(self.path) == name

    def text(self, name):
        if self.tar:
            return self.tar.extractfile(self.members[name]).read().decode()
        if os.path.isdir(self.path):
            for root, _, files in os.walk(self.path):
                if name in files:
                    with open(os.path.join(root, name)) as f:
                        return f.read()
            raise FileNotFoundError(f"{name} not in {self.path}")
        with open(self.path) as f:
            return f.read()

    def meta(self):
        return json.loads(self.text("meta.json")) if self.has("meta.json") else {}


def _names(path):
    return [f for _, _, files in os.walk(path) for f in files] if os.path.isdir(path) else [os.path.basename(path)]


def read_csv(text):
    rows = list(csv.DictReader(io.StringIO(text)))
    out = []
    for r in rows:
        d = {}
        for k, v in r.items():
            k = k.strip()
            try:
                d[k] = float(v) if v not in ("", None) else math.nan
            except ValueError:
                d[k] = v
        out.append(d)
    return out


def original_state(src, step):
    rows = read_csv(src.text(f"state_{step:06d}.csv"))
    for r in rows:
        for k, f in TO_SI.items():
            if k in r:
                r[k] *= f
    return rows


def swarf_state(src, step):
    return read_csv(src.text(f"state_{step:06d}.csv"))


def match(orig, swarf, spacing, offset, use_tool):
    """Pairs (original row, swarf row) by initial position; returns pairs and counts of the unmatched."""
    def keep(r):
        return use_tool or r.get("tool", 0) != 1

    o_rows = [r for r in orig if keep(r)]
    s_rows = [r for r in swarf if keep(r)]
    if offset is None:
        def lo(rows):
            wp = [r for r in rows if r.get("tool", 0) != 1] or rows
            return min(r["x0"] for r in wp), min(r["y0"] for r in wp)
        (ox, oy), (sx, sy) = lo(o_rows), lo(s_rows)
        offset = (sx - ox, sy - oy)
    q = 0.25 * spacing
    grid = {}
    for r in s_rows:
        grid.setdefault((round(r["x0"] / q), round(r["y0"] / q)), []).append(r)
    pairs, missing = [], 0
    for r in o_rows:
        x, y = r["x0"] + offset[0], r["y0"] + offset[1]
        kx, ky = round(x / q), round(y / q)
        best, bd = None, q
        for i in (kx - 1, kx, kx + 1):
            for j in (ky - 1, ky, ky + 1):
                for c in grid.get((i, j), []):
                    d = math.hypot(c["x0"] - x, c["y0"] - y)
                    if d < bd:
                        best, bd = c, d
        if best is None:
            missing += 1
        else:
            pairs.append((r, best))
    return pairs, missing, len(s_rows) - len(pairs), offset


def field_stats(pairs, field, base, offset):
    """max |Δ|, rms Δ, scale, and where the max is, for one field over the matched pairs."""
    diffs, scale, worst = [], 0.0, None
    for (o, s) in pairs:
        if field not in s or field not in o or math.isnan(s[field]):
            return None
        a, b = o[field], s[field]
        if field == "x":
            a, b = a + offset[0], b
        if field == "y":
            a, b = a + offset[1], b
        d = b - a
        diffs.append(d)
        ref = base.get((o["id"], field), 0.0) if field not in CHANGE_FROM else o[CHANGE_FROM[field]]
        scale = max(scale, abs(o[field] - ref))
        if worst is None or abs(d) > abs(worst[0]):
            worst = (d, o)
    if not diffs:
        return None
    m = max(abs(d) for d in diffs)
    rms = math.sqrt(sum(d * d for d in diffs) / len(diffs))
    return {"max_abs": m, "rms": rms, "scale": scale, "rel": m / scale if scale > 0 else (0.0 if m == 0 else math.inf),
            "at_id": int(worst[1]["id"]), "at_x0_um": worst[1]["x0"] * 1e6, "at_y0_um": worst[1]["y0"] * 1e6}


def cmd_states(a):
    osrc, ssrc = Source(a.orig), Source(a.swarf)
    meta = osrc.meta()
    h = meta.get("h")
    spacing = a.spacing or (h * CM / 1.5 if h else 1.0344827586e-5)
    offset = tuple(float(v) for v in a.offset.split(",")) if a.offset else None
    base = {}
    if osrc.has("state_000000.csv"):
        for r in original_state(osrc, 0):
            for f in FIELDS:
                if f in r:
                    base[(r["id"], f)] = r[f]
    dt = meta.get("dt")
    print(f"original: {a.orig}  dt = {dt} us = {dt * US if dt else float('nan'):.6e} s, spacing {spacing * 1e6:.3f} um")
    print(f"swarf:    {a.swarf}")
    sm = ssrc.meta()
    if dt and sm.get("dt") and abs(sm["dt"] - dt * US) > 1e-6 * dt * US:
        print(f"WARNING: time steps differ: original {dt * US:.9e} s, swarf {sm['dt']:.9e} s")
    report = {"dt_s": dt * US if dt else None, "steps": {}}
    if a.steps == "all":
        names = [n for n in (osrc.members if osrc.tar else _names(a.orig)) if n.startswith("state_")]
        steps = sorted(int(n[6:12]) for n in names if ssrc.has(n))
    else:
        steps = [int(s) for s in a.steps.split(",")]
    for step in steps:
        if not osrc.has(f"state_{step:06d}.csv") or not ssrc.has(f"state_{step:06d}.csv"):
            print(f"\nstep {step}: state_{step:06d}.csv missing on one side, skipped")
            continue
        pairs, miss_o, miss_s, off = match(original_state(osrc, step), swarf_state(ssrc, step), spacing, offset, a.tool)
        print(f"\nafter {step} steps: {len(pairs)} particles matched ({miss_o} original, {miss_s} swarf unmatched), "
              f"offset swarf - original = ({off[0] * 1e6:.3f}, {off[1] * 1e6:.3f}) um")
        print(f"  {'field':7s} {'max|diff|':>12s} {'rms diff':>12s} {'scale':>12s} {'max rel':>10s}  where (x0, y0 um, id)")
        rep = {"matched": len(pairs), "unmatched_original": miss_o, "unmatched_swarf": miss_s, "fields": {}}
        for f in FIELDS:
            st = field_stats(pairs, f, base, off)
            if st is None:
                print(f"  {f:7s} (not in both files)")
                continue
            rep["fields"][f] = st
            print(f"  {f:7s} {st['max_abs']:12.4e} {st['rms']:12.4e} {st['scale']:12.4e} {st['rel']:10.3e}  "
                  f"({st['at_x0_um']:.2f}, {st['at_y0_um']:.2f}, {st['at_id']})")
        report["steps"][step] = rep
    print("\nscale: the field's largest change from step 0 over the particles (x, y: the largest displacement);"
          " units SI (m, m/s, kg/m^3, Pa, K, N/m)")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(report, f, indent=1)
    return 0


def window_stats(dist_mm, values, lo, hi):
    sel = [v for d, v in zip(dist_mm, values) if lo <= d <= hi and not math.isnan(v)]
    if not sel:
        return {"n": 0, "mean": math.nan, "sd": math.nan}
    return {"n": len(sel), "mean": statistics.fmean(sel), "sd": statistics.stdev(sel) if len(sel) > 1 else 0.0}


def original_forces(path, speed):
    src = Source(path)
    rows = read_csv(src.text("forces.csv"))
    meta = src.meta()
    if speed is None:
        speed = (meta.get("tool_velocity") or [1.1666666e-4])[0]  # cm/µs; 70 m/min
    dist = [r["time"] * speed * 10.0 for r in rows]  # µs · cm/µs -> cm -> mm; the tool starts at the workpiece
    fc = [r["fx"] * FORCE_TO_N_PER_MM for r in rows]
    ff = [-r["fy"] * FORCE_TO_N_PER_MM for r in rows]  # feed force: −F·e_y, positive in a normal cut (swarf's sign)
    return dist, fc, ff, {"speed_m_per_s": speed * CM / US, "samples": len(rows)}


def swarf_forces(path, speed):
    src = Source(path)
    rows = read_csv(src.text("forces.csv"))
    if "tool_x" in rows[0] and speed is None:
        x0 = rows[0]["tool_x"]
        dist = [(r["tool_x"] - x0) * 1e3 for r in rows]  # the tool's travel [m] -> mm
    else:
        if speed is None:
            sys.exit("compare.py: swarf forces.csv has no tool_x: give --swarf-speed (m/s)")
        dist = [r["time"] * speed * 1e3 for r in rows]
    return dist, [r["fc_n_per_mm"] for r in rows], [r["ff_n_per_mm"] for r in rows], {"samples": len(rows)}


def cmd_forces(a):
    lo, hi = (float(v) for v in a.window.split(","))
    out = {"window_mm": [lo, hi]}
    sides = [("original", original_forces(a.orig, a.orig_speed))]
    if a.swarf:
        sides.append(("swarf", swarf_forces(a.swarf, a.swarf_speed)))
    print(f"forces over {lo:.3f}..{hi:.3f} mm of cut, N per mm of width (mean ± sd of the samples in the window)")
    for name, (dist, fc, ff, info) in sides:
        c, f = window_stats(dist, fc, lo, hi), window_stats(dist, ff, lo, hi)
        out[name] = {"fc": c, "ff": f, **info, "cut_mm_max": max(dist) if dist else 0.0}
        print(f"  {name:9s} F_c = {c['mean']:8.2f} ± {c['sd']:6.2f}   F_f = {f['mean']:8.2f} ± {f['sd']:6.2f}   "
              f"({c['n']} samples, trace to {out[name]['cut_mm_max']:.3f} mm)")
    if a.swarf:
        o, s = out["original"], out["swarf"]
        for k, label in (("fc", "F_c"), ("ff", "F_f")):
            d = s[k]["mean"] - o[k]["mean"]
            print(f"  swarf - original: {label} {d:+.2f} N/mm ({100 * d / o[k]['mean']:+.1f} %)")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=1)
    return 0


def cmd_selftest(_a):
    """Synthetic original (code units) and swarf (SI) files that differ by known amounts."""
    with tempfile.TemporaryDirectory() as d:
        od, sd = os.path.join(d, "orig"), os.path.join(d, "swarf")
        os.makedirs(os.path.join(od, "dumps"))
        os.makedirs(sd)
        dx = 0.03 / 29
        json.dump({"dt": 1.447342e-3, "h": 1.5 * dx, "tool_velocity": [1.16666666e-4, 0.0]},
                  open(os.path.join(od, "meta.json"), "w"))
        cols = ["id", "x0", "y0", "tool", "x", "y", "vx", "vy", "rho", "sxx", "sxy", "syy", "szz", "T", "eps_pl",
                "fcx", "fcy", "ftx", "fty"]
        for step in (0, 1):
            with open(os.path.join(od, "dumps", f"state_{step:06d}.csv"), "w") as fo, \
                    open(os.path.join(sd, f"state_{step:06d}.csv"), "w") as fs:
                fo.write(",".join(cols) + "\n")
                fs.write(",".join(cols[1:]) + "\n")
                k = 0
                for i in range(4):
                    for j in range(3):
                        x0, y0 = 0.005 + i * dx, 0.03 + j * dx
                        u = 1e-6 * step * (i + 1)
                        o = [k, x0, y0, 0, x0 + u, y0, 1e-4 * step, 0, 4.43 + 1e-4 * step, 1e-4 * step, 0, 0, 0,
                             300 + step, 0.0, 0, 0, 0, 0]
                        s = [o[1] * CM - 5e-4, o[2] * CM - 3e-4, 0, (x0 + u * 1.01) * CM - 5e-4, y0 * CM - 3e-4,
                             1e-4 * step * 1e4, 0, (4.43 + 1e-4 * step) * 1e3, 1e-4 * step * 1e11, 0, 0, 0,
                             300 + step, 0.0, 0, 0, 0, 0]
                        fo.write(",".join(repr(v) for v in o) + "\n")
                        fs.write(",".join(repr(v) for v in s) + "\n")
                        k += 1
        with open(os.path.join(od, "forces.csv"), "w") as f:
            f.write("step,time,fx,fy\n")
            for n in range(0, 700):
                t = n * 10.0  # µs
                f.write(f"{n},{t},{1.5e-4},{-0.8e-4}\n")
        with open(os.path.join(sd, "forces.csv"), "w") as f:
            f.write("time,step,fc_n_per_mm,ff_n_per_mm,contacts,chip_thickness_um,wear_rate_m_per_s,tool_x\n")
            for n in range(0, 700):
                t = n * 10.0e-6
                f.write(f"{t},{n},160,75,10,100,nan,{t * 1.1666666}\n")
        ns = argparse.Namespace(orig=od, swarf=sd, steps="all", json=os.path.join(d, "s.json"), offset=None,
                                spacing=None, tool=False)
        cmd_states(ns)
        rep = json.load(open(ns.json))["steps"]["1"]["fields"]
        assert rep["x"]["rel"] > 0.009 and rep["x"]["rel"] < 0.011, rep["x"]
        assert rep["rho"]["max_abs"] < 1e-9 and rep["sxx"]["rel"] < 1e-9 and rep["vx"]["max_abs"] < 1e-9, rep
        nf = argparse.Namespace(orig=od, swarf=sd, window="0.50,0.69", orig_speed=None, swarf_speed=None,
                                json=os.path.join(d, "f.json"))
        cmd_forces(nf)
        fr = json.load(open(nf.json))
        assert abs(fr["original"]["fc"]["mean"] - 150) < 1e-9 and abs(fr["original"]["ff"]["mean"] - 80) < 1e-9, fr
        assert abs(fr["swarf"]["fc"]["mean"] - 160) < 1e-9 and fr["swarf"]["fc"]["n"] > 0, fr
    print("\nselftest: 1 passed, 0 failed")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("states", help="per-field differences of the particle state")
    s.add_argument("--orig", required=True, help="original-dumps.tar.gz or its folder")
    s.add_argument("--swarf", required=True, help="folder (or .tar.gz) with swarf's state_NNNNNN.csv")
    s.add_argument("--steps", default="all", help="comma-separated steps, or all (default): every state both have")
    s.add_argument("--offset", help="DX,DY [m]: swarf initial position = original + offset (default: align minima)")
    s.add_argument("--spacing", type=float, help="particle spacing [m] (default: from the original's h/1.5)")
    s.add_argument("--tool", action="store_true", help="also compare the tool's thermal particles")
    s.add_argument("--json")
    s.set_defaults(fn=cmd_states)
    f = sub.add_parser("forces", help="F_c, F_f over a window of cut distance")
    f.add_argument("--orig", required=True, help="original-cut.tar.gz, its folder, or a forces.csv")
    f.add_argument("--swarf", help="swarf's forces.csv or its run folder")
    f.add_argument("--window", default="0.50,0.69", help="cut distance window in mm (default 0.50,0.69)")
    f.add_argument("--orig-speed", type=float, help="the original's tool speed in cm/us (default: meta.json)")
    f.add_argument("--swarf-speed", type=float, help="swarf's cutting speed in m/s (only without tool_x)")
    f.add_argument("--json")
    f.set_defaults(fn=cmd_forces)
    t = sub.add_parser("selftest", help="check this script on synthetic data")
    t.set_defaults(fn=cmd_selftest)
    a = ap.parse_args()
    sys.exit(a.fn(a))


if __name__ == "__main__":
    main()
