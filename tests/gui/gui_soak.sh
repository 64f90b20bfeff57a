#!/usr/bin/env bash
# GUI soak (docs/testing.md, GUI soak): under Xvfb, xdotool drives random clicks, drags, wheel
# turns, key presses and absurd typed values over the viewer for a given time, a share of them
# aimed at the controls (scene and scheme combos, Play/Step/Reset, pane add/remove, number
# fields, the Open path field). The viewer must stay alive, draw a frame at least every
# --max-gap seconds (its --heartbeat file) and stay under --rss-mb of resident memory.
# Every event is written to a log first, so a failure replays:
#   tests/gui/gui_soak.sh --seed S --replay OUT/events.log
# Usage: APICLAB=build/app/apiclab tests/gui/gui_soak.sh [--seconds 120] [--seed S] [--out DIR]
#          [--rss-mb 3000] [--max-gap 1.0] [--replay LOG]
set -uo pipefail
seconds=120
seed=$(((RANDOM << 15) | RANDOM))
out=/tmp/apiclab-gui-soak
rss_mb=3000
max_gap=1.0
replay=""
while (($#)); do
  case "$1" in
    --seconds) seconds="$2" ;;
    --seed) seed="$2" ;;
    --out) out="$2" ;;
    --rss-mb) rss_mb="$2" ;;
    --max-gap) max_gap="$2" ;;
    --replay) replay="$2" ;;
    *)
      echo "gui_soak.sh: unknown option '$1'" >&2
      exit 2
      ;;
  esac
  shift 2
done
app="${APICLAB:-build/app/apiclab}"
for tool in Xvfb xdotool; do
  if ! command -v "$tool" >/dev/null; then
    echo "SKIP: $tool not found (apt-get install xvfb xdotool)"
    exit 0
  fi
done
[ -x "$app" ] || {
  echo "gui_soak.sh: no viewer at '$app' (set APICLAB)" >&2
  exit 2
}
mkdir -p "$out"
log="$out/events.log"
beat="$out/heartbeat"
W=1280
H=800
rm -f "$beat" "$out/viewer.log"

# ---- The events: generated from the seed (bash's RANDOM is seeded by assignment) -------------
# One line each: DELAY_MS KIND ARGS. Coordinates are window pixels; the window sits at 0,0.
# Layout (app/gui/viewer.cpp): a 350 px control column, scene panes right of it over the top
# 60 % of the height, plots below. Rows of the column measured on a screenshot of the soak's
# start (rotating-disk, three panes); they move when a scene's description wraps differently,
# which the random clicks over the whole column cover.
generate() {
  RANDOM=$seed
  local t=0 ms kind
  local values=("1e308" "-1e308" "nan" "inf" "-inf" "0" "-0" "1e-320" "99999999999999999999999"
    "-1" "abc" "1e999" "0x1p-1074" "" "  " "3.5.6" "1,5" "12345678901234567890123456789")
  local paths=("/dev/zero" "/dev/null" "/" "/proc/self/status" "/nonexistent/scene.json"
    "assets/meshes/bunny.obj" "assets/scenes" "rotating-disk" "bunnies" "../../../../etc/passwd"
    "$(printf 'x%.0s' {1..600})" "eol-spin-3d" "torus-drop" "two-cubes")
  local keys=(Escape Return Tab space Up Down Left Right BackSpace Delete Home End Page_Up
    Page_Down ctrl+a ctrl+c ctrl+v ctrl+z ctrl+x F1 F11 alt+F4 shift+Tab KP_Enter)
  echo "# gui_soak seed $seed seconds $seconds size ${W}x$H"
  while ((t < seconds * 1000)); do
    ms=$((20 + RANDOM % 180))
    t=$((t + ms))
    kind=$((RANDOM % 100))
    local x=$((RANDOM % W)) y=$((RANDOM % H)) cx=$((RANDOM % 350)) cy=$((RANDOM % H))
    if ((kind < 22)); then # anywhere in the control column
      echo "$ms click $cx $cy 1"
    elif ((kind < 30)); then # scene combo, then an entry of its list
      echo "$ms click 170 71 1"
      echo "150 click $((20 + RANDOM % 300)) $((85 + RANDOM % 200)) 1"
    elif ((kind < 37)); then # a pane's scheme combo, then an entry
      local row=$((RANDOM % 3))
      echo "$ms click 55 $((370 + row * 56)) 1"
      echo "150 click 55 $((385 + row * 56 + RANDOM % 200)) 1"
    elif ((kind < 42)); then # Play / Step / Reset
      echo "$ms click $((58 + 109 * (RANDOM % 3))) 194 1"
    elif ((kind < 46)); then # a pane's remove button, or add pane
      if ((RANDOM % 2)); then echo "$ms click 315 $((370 + (RANDOM % 3) * 56)) 1"; else echo "$ms click 170 $((370 + (RANDOM % 4) * 56)) 1"; fi
    elif ((kind < 56)); then # an absurd value typed into a number field (ctrl+click edits)
      echo "$ms typefield $((20 + RANDOM % 130)) $((590 + RANDOM % 205)) ${values[RANDOM % ${#values[@]}]}"
    elif ((kind < 59)); then # a path typed into Open
      echo "$ms typepath 140 99 ${paths[RANDOM % ${#paths[@]}]}"
    elif ((kind < 72)); then # drags: camera in the panes, sliders in the column
      local x2=$((RANDOM % W)) y2=$((RANDOM % H))
      echo "$ms drag $x $y $x2 $y2 $((1 + (RANDOM % 3)))"
    elif ((kind < 82)); then # wheel turns: zoom in panes, scroll in the column
      echo "$ms wheel $x $y $((4 + RANDOM % 2)) $((1 + RANDOM % 8))"
    elif ((kind < 92)); then # a key press
      echo "$ms key $x $y ${keys[RANDOM % ${#keys[@]}]}"
    else # a click anywhere (panes, plots, legends)
      echo "$ms click $x $y $((1 + (RANDOM % 3)))"
    fi
  done
}

# ---- The viewer ---------------------------------------------------------------------------------
Xvfb -displayfd 1 -screen 0 "${W}x${H}x24" -nolisten tcp >"$out/display" 2>"$out/xvfb.log" &
xvfb=$!
for _ in $(seq 50); do
  [ -s "$out/display" ] && break
  sleep 0.1
done
export DISPLAY=":$(head -1 "$out/display")"
viewer=""
watcher=""
cleanup() {
  [ -n "$watcher" ] && kill "$watcher" 2>/dev/null
  [ -n "$viewer" ] && kill "$viewer" 2>/dev/null
  kill "$xvfb" 2>/dev/null
  wait 2>/dev/null
}
trap cleanup EXIT
if [ -n "$replay" ]; then
  [ -r "$replay" ] || {
    echo "gui_soak.sh: cannot read the replay log '$replay'" >&2
    exit 2
  }
  [ "$replay" -ef "$log" ] || cp "$replay" "$log"
  seed=$(head -1 "$log" | awk '{print $4}')
else
  generate >"$log"
fi
echo "gui_soak: seed $seed, $(grep -vc '^#' "$log") events over ${seconds} s, log $log"
echo "gui_soak: replay with: APICLAB=$app tests/gui/gui_soak.sh --seed $seed --replay $log"
# --max-memory caps every scene the viewer loads (all panes' simulations together) below the RSS
# bound, so an RSS over it is a leak or an estimate gone wrong, not a big scene.
"$app" gui rotating-disk --schemes pic,flip,apic --vectors --size "${W}x$H" --heartbeat "$beat" \
  --max-memory "$((rss_mb * 8 / 10))M" >"$out/viewer.log" 2>&1 &
viewer=$!
for _ in $(seq 300); do # the first frame (a loaded machine may take a while)
  [ -s "$beat" ] && break
  kill -0 "$viewer" 2>/dev/null || break
  sleep 0.1
done
if ! [ -s "$beat" ]; then
  echo "FAIL: the viewer drew no frame in 30 s"
  cat "$out/viewer.log"
  exit 1
fi
xdotool search --sync --onlyvisible --name apiclab windowmove 0 0 >/dev/null 2>&1

# ---- Watchdog, 4 times a second: alive, a frame within max_gap s, RSS under the bound ---------
# It runs beside the events (a slow xdotool call must not hide a stall) and writes its state to
# $out/watch ("WORST_GAP PEAK_RSS_MB") and the first failure to $out/failure.
watch() {
  local worst=0 peak=0 now mtime gap rss
  while :; do
    if ! kill -0 "$viewer" 2>/dev/null; then
      echo "the viewer exited" >"$out/failure"
      return
    fi
    now=$(date +%s.%N)
    mtime=$(stat -c %.9Y "$beat" 2>/dev/null || echo "$now")
    read -r gap worst < <(awk -v a="$now" -v b="$mtime" -v w="$worst" \
      'BEGIN { g = a - b; printf "%.3f %.3f\n", g, (g > w ? g : w) }')
    rss=$(awk '/^VmRSS/ { print int($2 / 1024) }' "/proc/$viewer/status" 2>/dev/null || echo 0)
    ((rss > peak)) && peak=$rss
    echo "$worst $peak" >"$out/watch"
    # Slow frames with the machine's load beside them: a starved process is not a hung one.
    awk -v g="$gap" -v m="$max_gap" 'BEGIN { exit !(g > m / 2) }' &&
      echo "$(date +%T) gap $gap s, load $(cut -d' ' -f1-3 /proc/loadavg)" >>"$out/slow-frames.log"
    if awk -v g="$gap" -v m="$max_gap" 'BEGIN { exit !(g > m) }'; then
      echo "no frame for $gap s (bound $max_gap s)" >"$out/failure"
      return
    fi
    if ((rss > rss_mb)); then
      echo "resident memory $rss MB over the bound $rss_mb MB" >"$out/failure"
      return
    fi
    sleep 0.25
  done
}
rm -f "$out/failure" "$out/watch" "$out/slow-frames.log"
watch &
watcher=$!

# ---- Drive it: until --seconds have passed (a replay runs its whole log) -----------------------
event=0
last_events=()
run_event() { # KIND ARGS...
  local kind=$1
  shift
  case "$kind" in
    click) xdotool mousemove "$1" "$2" click "$3" ;;
    drag) xdotool mousemove "$1" "$2" mousedown "$5" mousemove "$(((($1 + $3)) / 2))" \
      "$(((($2 + $4)) / 2))" mousemove "$3" "$4" mouseup "$5" ;;
    wheel) xdotool mousemove "$1" "$2" click --repeat "$4" --delay 10 "$3" ;;
    key) xdotool mousemove "$1" "$2" key "$3" ;;
    typefield) # ctrl+click turns an ImGui slider or drag into a text field; select all, type
      # Pauses let a slow frame (software GL on a loaded machine) take each step in turn.
      xdotool mousemove "$1" "$2" keydown ctrl click 1 keyup ctrl sleep 0.3 key ctrl+a sleep 0.2
      shift 2
      xdotool type --delay 20 -- "$*"
      xdotool sleep 0.2 key Return
      ;;
    typepath)
      xdotool mousemove "$1" "$2" click 1 key ctrl+a
      shift 2
      xdotool type --delay 2 -- "$*"
      xdotool key Return mousemove 300 99 click 1 # Enter, then the Open button
      ;;
  esac
}
start=$SECONDS
while read -r delay kind args; do
  [ -z "$replay" ] && ((SECONDS - start >= seconds)) && break
  [ -e "$out/failure" ] && break
  event=$((event + 1))
  sleep "0.$(printf %03d "$delay")"
  last_events+=("$event: $delay $kind $args")
  ((${#last_events[@]} > 8)) && last_events=("${last_events[@]:1}")
  # shellcheck disable=SC2086
  run_event "$kind" $args 2>>"$out/xdotool.log"
done < <(grep -v '^#' "$log")
elapsed=$((SECONDS - start))
# The window still answers after the last event.
[ -e "$out/failure" ] || sleep "$max_gap" 0.5
kill "$watcher" 2>/dev/null
wait "$watcher" 2>/dev/null
# The window as the events left it, for a person to look at (ffmpeg's X11 grab, when present).
command -v ffmpeg >/dev/null && ffmpeg -loglevel error -y -f x11grab -video_size "${W}x$H" \
  -i "$DISPLAY" -frames:v 1 "$out/last.png" 2>/dev/null
read -r worst_gap peak_rss <"$out/watch"
echo "gui_soak: $event events in $elapsed s; worst frame gap seen $worst_gap s (bound $max_gap s); peak RSS $peak_rss MB (bound $rss_mb MB); load $(cut -d' ' -f1-3 /proc/loadavg)"
[ -s "$out/slow-frames.log" ] && echo "gui_soak: $(wc -l <"$out/slow-frames.log") samples over half the bound, in $out/slow-frames.log"
if [ -e "$out/failure" ]; then
  echo "FAIL: $(cat "$out/failure") after event $event"
  printf '      %s\n' "${last_events[@]}"
  echo "      viewer output (last lines):"
  tail -5 "$out/viewer.log" | sed 's/^/      /'
  { head -1 "$log"; grep -v '^#' "$log" | head -"$event"; } >"$out/failing-events.log"
  echo "      replay: APICLAB=$app tests/gui/gui_soak.sh --seed $seed --replay $out/failing-events.log"
  exit 1
fi
echo "PASS: the viewer stayed alive, drawing and under $rss_mb MB through $event random events"
