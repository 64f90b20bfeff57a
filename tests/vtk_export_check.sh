#!/usr/bin/env bash
# A `--dump-format vtk` run read by VTK's own XML reader (python3-vtk9; README, Exports): the
# time series, point count, positions, velocities and ids against the CSV dump of the same run.
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
"$APICLAB" run two-cubes --frames 2 --dump "$TMP/d" --dump-format csv,vtk --csv "$TMP/d.csv" --quiet || exit 1
/usr/bin/python3 "$SRC/tests/vtk_read_check.py" "$TMP/d"
