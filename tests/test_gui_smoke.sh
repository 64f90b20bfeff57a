#!/usr/bin/env bash
# GUI smoke test: the viewer under Xvfb, side by side with pic, flip, apic, 60 frames, then a
# screenshot that must be non-blank and show particles in each of the three pane areas.
# Usage: APICLAB=path/to/apiclab CHECK=path/to/gui_screenshot_check test_gui_smoke.sh OUTDIR
set -euo pipefail
out="${1:-/tmp/apiclab-gui-smoke}"
mkdir -p "$out"
if ! command -v xvfb-run >/dev/null; then
  echo "SKIP: xvfb-run not found (apt-get install xvfb xauth)"
  exit 0
fi
png="$out/gui-smoke.png"
rm -f "$png"
APICLAB_PRINT_LAYOUT=1 xvfb-run -a -s "-screen 0 1600x900x24" "$APICLAB" gui rotating-disk --schemes pic,flip,apic --vectors \
  --screenshot "$png" --frames 60 --size 1600x900 >"$out/gui-smoke.log" 2>&1 || {
  cat "$out/gui-smoke.log"
  exit 1
}
cat "$out/gui-smoke.log"
grep '^pane ' "$out/gui-smoke.log" | "$CHECK" "$png" 3
