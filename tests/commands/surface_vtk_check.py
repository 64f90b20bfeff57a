#!/usr/bin/python3
"""Reads the EoL surfaces of a `--dump-format vtk,obj` run with VTK's own reader (python3-vtk9)
or, with --paraview under pvbatch, with ParaView's: each frame_NNNN_surfaceK.vtp has the OBJ's
vertices (positions equal to float precision) and elements, a velocity array, and is closed (2D:
every point ends two lines; 3D: no boundary or non-manifold edge); series.pvd lists it at each
frame's time. Usage: surface_vtk_check.py DUMP_DIR [--paraview]"""
import csv
import glob
import os
import struct
import sys
import xml.etree.ElementTree as ET

d = sys.argv[1]
paraview = "--paraview" in sys.argv[2:]
frames = list(csv.DictReader(open(f"{d}/frames.csv")))
pvd = ET.parse(f"{d}/series.pvd").getroot().find("Collection").findall("DataSet")
surfaces = sorted(glob.glob(f"{d}/frame_*_surface*.vtp"))
assert len(surfaces) >= len(frames), (surfaces, frames)
listed = {e.get("file"): float(e.get("timestep")) for e in pvd}


def f32(x):
    return struct.unpack("f", struct.pack("f", x))[0]


def read_obj(path):
    verts, cells = [], []
    for line in open(path):
        tag, *rest = line.split()
        if tag == "v":
            verts.append(tuple(f32(float(x)) for x in rest))
        elif tag in ("l", "f"):
            cells.append(tuple(int(i) - 1 for i in rest))
    return verts, cells


for path in surfaces:
    name = os.path.basename(path)
    frame = int(name[6:10])
    assert abs(listed[name] - float(frames[frame]["t"])) <= 1e-12, (name, listed.get(name))
    verts, cells = read_obj(path.replace(".vtp", ".obj"))
    dim = len(cells[0])
    if paraview:
        from paraview.simple import XMLPolyDataReader
        reader = XMLPolyDataReader(FileName=[path])
        reader.UpdatePipeline()
        info = reader.GetDataInformation()
        assert info.GetNumberOfPoints() == len(verts), (name, info.GetNumberOfPoints(), len(verts))
        assert info.GetNumberOfCells() == len(cells), (name, info.GetNumberOfCells(), len(cells))
        continue
    from vtkmodules.vtkFiltersCore import vtkFeatureEdges
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    poly = reader.GetOutput()
    assert poly.GetNumberOfPoints() == len(verts), (name, poly.GetNumberOfPoints(), len(verts))
    kind = poly.GetLines() if dim == 2 else poly.GetPolys()
    assert kind.GetNumberOfCells() == len(cells) == poly.GetNumberOfCells(), name
    pts = poly.GetPoints().GetData()
    for q, v in enumerate(verts):
        assert pts.GetTuple3(q) == v, (name, q, pts.GetTuple3(q), v)
    for c, want in enumerate(cells):
        ids = poly.GetCell(c).GetPointIds()
        assert tuple(ids.GetId(k) for k in range(ids.GetNumberOfIds())) == want, (name, c)
    assert poly.GetPointData().GetArray("velocity").GetNumberOfTuples() == len(verts), name
    if dim == 2:
        ends = [0] * len(verts)
        for cell in cells:
            for i in cell:
                ends[i] += 1
        assert set(ends) == {2}, (name, set(ends))
    else:
        edges = vtkFeatureEdges()
        edges.SetInputData(poly)
        edges.BoundaryEdgesOn()
        edges.NonManifoldEdgesOn()
        edges.FeatureEdgesOff()
        edges.ManifoldEdgesOff()
        edges.Update()
        assert edges.GetOutput().GetNumberOfCells() == 0, (name, "open or non-manifold edges")
who = "ParaView" if paraview else "VTK"
print(f"surface_vtk_check: {len(surfaces)} surfaces in {len(frames)} frames read by {who}")
