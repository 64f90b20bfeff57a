# The README picture of a --dump-format vtk run opened in ParaView itself (Debian's paraview):
#   (apt-get install paraview python3-paraview)
#   xvfb-run -a pvbatch tests/commands/paraview_screenshot.py out/series.pvd shot.png "caption"
# Opens the series.pvd as a time series, goes to its last time, colours the points by speed.
import sys
from paraview.simple import (PVDReader, GetActiveViewOrCreate, Show, ColorBy, Text,
                             SaveScreenshot, GetColorTransferFunction, GetScalarBar)
series = PVDReader(FileName=sys.argv[1])
times = series.TimestepValues
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [900, 600]
view.UseColorPaletteForBackground = 0
view.Background = [1, 1, 1]
view.OrientationAxesVisibility = 0
view.ViewTime = times[-1] if len(times) else 0
shown = Show(series, view)
shown.Representation = "Points"
shown.PointSize = 2
ColorBy(shown, ("POINTS", "speed"))
shown.RescaleTransferFunctionToDataRange(True, False)
shown.SetScalarBarVisibility(view, True)
bar = GetScalarBar(GetColorTransferFunction("speed"), view)
bar.Title = "speed [m/s]"
bar.ComponentTitle = ""
bar.TitleColor = [0, 0, 0]
bar.LabelColor = [0, 0, 0]
caption = Text(Text="%s  (ParaView, t = %.4g s of %d frames)" % (
    sys.argv[3] if len(sys.argv) > 3 else sys.argv[1], view.ViewTime, len(times)))
label = Show(caption, view)
label.Color = [0, 0, 0]
label.FontSize = 14
label.WindowLocation = "Lower Left Corner"
view.CameraPosition = [1.2, 0.62, 1.3]
view.CameraFocalPoint = [0.5, 0.24, 0.49]
view.CameraViewUp = [0, 1, 0]
view.ResetCamera(False)
SaveScreenshot(sys.argv[2], view, ImageResolution=[900, 600])
print("%s: %d frames, last t = %g" % (sys.argv[1], len(times), view.ViewTime))
