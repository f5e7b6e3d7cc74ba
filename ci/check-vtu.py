#!/usr/bin/env python3
"""Reads swarf's VTU frames with other tools and compares them with swarf's own values.

usage: check-vtu.py RAW_RUN_FOLDER ZLIB_RUN_FOLDER

The two run folders hold the same run (same scene, backend and build), written with output.vtu_encoding = "raw"
and "base64-zlib". swarf's own values are the raw frame's bytes, decoded here independently of any VTK library
(each array is a UInt64 byte count and little-endian data at its offset), and summary.json's particle count.
The check: the count matches; meshio reads the base64-zlib frame (it cannot read raw appended data) and every point
array and the points equal swarf's bit for bit; VTK, where the `vtk` module is installed, reads both frames with
the same result. It prints the frames' sizes and their ratio.
"""

import json
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from frames import last_frame  # noqa: E402

TYPES = {"Float32": "<f4", "Float64": "<f8", "UInt32": "<u4", "Int32": "<i4", "Int64": "<i8", "UInt8": "u1"}


def read_raw(path):
    """swarf's raw VTU: {name: array} of the point data, plus "Points"."""
    data = open(path, "rb").read()
    mark = b'<AppendedData encoding="raw">'
    at = data.index(mark)
    header = data[:at].decode()
    start = data.index(b"_", at + len(mark)) + 1
    arrays = {}
    section = None
    for tag in re.finditer(r"<(/?)(\w+)([^>]*)>", header):
        closing, name, attrs = tag.groups()
        if name in ("PointData", "Points", "Cells", "FieldData"):
            section = None if closing or attrs.endswith("/") else name
        if name == "DataArray" and section in ("PointData", "Points"):
            a = dict(re.findall(r'(\w+)="([^"]*)"', attrs))
            offset = start + int(a["offset"])
            n = int(np.frombuffer(data[offset : offset + 8], "<u8")[0])
            values = np.frombuffer(data[offset + 8 : offset + 8 + n], TYPES[a["type"]])
            arrays[a["Name"]] = values.reshape(-1, int(a.get("NumberOfComponents", "1")))
    return arrays


def same(what, got, want):
    got = np.asarray(got).reshape(want.shape)
    if got.dtype != want.dtype or not np.array_equal(got.view(np.uint8), want.view(np.uint8)):
        sys.exit(f"{what}: differs from swarf's values ({got.dtype}, {want.dtype})")


def check(tool, arrays, want):
    same(f"{tool}: points", arrays["Points"], want["Points"])
    for name, values in want.items():
        if name != "Points":
            same(f"{tool}: {name}", arrays[name], values)
    print(f"{tool}: {len(want) - 1} point arrays and the points equal swarf's ({len(want['Points'])} points)")


def with_meshio(path):
    import meshio

    m = meshio.read(path)
    return dict(m.point_data, Points=m.points)


def with_vtk(path):
    from vtk import vtkXMLUnstructuredGridReader
    from vtk.util.numpy_support import vtk_to_numpy

    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    pd = g.GetPointData()
    arrays = {pd.GetArrayName(k): vtk_to_numpy(pd.GetArray(k)) for k in range(pd.GetNumberOfArrays())}
    arrays["Points"] = vtk_to_numpy(g.GetPoints().GetData())
    return arrays


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    raw_run, zlib_run = sys.argv[1:]
    raw, zlib = last_frame(raw_run), last_frame(zlib_run)
    want = read_raw(raw)
    particles = json.load(open(os.path.join(raw_run, "summary.json")))["particles"]
    if len(want["Points"]) != particles or len(want["id"]) != particles:
        sys.exit(f"{raw}: {len(want['Points'])} points, summary.json says {particles}")
    print(f"swarf: {particles} particles; density sum {want['density'].sum():.6e}")
    check("meshio (base64-zlib)", with_meshio(zlib), want)
    try:
        import vtk  # noqa: F401
    except ImportError:
        print("vtk: not installed, skipped")
    else:
        check("vtk (raw)", with_vtk(raw), want)
        check("vtk (base64-zlib)", with_vtk(zlib), want)
    a, b = os.path.getsize(raw), os.path.getsize(zlib)
    print(f"sizes: raw {a} bytes, base64-zlib {b} bytes, ratio {a / b:.2f}")


main()
