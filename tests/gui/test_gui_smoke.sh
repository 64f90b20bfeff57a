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
# Layout: every widget the viewer reports lies inside the window; the control column's header
# wraps inside the column (it ran under its edge, "...Eulerian-on-Lagr"); each pane's kernel and
# integrator combos are there (labelled: "kernel: quadratic").
awk '/^window: / { W = $4; H = $5 }
     /^widget / { sub(/^widget /, ""); split($0, p, ": "); split(p[2], r, " ");
                  if (r[1] < 0 || r[2] < 0 || r[1] + r[3] > W || r[2] + r[4] > H) {
                    print "FAIL: " p[1] " at " p[2] " outside the " W "x" H " window"; bad = 1 }
                  if (p[1] == "header" && r[1] + r[3] > 350) { print "FAIL: header past the column: " p[2]; bad = 1 }
                  n++ }
     END { if (n < 7) { print "FAIL: " n " widgets reported"; bad = 1 } exit bad }' "$out/gui-smoke.log"
# Each pane's kernel and integrator combos show their text whole ("integrator: midpoin" was cut).
for k in 0 1 2; do
  for what in kernel integrator; do
    combo=$(grep "^widget pane $k $what: " "$out/gui-smoke.log" | sed 's/.*: //')
    text=$(grep "^widget pane $k $what text: " "$out/gui-smoke.log" | sed 's/.*: //')
    [ -n "$combo" ] && [ -n "$text" ] || { echo "FAIL: no $what combo in pane $k"; exit 1; }
    echo "$combo $text" | awk -v w="pane $k $what" '$5 + $7 > $1 + $3 + 0.5 { print "FAIL: " w " text cut"; exit 1 }'
  done
done
grep -q '^text pane 1: FLIP |' "$out/gui-smoke.log" || { echo "FAIL: pane 1 is not titled FLIP"; exit 1; }
# Each plot's legend band lies above its data box, never over it.
awk '/^widget plot .* box: / { split($0, p, ": "); split(p[2], r, " "); top[$3] = r[2] }
     /^widget plot .* legend: / { split($0, p, ": "); split(p[2], r, " "); bottom[$3] = r[2] + r[4] }
     END { for (k in bottom) { n++; if (bottom[k] > top[k]) { print "FAIL: the " k " legend over its data"; bad = 1 } }
           if (n < 4) { print "FAIL: " n " plot legends reported"; bad = 1 }
           exit bad }' "$out/gui-smoke.log"
echo "layout: every widget inside the window, legends above the data"

# Every pane blown up at its first step (a fixed step of 1e30 s): the window keeps drawing. The
# GUI soak hung here: all panes failed, so their inf speeds set the colour scale, and the colour
# bar's tick loop never reached inf (render/legend.cpp). 60 s is many times what it needs.
blown="$out/gui-blown.png"
rm -f "$blown"
APICLAB_PRINT_LAYOUT=1 timeout 60 xvfb-run -a -s "-screen 0 1280x800x24" "$APICLAB" gui eol-drop \
  --set 'solver.method="mpm"' --schemes asflip,apic,rpic,polypic --dt 1e30 --screenshot "$blown" \
  --frames 3 --size 1280x800 \
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
# Four narrow panes: each title strip keeps the blow-up's time (the label gives way first); the
# PolyPIC pane (9 modes) shows the G-mode warning `run` prints, in the registry's spelling.
for k in 0 1 2 3; do
  grep -q "^text pane $k: .* | blew up at .*t = 1e+30 s" "$out/gui-blown.log" || {
    grep '^text ' "$out/gui-blown.log"
    echo "FAIL: pane $k's title strip lost the blow-up's time"
    exit 1
  }
done
grep -q '^text pane 3: PolyPIC(9 modes) |' "$out/gui-blown.log" || { echo "FAIL: pane 3 not titled PolyPIC"; exit 1; }
# The label, cut with "...", ends before the details begin.
awk '/^widget pane [0-9] title: / { split($0, p, ": "); split(p[2], r, " "); end[$3] = r[1] + r[3] }
     /^widget pane [0-9] details: / { split($0, p, ": "); split(p[2], r, " "); start[$3] = r[1] + 0 }
     END { for (k in start) if (end[k] > start[k]) { print "FAIL: pane " k " label runs into its details"; bad = 1 }
           exit bad }' "$out/gui-blown.log"
grep -q '^widget pane 3 warning: ' "$out/gui-blown.log" || { echo "FAIL: no G-mode warning in the PolyPIC pane"; exit 1; }
! grep -q '^widget pane [012] warning: ' "$out/gui-blown.log" || { echo "FAIL: a warning in a pane without PolyPIC"; exit 1; }
echo "every pane blown up: the window still drew ($blown)"
