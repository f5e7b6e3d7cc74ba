#!/usr/bin/env python3
"""Checks a swarf HDF5 particle run (host/output/hdf5.rs) with h5py, independently of the Rust code.

    python3 ci/check-hdf5.py runs/rings/particles.h5 [--frames N] [--quiet]

Opens the run file, follows its external links to every frame, and checks:
  - root attributes format = "swarf-particles", version = 1, frames = the number of members of /frames;
  - every frame /frames/NNNNN (names 00000, 00001, ... without gaps) resolves, with
    points of shape (n, 3), float, all finite; connectivity = 0 .. n-1;
    every other dataset of first dimension n; every float dataset finite;
    a finite attribute time, non-decreasing from frame to frame;
  - the .xmf beside the run file, if there, names the same number of frames (or one fewer: it is rewritten
    after the run file) with the same times.
Prints a summary; exits 0 if every check passed, 1 if one failed, 2 if the file cannot be read at all.
Needs h5py and numpy (pip install h5py).
"""

import argparse
import math
import os
import re
import sys

try:
    import h5py
    import numpy as np
except ImportError as e:  # pragma: no cover - a CI set-up error, reported plainly
    print(f"check-hdf5: {e}; install with: pip install h5py", file=sys.stderr)
    sys.exit(2)

FORMAT = "swarf-particles"
VERSION = 1
ROWS = 1 << 20  # rows read at a time, so that any frame size is checked in bounded memory


def as_str(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def dtype_name(ds):
    kind = {"f": "f", "u": "u", "i": "i"}.get(ds.dtype.kind, ds.dtype.kind)
    comps = "" if ds.ndim == 1 else "x" + "x".join(str(d) for d in ds.shape[1:])
    return f"{kind}{8 * ds.dtype.itemsize}{comps}"


def non_finite(ds):
    """Number of non-finite values of a float dataset, read ROWS rows at a time."""
    bad = 0
    for start in range(0, ds.shape[0], ROWS):
        bad += int(np.count_nonzero(~np.isfinite(ds[start : start + ROWS])))
    return bad


def check_connectivity(ds, n):
    for start in range(0, n, ROWS):
        block = ds[start : start + ROWS]
        if not np.array_equal(block, np.arange(start, start + len(block), dtype=block.dtype)):
            return False
    return True


def xmf_times(path):
    text = open(path, encoding="utf-8").read()
    grids = re.findall(r'<Grid[^>]*GridType="Uniform"[^>]*>\s*<Time Value="([^"]*)"', text)
    return [float(t) for t in grids]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run", help="the run file, e.g. runs/rings/particles.h5")
    ap.add_argument("--frames", type=int, help="fail unless the run has exactly this many frames")
    ap.add_argument("--quiet", action="store_true", help="print only failures and the summary line")
    args = ap.parse_args()

    errors = []

    def fail(msg):
        errors.append(msg)
        print(f"FAIL {msg}")

    try:
        f = h5py.File(args.run, "r")
    except OSError as e:
        print(f"check-hdf5: {args.run}: cannot open: {e}", file=sys.stderr)
        return 2

    with f:
        fmt = as_str(f.attrs.get("format", ""))
        version = f.attrs.get("version")
        if fmt != FORMAT:
            fail(f"root attribute format is {fmt!r}, expected {FORMAT!r}")
        if version != VERSION:
            fail(f"root attribute version is {version!r}, expected {VERSION}")
        if "frames" not in f:
            fail("no group /frames")
            names = []
        else:
            names = sorted(f["frames"].keys())
        count = f.attrs.get("frames")
        if count is None or int(count) != len(names):
            fail(f"root attribute frames = {count!r}, but /frames has {len(names)} members")
        # Frames are numbered without gaps (more digits past 99999, so compare as numbers), from 00000 in a run
        # file; a frame file (in the run's NAME.frames folder) holds the one frame of its own number.
        frame_file = os.path.basename(os.path.dirname(os.path.abspath(args.run))).endswith(".frames")
        first = int(names[0]) if frame_file and len(names) == 1 and names[0].isdigit() else 0
        expected = [f"{k:05d}" for k in range(first, first + len(names))]
        numbered = all(n.isdigit() for n in names) and sorted(names, key=int) == expected
        if not numbered:
            fail(f"frame names are not {first:05d} .. {first + len(names) - 1:05d}: {names[:5]}")
        if args.frames is not None and len(names) != args.frames:
            fail(f"{len(names)} frames, expected {args.frames}")

        times = []
        resolved = 0
        sizes = []
        layout = None
        total = 0
        for name in sorted(names, key=lambda s: int(s) if s.isdigit() else -1):
            where = f"frame {name}"
            try:
                g = f["frames"][name]
            except (KeyError, OSError) as e:
                fail(f"{where}: does not resolve (missing or incomplete frame file?): {e}")
                continue
            if "points" not in g:
                fail(f"{where}: no points dataset")
                continue
            pts = g["points"]
            if pts.ndim != 2 or pts.shape[1] != 3:
                fail(f"{where}: points has shape {pts.shape}, expected (n, 3)")
                continue
            if pts.dtype.kind != "f":
                fail(f"{where}: points are {pts.dtype}, expected float")
                continue
            n = pts.shape[0]
            resolved += 1
            sizes.append(n)
            total += n
            for dname, ds in g.items():
                if not isinstance(ds, h5py.Dataset):
                    fail(f"{where}: {dname} is not a dataset")
                    continue
                if ds.ndim == 0 or ds.shape[0] != n:
                    fail(f"{where}: {dname} has shape {ds.shape}, expected first dimension {n}")
                    continue
                if ds.dtype.kind == "f":
                    bad = non_finite(ds)
                    if bad:
                        fail(f"{where}: {dname} has {bad} non-finite values")
            if "connectivity" not in g:
                fail(f"{where}: no connectivity dataset")
            elif g["connectivity"].shape != (n,) or not check_connectivity(g["connectivity"], n):
                fail(f"{where}: connectivity is not 0 .. n-1")
            t = g.attrs.get("time")
            if t is None or not math.isfinite(float(t)):
                fail(f"{where}: attribute time is {t!r}, expected a finite number")
            else:
                t = float(t)
                if times and t < times[-1]:
                    fail(f"{where}: time {t!r} before the previous frame's {times[-1]!r}")
                times.append(t)
            this_layout = ", ".join(f"{d}:{dtype_name(ds)}" for d, ds in g.items() if d != "connectivity")
            if layout is None:
                layout = this_layout
            if not args.quiet:
                step = g.attrs.get("step")
                step = "" if step is None else f" step {step}"
                print(f"  {name}: n = {n}, t = {t!r}{step}")
            if this_layout != layout and not args.quiet:
                print(f"  {name}: arrays differ from frame 00000: {this_layout}")

        xmf = os.path.splitext(args.run)[0] + ".xmf"
        if os.path.exists(xmf):
            try:
                xtimes = xmf_times(xmf)
            except (OSError, ValueError) as e:
                fail(f"{xmf}: cannot read: {e}")
            else:
                if len(xtimes) not in (len(names), len(names) - 1):
                    fail(f"{xmf} names {len(xtimes)} frames, the run file {len(names)}")
                elif resolved == len(names) and xtimes != times[: len(xtimes)]:
                    fail(f"{xmf}: times differ from the run file's")

    span = f"t = {times[0]!r} .. {times[-1]!r}" if times else "no times"
    nspan = f"n = {min(sizes)} .. {max(sizes)}" if sizes else "no particles"
    print(f"{args.run}: {len(names)} frames, {nspan}, {total} particle records, {span}")
    if layout:
        print(f"  datasets: {layout}")
    if errors:
        print(f"check-hdf5: {len(errors)} check(s) failed")
        return 1
    print("check-hdf5: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
