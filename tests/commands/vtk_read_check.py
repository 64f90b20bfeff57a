#!/usr/bin/python3
"""Reads a `--dump-format vtk` run with VTK's own readers (python3-vtk9): series.pvd lists every
frame with the time in frames.csv, and each .vtp has the CSV's particles, positions and velocity
(to float32), id and object. Usage: vtk_read_check.py DUMP_DIR"""
import csv
import struct
import sys
import xml.etree.ElementTree as ET

import vtk

d = sys.argv[1]
frames = list(csv.DictReader(open(f"{d}/frames.csv")))
pvd = ET.parse(f"{d}/series.pvd").getroot().find("Collection").findall("DataSet")
assert len(pvd) == len(frames), (len(pvd), len(frames))
for entry, row in zip(pvd, frames):
    assert abs(float(entry.get("timestep")) - float(row["t"])) <= 1e-12, (entry.get("timestep"), row)
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(f"{d}/{entry.get('file')}")
    reader.Update()
    poly = reader.GetOutput()
    rows = list(csv.DictReader(open(f"{d}/{entry.get('file').replace('.vtp', '.csv')}")))
    n = poly.GetNumberOfPoints()
    assert n == len(rows) and poly.GetNumberOfVerts() == n, (n, len(rows))
    pts = poly.GetPoints().GetData()
    vel = poly.GetPointData().GetArray("velocity")
    ids = poly.GetPointData().GetArray("id")
    f32 = lambda x: struct.unpack("f", struct.pack("f", x))[0]
    for q in range(0, n, max(1, n // 500)):
        r = rows[q]
        assert int(ids.GetTuple1(q)) == int(r["id"])
        for a, k in enumerate("xyz"):
            if k in r:
                assert pts.GetTuple3(q)[a] == float(r[k]), (q, k)
                assert vel.GetTuple3(q)[a] == f32(float(r["v" + k])), (q, k)
    for name in ("object", "mass", "volume0", "F", "C", "speed", "noise"):
        assert poly.GetPointData().GetArray(name) is not None, name
print(f"vtk_read_check: {len(frames)} frames read by VTK {vtk.vtkVersion.GetVTKVersion()}")
