#!/usr/bin/python3
# The README picture of a --dump-format vtk frame, drawn by VTK (python3-vtk9) offscreen:
#   xvfb-run -a /usr/bin/python3 tests/commands/vtk_screenshot.py out/frame_0007.vtp shot.png "caption"
import sys, vtk
r = vtk.vtkXMLPolyDataReader(); r.SetFileName(sys.argv[1]); r.Update()
poly = r.GetOutput(); poly.GetPointData().SetActiveScalars("speed")
m = vtk.vtkPolyDataMapper(); m.SetInputData(poly); m.SetScalarModeToUsePointData()
m.SetScalarRange(poly.GetPointData().GetArray("speed").GetRange())
lut = vtk.vtkLookupTable(); lut.SetHueRange(0.67, 0.0); lut.SetNumberOfColors(256); lut.Build(); m.SetLookupTable(lut)
a = vtk.vtkActor(); a.SetMapper(m); a.GetProperty().SetPointSize(2)
bar = vtk.vtkScalarBarActor(); bar.SetLookupTable(lut); bar.SetTitle("speed [m/s]"); bar.SetNumberOfLabels(4); bar.SetWidth(0.08); bar.SetHeight(0.5); bar.SetPosition(0.88, 0.3); bar.SetUnconstrainedFontSize(True); bar.GetLabelTextProperty().SetFontSize(14); bar.GetTitleTextProperty().SetFontSize(14); bar.GetLabelTextProperty().ItalicOff(); bar.GetTitleTextProperty().ItalicOff()
ren = vtk.vtkRenderer(); ren.AddActor(a); ren.AddActor2D(bar); ren.SetBackground(1, 1, 1)
bar.GetTitleTextProperty().SetColor(0,0,0); bar.GetLabelTextProperty().SetColor(0,0,0)
txt = vtk.vtkTextActor(); txt.SetInput(sys.argv[3]); txt.GetTextProperty().SetColor(0,0,0); txt.GetTextProperty().SetFontSize(18); txt.SetPosition(10, 10); ren.AddActor2D(txt)
w = vtk.vtkRenderWindow(); w.SetOffScreenRendering(1); w.AddRenderer(ren); w.SetSize(900, 600)
c = ren.GetActiveCamera(); c.SetPosition(1.2, 0.62, 1.3); c.SetFocalPoint(0.5, 0.24, 0.49); c.SetViewUp(0, 1, 0); ren.ResetCameraClippingRange()
w.Render()
f = vtk.vtkWindowToImageFilter(); f.SetInput(w); f.Update()
pw = vtk.vtkPNGWriter(); pw.SetFileName(sys.argv[2]); pw.SetInputConnection(f.GetOutputPort()); pw.Write()
