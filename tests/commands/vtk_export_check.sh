#!/usr/bin/env bash
# A `--dump-format vtk` run (zlib-compressed, and vtk-raw) read by VTK's own XML reader
# (python3-vtk9; README, Exports): the time series, point count, positions, velocities and ids
# against the CSV dump of the same run; then, where Debian's paraview is installed, ParaView
# itself opens series.pvd as a time series and draws its last frame.
# Skipped where python3-vtk9 is not installed (it is not in setup.sh: ~300 MB).
# Usage: APICLAB=/path/to/apiclab vtk_export_check.sh SOURCE_DIR
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
SRC=${1:?usage: vtk_export_check.sh SOURCE_DIR}
if ! /usr/bin/python3 -c 'import vtk' 2>/dev/null; then
  echo "SKIP: python3-vtk9 is not installed (apt-get install python3-vtk9)"
  exit 0
fi
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-vtk.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
for format in vtk vtk-raw; do
  "$APICLAB" run two-cubes --frames 1 --dump "$TMP/$format" --dump-format "csv,$format" \
    --csv "$TMP/d.csv" --quiet || exit 1
  grep -q 'compressor="vtkZLibDataCompressor"' "$TMP/$format/frame_0001.vtp"
  compressed=$?
  if [ "$format" = vtk ] && [ $compressed -ne 0 ]; then
    echo "note: this apiclab was built without zlib: vtk is raw"
  fi
  /usr/bin/python3 "$SRC/tests/commands/vtk_read_check.py" "$TMP/$format" || exit 1
done
if command -v pvbatch >/dev/null && command -v xvfb-run >/dev/null; then
  out=$(xvfb-run -a pvbatch "$SRC/tests/commands/paraview_screenshot.py" "$TMP/vtk/series.pvd" \
    "$TMP/paraview.png" two-cubes 2>&1)
  if echo "$out" | grep -q 'series.pvd: 2 frames, last t = 0.041' && [ -s "$TMP/paraview.png" ]; then
    echo "ParaView opened series.pvd: 2 frames"
  else
    echo "FAIL: ParaView did not open series.pvd as 2 frames: $out"
    exit 1
  fi
else
  echo "note: paraview is not installed; ParaView itself not tried (apt-get install paraview python3-paraview)"
fi
