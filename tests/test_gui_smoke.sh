#!/usr/bin/env bash
# GUI smoke test: the viewer under Xvfb, side by side with pic, flip, apic, 60 frames, then a
# screenshot that must be non-blank and show particles in each of the three pane areas; then
# every pane blown up at once, which must not stop the window drawing.
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

# Every pane blown up at its first step (a fixed step of 1e30 s): the window keeps drawing. The
# GUI soak hung here: all panes failed, so their inf speeds set the colour scale, and the colour
# bar's tick loop never reached inf (render/legend.cpp). 60 s is many times what it needs.
blown="$out/gui-blown.png"
rm -f "$blown"
timeout 60 xvfb-run -a -s "-screen 0 1280x800x24" "$APICLAB" gui eol-drop --set 'solver.method="mpm"' \
  --schemes asflip,apic,rpic,pic --dt 1e30 --screenshot "$blown" --frames 3 --size 1280x800 \
  >"$out/gui-blown.log" 2>&1 || {
  rc=$?
  cat "$out/gui-blown.log"
  echo "FAIL: the viewer with every pane blown up exited $rc (124: it stopped drawing)"
  exit 1
}
grep -q 't = 1e+30 s' "$out/gui-blown.log" || {
  cat "$out/gui-blown.log"
  echo "FAIL: the screenshot was not taken after the blow-up"
  exit 1
}
[ -s "$blown" ] || { echo "FAIL: no screenshot at $blown"; exit 1; }
echo "every pane blown up: the window still drew ($blown)"
