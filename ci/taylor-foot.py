#!/usr/bin/env python3
"""The Taylor bar's length and footprint from a run's last frame, measured several ways (docs/3d.md).

usage: taylor-foot.py RUN_FOLDER DX

summary.json gives the bar's final length (z extent of the centres) and footprint (the largest distance of a
centre from the axis). That largest distance is one particle's: the outermost lip particle sets it, so it can
grow with refinement while the foot's body does not. This prints, besides it, measures that a few particles
cannot move, from the raw VTU frame (pure Python: the GPU machine has no numpy):

- L: centres' z extent, and + dx (the material's, each particle standing for a cell of side dx);
- r_max: the largest centre radius, and + dx/2;
- in the foot's slab (centres within 2 dx of the lowest): the radius quantiles 0.99 and 0.999;
- lone: slab particles with no other slab particle within 1.5 dx (detached lip particles), and r_max without them.
"""

import array
import math
import os
import re
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from frames import last_frame  # noqa: E402


def points(path):
    """The frame's points as a flat array of x, y, z (raw appended encoding, Float64 or Float32)."""
    data = open(path, "rb").read()
    mark = b'<AppendedData encoding="raw">'
    if mark not in data:
        sys.exit(f"{path}: not a raw-encoded frame (set output.vtu_encoding = \"raw\")")
    at = data.index(mark)
    start = data.index(b"_", at + len(mark)) + 1
    header = data[:at].decode()
    tag = re.search(r'<DataArray type="(Float64|Float32)" Name="Points"[^>]*offset="(\d+)"', header)
    if not tag:
        sys.exit(f"{path}: no Points array")
    offset = start + int(tag.group(2))
    (n,) = struct.unpack_from("<Q", data, offset)
    a = array.array("d" if tag.group(1) == "Float64" else "f")
    a.frombytes(data[offset + 8 : offset + 8 + n])
    if sys.byteorder != "little":
        a.byteswap()
    return a


def quantile(sorted_values, q):
    return sorted_values[min(len(sorted_values) - 1, int(q * len(sorted_values)))]


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    run, dx = sys.argv[1], float(sys.argv[2])
    p = points(last_frame(run))
    xs, ys, zs = p[0::3], p[1::3], p[2::3]
    zmin, zmax = min(zs), max(zs)
    radii = [math.hypot(x, y) for x, y in zip(xs, ys)]
    slab = [(xs[i], ys[i], radii[i]) for i in range(len(zs)) if zs[i] < zmin + 2.0 * dx]
    rs = sorted(r for _, _, r in slab)
    # Lone particles: none other in the slab within 1.5 dx (a hash of 1.5 dx cells in x, y).
    cell = 1.5 * dx
    grid = {}
    for k, (x, y, _) in enumerate(slab):
        grid.setdefault((math.floor(x / cell), math.floor(y / cell)), []).append(k)
    lone = set()
    for k, (x, y, _) in enumerate(slab):
        cx, cy = math.floor(x / cell), math.floor(y / cell)
        near = any(
            j != k and math.hypot(slab[j][0] - x, slab[j][1] - y) < cell
            for i in (-1, 0, 1)
            for m in (-1, 0, 1)
            for j in grid.get((cx + i, cy + m), ())
        )
        if not near:
            lone.add(k)
    bound = sorted(r for k, (_, _, r) in enumerate(slab) if k not in lone) or [0.0]
    mm = 1e3
    print(
        f"{run}: {len(zs)} particles, dx {dx * mm:.3f} mm | L centres {(zmax - zmin) * mm:.2f} (+dx {(zmax - zmin + dx) * mm:.2f}) mm"
        f" | r_max {max(radii) * mm:.2f} (+dx/2 {(max(radii) + dx / 2) * mm:.2f}) mm"
        f" | slab {len(slab)}: q0.99 {quantile(rs, 0.99) * mm:.2f}, q0.999 {quantile(rs, 0.999) * mm:.2f} mm"
        f" | lone {len(lone)}, r_max without them {bound[-1] * mm:.2f} mm"
    )


if __name__ == "__main__":
    main()
