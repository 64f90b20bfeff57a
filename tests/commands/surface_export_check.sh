#!/usr/bin/env bash
# The EoL surfaces of `--dump-format vtk,obj` (eol-drop, eol-drop-3d) read by VTK's own XML
# reader (python3-vtk9) and, where Debian's paraview is installed, by ParaView itself (pvbatch):
# tests/commands/surface_vtk_check.py. Skipped where python3-vtk9 is not installed.
# Usage: APICLAB=/path/to/apiclab surface_export_check.sh SOURCE_DIR
set -u
APICLAB=${APICLAB:?set APICLAB to the apiclab executable}
SRC=${1:?usage: surface_export_check.sh SOURCE_DIR}
if ! /usr/bin/python3 -c 'import vtk' 2>/dev/null; then
  echo "SKIP: python3-vtk9 is not installed (apt-get install python3-vtk9)"
  exit 0
fi
TMP=$(mktemp -d "${TMPDIR:-/tmp}/apiclab-surface.XXXXXX")
trap 'rm -rf "$TMP"' EXIT
for scene in eol-drop eol-drop-3d; do
  "$APICLAB" run "$scene" --frames 2 --dump "$TMP/$scene" --dump-format vtk,obj \
    --csv "$TMP/$scene.csv" --quiet || exit 1
  /usr/bin/python3 "$SRC/tests/commands/surface_vtk_check.py" "$TMP/$scene" || exit 1
  if command -v pvbatch >/dev/null && command -v xvfb-run >/dev/null; then
    xvfb-run -a pvbatch "$SRC/tests/commands/surface_vtk_check.py" "$TMP/$scene" --paraview || exit 1
  else
    echo "note: paraview is not installed; ParaView itself not tried"
  fi
done
